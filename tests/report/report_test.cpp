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
  std::string detail = "3602 triangles";
  while (detail.size() < 300) detail += ", and a further remark on what this stage did";
  result.stages.push_back({"coarsen", 0.5, detail});
  result.stages.push_back({"verify coarse", 0.25, "1898 vertices"});
  const std::string table = summary_table(result, PipelineOptions{});
  EXPECT_NE(table.find(detail + "\n  verify coarse"), std::string::npos) << table;
}
