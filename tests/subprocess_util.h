// SPDX-License-Identifier: MIT
// Test helpers: run an external referee (/usr/bin/python3 + meshio, hexeval.py) and
// capture its output; run code in a forked child with a file-size limit.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <functional>
#include <string>

namespace dthex_test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout only
};

inline CommandResult run_command(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[65536];
  size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.output.append(buffer, got);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

//! True once /usr/bin/python3 can import meshio (checked once per process).
inline bool meshio_available() {
  static const bool available = run_command("/usr/bin/python3 -c 'import meshio' 2>/dev/null").exit_code == 0;
  return available;
}

//! Runs body in a forked child whose files may not grow past max_file_bytes (writes past it
//! fail with EFBIG instead of killing the child: SIGXFSZ is ignored). Returns the child's
//! exit code, or -1 if it died from a signal.
inline int run_with_file_size_limit(rlim_t max_file_bytes, const std::function<int()>& body) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{max_file_bytes, max_file_bytes};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 99;
    try {
      code = body();
    } catch (...) {
      code = 98;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace dthex_test
