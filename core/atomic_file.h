// SPDX-License-Identifier: MIT
// Files are written whole or not at all: to a temporary name beside the target,
// then renamed over it. A failed or interrupted write leaves no partial file.
#pragma once

#include <functional>
#include <string>

namespace dthex {

//! Calls write(temporary_path) and renames the result onto path. If write throws,
//! the file is empty, or the rename fails, the temporary file is removed and an
//! InputError (unwritable folder) or std::runtime_error is thrown naming path.
//! The temporary is registered so that a SIGINT/SIGTERM handler can remove it.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& write);

//! Removes every temporary file still registered (called from signal handlers:
//! async-signal-safe, uses unlink only).
void remove_pending_temporaries() noexcept;

//! Installs SIGINT/SIGTERM handlers that remove pending temporaries and exit with 130/143.
void install_interrupt_cleanup();

}  // namespace dthex
