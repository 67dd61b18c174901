// SPDX-License-Identifier: MIT
// Scratch folders for tests that write files. Every folder of one test process lives in one
// root folder of its own, which a global test environment removes when the process's tests
// end: a run of the suite leaves nothing behind in the temp folder (a crashed test leaves
// its root, which names the process).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <iterator>
#include <string>
#include <system_error>

namespace dthex_test {

inline const std::filesystem::path& scratch_root() {
  static const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("dthex_tests_" + std::to_string(::getpid()));
  return root;
}

//! An empty folder of its own for one test, under scratch_root().
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path dir = scratch_root() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

//! The entries in `dir`: what a write left there (a failed write leaves nothing).
inline size_t count_files(const std::filesystem::path& dir) {
  return size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;  // a folder a test made read-only must not fail the run
    std::filesystem::remove_all(scratch_root(), ignored);
  }
};

// Registered once per process, whichever test files include this header.
inline ::testing::Environment* const scratch_cleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

}  // namespace dthex_test
