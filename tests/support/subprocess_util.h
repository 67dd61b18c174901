// SPDX-License-Identifier: MIT
// Test helpers for everything that runs a process: the Verdict-based referee script
// (hexeval, run by /usr/bin/python3 with meshio), om_dthex itself (bounded by a timeout,
// stdout and stderr kept), code in a forked child with a file-size limit, and scratch folders
// for their files.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <dthex/io/atomic_file.h>

#include "scratch_dir.h"

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

//! Runs `write` in a child whose files may not grow past max_file_bytes (as a full disk would
//! refuse them) and says what it threw: 0 an OutputError (om_dthex's exit 2: the user's disk,
//! not a bug), 1 nothing, 2 another runtime_error, 3 another InputError, -1 killed.
inline int write_failure_under_file_size_limit(rlim_t max_file_bytes, const std::function<void()>& write) {
  return run_with_file_size_limit(max_file_bytes, [&] {
    try {
      write();
    } catch (const dthex::OutputError&) {
      return 0;
    } catch (const dthex::InputError&) {
      return 3;
    } catch (const std::runtime_error&) {
      return 2;
    }
    return 1;
  });
}
//! What write_failure_under_file_size_limit's codes mean, for a test's failure message.
inline constexpr const char* kWriteFailureCodes =
    "0 = OutputError thrown, 1 = no error, 2 = other runtime_error, 3 = other InputError, -1 = killed";

namespace fs = std::filesystem;

inline void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

inline std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline size_t entries_in(const fs::path& dir) {
  return size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

struct CommandRun {
  int exit_code = -1;
  std::string out, err;
};

//! Runs `prefix om_dthex args` through bash, bounded by `timeout_seconds` so that a hang
//! shows as exit 137 (killed) instead of stalling the suite.
inline CommandRun run_om_dthex(const std::string& args, const fs::path& scratch, const std::string& prefix = "",
                               int timeout_seconds = 120) {
  const fs::path out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const std::string command = prefix + "timeout -s KILL " + std::to_string(timeout_seconds) + " " +
                              std::string(DTHEX_BINARY_DIR) + "/om_dthex " + args + " >" + out.string() + " 2>" +
                              err.string() + " </dev/null";
  const int status = std::system(("bash -c " + shell_quote(command)).c_str());
  CommandRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_bytes(out);
  r.err = read_bytes(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

}  // namespace dthex_test
