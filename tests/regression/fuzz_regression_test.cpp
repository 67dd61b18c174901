// SPDX-License-Identifier: MIT
// Replays the fuzzers' seed corpus and every committed regression input (tests/fuzz/)
// through the fuzz targets' own code, so that what the fuzzers once found stays fixed in
// the ordinary (and the sanitizer) build. A target aborts on a broken promise; here that
// would end the test binary, which ctest reports as a failure naming this test.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#define LLVMFuzzerTestOneInput fuzz_read_one
#include "../fuzz/fuzz_read.cpp"
#undef LLVMFuzzerTestOneInput
#define LLVMFuzzerTestOneInput fuzz_verify_one
#include "../fuzz/fuzz_verify.cpp"
#undef LLVMFuzzerTestOneInput
#define LLVMFuzzerTestOneInput fuzz_pipeline_one
#include "../fuzz/fuzz_pipeline.cpp"
#undef LLVMFuzzerTestOneInput

namespace {

namespace fs = std::filesystem;

using Target = int (*)(const uint8_t*, size_t);

//! Runs every file of tests/fuzz/<folder>/<target>; returns how many there were.
size_t replay(const std::string& target_name, Target target, const std::vector<std::string>& folders) {
  size_t count = 0;
  for (const std::string& folder : folders) {
    const fs::path dir = fs::path(DTHEX_SOURCE_DIR) / "tests" / "fuzz" / folder / target_name;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (!entry.is_regular_file() || entry.path().filename().string().front() == '.') continue;
      std::ifstream in(entry.path(), std::ios::binary);
      std::stringstream bytes;
      bytes << in.rdbuf();
      const std::string data = bytes.str();
      SCOPED_TRACE(entry.path().string());
      EXPECT_EQ(target(reinterpret_cast<const uint8_t*>(data.data()), data.size()), 0);
      ++count;
    }
  }
  return count;
}

TEST(FuzzRegression, ReadersOnCorpusAndRegressions) {
  EXPECT_GE(replay("fuzz_read", fuzz_read_one, {"corpus", "regressions"}), 15u);
}

TEST(FuzzRegression, VerifyOnCorpusAndRegressions) {
  EXPECT_GE(replay("fuzz_verify", fuzz_verify_one, {"corpus", "regressions"}), 5u);
}

TEST(FuzzRegression, PipelineOnCorpusAndRegressions) {
  EXPECT_GE(replay("fuzz_pipeline", fuzz_pipeline_one, {"corpus", "regressions"}), 10u);
}

}  // namespace
