// SPDX-License-Identifier: MIT
#include "core/atomic_file.h"

#include "core/types.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <unistd.h>

namespace dthex {
namespace {

// A fixed table of temporary paths, readable from a signal handler without allocation.
constexpr int kMaxPending = 16;
constexpr size_t kMaxPath = 4096;
char pending_paths[kMaxPending][kMaxPath];
std::atomic<bool> pending_used[kMaxPending];
std::mutex pending_mutex;

int register_pending(const std::string& path) {
  std::lock_guard<std::mutex> lock(pending_mutex);
  if (path.size() + 1 > kMaxPath) return -1;
  for (int i = 0; i < kMaxPending; ++i) {
    if (!pending_used[i].load()) {
      std::memcpy(pending_paths[i], path.c_str(), path.size() + 1);
      pending_used[i].store(true);
      return i;
    }
  }
  return -1;
}

void unregister_pending(int slot) {
  if (slot >= 0) pending_used[slot].store(false);
}

extern "C" void on_interrupt(int signal_number) {
  remove_pending_temporaries();
  _exit(128 + signal_number);
}

}  // namespace

void remove_pending_temporaries() noexcept {
  for (int i = 0; i < kMaxPending; ++i)
    if (pending_used[i].load()) ::unlink(pending_paths[i]);
}

void install_interrupt_cleanup() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGHUP, &action, nullptr);
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError("cannot write '" + path + "': folder '" + folder.string() + "' does not exist");
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError("cannot write '" + path + "': folder '" + folder.string() + "' is not writable");
  if (fs::is_directory(target, ec))
    throw InputError("cannot write '" + path + "': it is a directory");

  const std::string temporary =
      (folder / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()))).string();
  const int slot = register_pending(temporary);
  auto discard = [&] {
    std::remove(temporary.c_str());
    unregister_pending(slot);
  };
  try {
    write(temporary);
  } catch (...) {
    discard();
    throw;
  }
  if (fs::file_size(temporary, ec) == 0 || ec) {
    discard();
    throw std::runtime_error("writing '" + path + "' failed: nothing was written (disk full?)");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    discard();
    throw std::runtime_error("cannot write '" + path + "': rename from the temporary file failed: " +
                             std::strerror(errno));
  }
  unregister_pending(slot);
}

}  // namespace dthex
