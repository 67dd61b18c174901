// SPDX-License-Identifier: MIT
#include <dthex/io/output_file.h>

#include <dthex/io/atomic_file.h>

#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <stdexcept>

namespace dthex {

OutputFile::OutputFile(const std::string& temporary_path, const std::string& target_path) : target_(target_path) {
  file_ = std::fopen(temporary_path.c_str(), "wb");
  if (!file_) fail();
  buffer_.resize(size_t(1) << 20);
  std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
}

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
}

void OutputFile::print(const char* format, ...) {
  va_list args;
  va_start(args, format);
  const int written = std::vfprintf(file_, format, args);
  va_end(args);
  if (written < 0) fail();
}

void OutputFile::write(const void* data, size_t bytes) {
  if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes) fail();
}

void OutputFile::close() {
  errno = 0;
  const bool flushed = std::fflush(file_) == 0 && !std::ferror(file_);
  const int flush_errno = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed) errno = flush_errno;
  if (!flushed || !closed) fail();
}

void OutputFile::fail() const {
  const int error = errno;
  throw OutputError("writing '" + target_ + "' failed: " +
                           (error ? std::strerror(error) : "unknown I/O error"));
}

}  // namespace dthex
