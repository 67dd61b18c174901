// SPDX-License-Identifier: MIT
#include <dthex/io/atomic_file.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <unistd.h>

namespace dthex {
namespace {

// A fixed table of temporary paths, readable from a signal handler without allocation.
constexpr int kMaxPending = 16;
constexpr size_t kMaxPath = 4096;
char pending_paths[kMaxPending][kMaxPath];
std::atomic<bool> pending_used[kMaxPending];
std::mutex pending_mutex;
std::atomic<unsigned> temporary_counter{0};
AtomicWriteGroup* open_group = nullptr;

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

void discard(const std::string& temporary, int slot) {
  std::remove(temporary.c_str());
  unregister_pending(slot);
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
  std::signal(SIGXFSZ, SIG_IGN);
}

void check_output_path(const std::string& option, const std::string& path) {
  namespace fs = std::filesystem;
  const std::string what = option.empty() ? "cannot write '" + path + "'" : option + " '" + path + "'";
  if (path.empty()) throw OutputError(what + ": the path is empty");
  const fs::path target(path);
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw OutputError(what + ": it is a directory");
  if (!fs::is_directory(folder, ec))
    throw OutputError(what + ": folder '" + folder.string() + "' does not exist");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw OutputError(what + ": folder '" + folder.string() + "' is not writable");
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  namespace fs = std::filesystem;
  check_output_path("", path);
  const fs::path target(path);
  fs::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  const std::string temporary = (folder / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) +
                                           "_" + std::to_string(temporary_counter++)))
                                    .string();
  const int slot = register_pending(temporary);
  try {
    write(temporary);
  } catch (const std::bad_alloc&) {
    discard(temporary, slot);
    throw;
  } catch (const InputError&) {
    discard(temporary, slot);
    throw;
  } catch (const std::exception& e) {
    discard(temporary, slot);
    throw OutputError(e.what());
  } catch (...) {
    discard(temporary, slot);
    throw;
  }
  std::error_code ec;
  if (fs::file_size(temporary, ec) == 0 || ec) {
    discard(temporary, slot);
    throw OutputError("writing '" + path + "' failed: nothing was written (disk full?)");
  }
  if (open_group) {
    open_group->pending_.push_back({temporary, path, slot});
    return;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    discard(temporary, slot);
    throw OutputError("cannot write '" + path + "': renaming the temporary file failed: " + std::strerror(error));
  }
  unregister_pending(slot);
}

AtomicWriteGroup::AtomicWriteGroup() {
  if (open_group) throw std::logic_error("AtomicWriteGroup: only one group may be open at a time");
  open_group = this;
}

AtomicWriteGroup::~AtomicWriteGroup() {
  if (open_group == this) open_group = nullptr;
  for (const Pending& p : pending_) discard(p.temporary, p.slot);
}

void AtomicWriteGroup::commit() {
  open_group = nullptr;
  while (!pending_.empty()) {
    const Pending p = pending_.front();
    pending_.erase(pending_.begin());
    if (std::rename(p.temporary.c_str(), p.target.c_str()) != 0) {
      const int error = errno;
      discard(p.temporary, p.slot);
      throw OutputError("cannot write '" + p.target + "': renaming the temporary file failed: " +
                        std::strerror(error));  // the destructor removes the others
    }
    unregister_pending(p.slot);
  }
}

}  // namespace dthex
