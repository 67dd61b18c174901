// SPDX-License-Identifier: MIT
#include <dthex/io/atomic_file.h>
#include <dthex/mesh/types.h>
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {
fs::path atomic_folder(const std::string& name) {
  return dthex_test::fresh_dir("atomic_" + name);
}
}  // namespace

TEST(AtomicFile, WritesWholeFileUnderFinalName) {
  const fs::path dir = atomic_folder("ok");
  const std::string target = (dir / "out.txt").string();
  dthex::write_atomically(target, [](const std::string& tmp) { std::ofstream(tmp) << "hello"; });
  std::ifstream in(target);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "hello");
  EXPECT_EQ(dthex_test::count_files(dir), 1u);
}

TEST(AtomicFile, FailedWriteLeavesNeitherTemporaryNorOldFile) {
  const fs::path dir = atomic_folder("fail");
  const std::string target = (dir / "out.txt").string();
  EXPECT_THROW(dthex::write_atomically(target,
                                       [](const std::string& tmp) {
                                         std::ofstream(tmp) << "partial";
                                         throw std::runtime_error("disk full");
                                       }),
               std::runtime_error);
  EXPECT_EQ(dthex_test::count_files(dir), 0u);
}

TEST(AtomicFile, MissingFolderIsAnInputError) {
  EXPECT_THROW(dthex::write_atomically("/nonexistent_dthex_dir/out.vtu", [](const std::string&) {}),
               dthex::InputError);
}

TEST(AtomicFile, EmptyResultIsRefused) {
  const fs::path dir = atomic_folder("empty");
  EXPECT_THROW(dthex::write_atomically((dir / "o.txt").string(), [](const std::string& tmp) { std::ofstream{tmp}; }),
               std::runtime_error);
  EXPECT_EQ(dthex_test::count_files(dir), 0u);
}
