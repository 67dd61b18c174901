// SPDX-License-Identifier: MIT
#include <dthex/report/report.h>

#include <gtest/gtest.h>

using namespace dthex;

// A stage whose result is longer than a terminal line is printed whole, and the next stage
// starts on a line of its own (a fixed buffer once cut the coarsening's long result and
// its line break, and the next stage ran on after it).
TEST(SummaryTable, LongStageResultIsPrintedWholeOnItsOwnLine) {
  PipelineResult result;
  result.input_path = "in.off";
  RemeshStageReport remesh;
  remesh.outcome = RemeshStageReport::Outcome::failed_verification;
  while (remesh.failure.size() < 300) remesh.failure += "a further remark on what this stage did, ";
  SurfaceSummary coarse;
  coarse.vertices = 1898;
  result.stages.push_back({"remesh input", 0.5, remesh});
  result.stages.push_back({"verify coarse", 0.25, coarse});
  const std::string detail = describe(result.stages.front().report);
  EXPECT_GT(detail.size(), 300u);
  const std::string table = summary_table(result, PipelineOptions{});
  EXPECT_NE(table.find(detail + "\n  verify coarse"), std::string::npos) << table;
  EXPECT_NE(table.find("1898 vertices"), std::string::npos) << table;
}
