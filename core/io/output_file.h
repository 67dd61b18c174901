// SPDX-License-Identifier: MIT
// A buffered output file whose every failure throws, for the writers that run inside
// write_atomically: a full disk must never leave a silently truncated file behind.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace dthex {

//! A FILE* whose open, formatted writes, raw writes, flush and close all throw
//! OutputError (core/io/atomic_file.h) on failure. Errors name the target path, not the temporary one.
class OutputFile {
 public:
  OutputFile(const std::string& temporary_path, const std::string& target_path);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();

  __attribute__((format(printf, 2, 3))) void print(const char* format, ...);
  void write(const void* data, size_t bytes);
  //! Flushes and closes; a late error (the last buffer not fitting on the disk) throws here.
  void close();

 private:
  [[noreturn]] void fail() const;

  std::string target_;
  std::vector<char> buffer_;
  std::FILE* file_ = nullptr;
};

}  // namespace dthex
