// SPDX-License-Identifier: MIT
// Files are written whole or not at all: to a temporary name beside the target,
// then renamed over it. A failed or interrupted write leaves no partial file.
#pragma once

#include <dthex/mesh/types.h>

#include <functional>
#include <string>
#include <vector>

namespace dthex {

//! An output file could not be written (folder missing or unwritable, target is a
//! directory, disk full, file-size limit, I/O error). It is an InputError: the command
//! exits with code 2, since the fix is on the user's side (another path, free space).
struct OutputError : InputError {
  using InputError::InputError;
};

//! Calls write(temporary_path) and renames the result onto path. If write throws,
//! the file is empty, or the rename fails, the temporary file is removed and an
//! OutputError naming path is thrown (std::bad_alloc passes through unchanged).
//! The temporary is registered so that a SIGINT/SIGTERM handler can remove it.
//! While an AtomicWriteGroup is open the rename is deferred to its commit().
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& write);

//! Makes several outputs appear together or not at all: while one is alive (one at a
//! time, on one thread), write_atomically() leaves each result under its temporary
//! name; commit() renames them all. Destroyed without commit() (an error, a later
//! failing output), it removes every temporary, so no output of a failed run is left.
class AtomicWriteGroup {
 public:
  AtomicWriteGroup();
  AtomicWriteGroup(const AtomicWriteGroup&) = delete;
  AtomicWriteGroup& operator=(const AtomicWriteGroup&) = delete;
  ~AtomicWriteGroup();
  //! Renames every written temporary onto its target; throws OutputError if one fails
  //! (the remaining temporaries are removed).
  void commit();

 private:
  friend void write_atomically(const std::string&, const std::function<void(const std::string&)>&);
  struct Pending {
    std::string temporary, target;
    int slot;
  };
  std::vector<Pending> pending_;
};

//! Refuses, before any work, an output path that could never be written: its folder is
//! missing or not writable, or the path is a directory. Throws OutputError
//! "<option> '<path>': <problem>" (option may be empty).
void check_output_path(const std::string& option, const std::string& path);

//! Removes every temporary file still registered (called from signal handlers:
//! async-signal-safe, uses unlink only).
void remove_pending_temporaries() noexcept;

//! Installs SIGINT/SIGTERM/SIGHUP handlers that remove pending temporaries and exit with
//! 128 + the signal number (130 for SIGINT), and ignores SIGXFSZ so that a file-size
//! limit (ulimit -f) makes a write fail with EFBIG, reported, instead of killing us.
void install_interrupt_cleanup();

}  // namespace dthex
