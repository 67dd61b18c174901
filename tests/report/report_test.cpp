// SPDX-License-Identifier: MIT
#include <dthex/report/report.h>
#include "bundled_meshes.h"
#include "mesh_tries.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <set>

using namespace dthex;

namespace {


// The sphere meshed by DTHex once for the tests below (well under a second).
const PipelineResult& sphere_run() {
  static const PipelineResult run = [] {
    Progress quiet;
    return run_pipeline(dthex_test::bundled_mesh("sphere728.off"), PipelineOptions{}, quiet);
  }();
  return run;
}

// A value of a stage entry's "report" that is a number, a boolean, or an array of numbers.
bool numeric(const nlohmann::json& v) {
  if (v.is_number() || v.is_boolean()) return true;
  if (!v.is_array()) return false;
  for (const auto& e : v)
    if (!e.is_number()) return false;
  return true;
}

}  // namespace

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

// The JSON stage entries carry the typed reports' fields: the untangle entry's inverted
// counts are the numbers the untangler reported, the measure entry's those of the mesh, and
// every report value is a number or a boolean (strings only for the few enum and error fields),
// with the sentence apart under "summary".
TEST(ReportJson, StageEntriesCarryTheReportsAsNumbers) {
  const PipelineResult& r = sphere_run();
  const nlohmann::json j = nlohmann::json::parse(report_json(r, PipelineOptions{}));
  ASSERT_EQ(j["stages"].size(), r.stages.size());
  const UntangleReport* untangle = r.stage_report<UntangleReport>("untangle");
  ASSERT_NE(untangle, nullptr);
  EXPECT_EQ(untangle->inverted_before, r.inverted_before_untangle);
  const std::set<std::string> string_fields = {"outcome", "failure", "kept"};
  bool saw_untangle = false, saw_measure = false;
  for (size_t i = 0; i < r.stages.size(); ++i) {
    const nlohmann::json& s = j["stages"][i];
    EXPECT_EQ(s["name"], r.stages[i].name);
    EXPECT_TRUE(s["seconds"].is_number());
    EXPECT_FALSE(s.contains("result")) << s.dump();
    EXPECT_EQ(s["summary"], describe(r.stages[i].report));
    ASSERT_TRUE(s["report"].is_object()) << s.dump();
    EXPECT_FALSE(s["report"].empty()) << s.dump();
    for (const auto& [key, value] : s["report"].items()) {
      if (value.is_object()) continue;  // a nested statistic (a surface's triangle shape)
      if (string_fields.count(key))
        EXPECT_TRUE(value.is_string()) << s["name"] << "." << key;
      else
        EXPECT_TRUE(numeric(value)) << s["name"] << "." << key << " = " << value.dump();
    }
    if (s["name"] == "untangle") {
      saw_untangle = true;
      ASSERT_TRUE(s["report"]["inverted_before"].is_number_unsigned());
      EXPECT_EQ(s["report"]["inverted_before"].get<size_t>(), untangle->inverted_before);
      EXPECT_EQ(s["report"]["inverted_after"].get<size_t>(), untangle->inverted_after);
      EXPECT_EQ(s["report"]["inverted_before"], j["hex"]["inverted_before_untangle"]);
      EXPECT_EQ(s["report"]["undone"].get<bool>(), untangle->undone);
    }
    if (s["name"] == "measure") {
      saw_measure = true;
      EXPECT_EQ(s["report"]["inverted"], j["hex"]["inverted"]);
      EXPECT_EQ(s["report"]["conforming"], j["hex"]["conforming"]);
      EXPECT_EQ(s["report"]["min_scaled_jacobian"], j["hex"]["scaled_jacobian"]["min"]);
    }
    if (s["name"] == "dice") EXPECT_EQ(s["report"]["hexes"], j["hex"]["hexes"]);
    if (s["name"] == "read") EXPECT_EQ(s["report"]["triangles"], j["input"]["surface"]["triangles"]);
  }
  EXPECT_TRUE(saw_untangle);
  EXPECT_TRUE(saw_measure);
  // No retry on the sphere: the key is there, and null.
  EXPECT_TRUE(j["coarse"]["thickness_retry"].is_null());
  EXPECT_TRUE(j["coarse"]["finer_retry"].is_null());
}

// An enum is a string of its name, and the retry's two meshes are numbers, kept or not.
TEST(ReportJson, EnumsAreNamesAndTheThicknessRetryIsFields) {
  PipelineResult r;
  r.input_path = "in.off";
  RemeshStageReport remesh;
  remesh.outcome = RemeshStageReport::Outcome::no_better;
  remesh.needle_share_before = 0.4;
  remesh.needle_share_after = 0.5;
  r.stages.push_back({"remesh input", 1.0, remesh});
  MeshTryReport first;
  first.min_scaled_jacobian = 0.04;
  first.inverted = 3;
  r.stages.push_back({"curvature-sized try", 2.0, first});
  r.thickness_retry.ran = true;
  r.thickness_retry.thin_wall_vertices = 120;
  r.thickness_retry.coarsening_vertices = 1000;
  r.thickness_retry.curvature = first;
  r.thickness_retry.thickness.thickness_ratio = 1;
  r.thickness_retry.thickness.min_scaled_jacobian = 0.21;
  r.thickness_retry.thickness.conforming = true;
  r.thickness_retry.kept_thickness = true;
  const nlohmann::json j = nlohmann::json::parse(report_json(r, PipelineOptions{}));
  EXPECT_EQ(j["stages"][0]["report"]["outcome"], "no_better");
  EXPECT_EQ(j["stages"][0]["report"]["needle_share_after"], 0.5);
  EXPECT_NE(j["stages"][0]["summary"].get<std::string>().find("no better"), std::string::npos);
  EXPECT_EQ(j["stages"][1]["report"]["inverted"], 3);
  EXPECT_FALSE(j["stages"][1]["report"]["failed"].get<bool>());
  const nlohmann::json& retry = j["coarse"]["thickness_retry"];
  EXPECT_EQ(retry["thin_wall_vertices"], 120);
  EXPECT_EQ(retry["coarsening_vertices"], 1000);
  EXPECT_EQ(retry["kept"], "thickness");
  EXPECT_EQ(retry["curvature_sized"]["min_scaled_jacobian"], 0.04);
  EXPECT_EQ(retry["thickness_sized"]["min_scaled_jacobian"], 0.21);
  EXPECT_EQ(retry["thickness_sized"]["thickness_ratio"], 1.0);
  const std::string text = describe(r.thickness_retry);
  EXPECT_NE(text.find("120 of 1000 input vertices"), std::string::npos) << text;
  EXPECT_NE(text.find("kept the thickness-sized mesh"), std::string::npos) << text;
  EXPECT_NE(summary_table(r, PipelineOptions{}).find("thin walls: " + text), std::string::npos);
  EXPECT_EQ(describe(ThicknessRetryReport{}), "");
}

// The finer retry's tries are numbers with their eps, and its text names the one kept.
TEST(ReportJson, TheFinerRetryIsFieldsAndALineInTheSummary) {
  PipelineResult r;
  r.input_path = "in.off";
  MeshTryReport unsound, failed, sound;
  unsound.eps = 0.4;
  unsound.inverted = 1;
  unsound.min_scaled_jacobian = -0.01;
  unsound.fold_repair_left = true;
  failed.eps = 0.28;
  failed.failed = true;
  failed.failure = "tetgen: refused";
  sound.eps = 0.196;
  sound.min_scaled_jacobian = 0.4;
  sound.conforming = true;
  r.finer_retry.ran = true;
  r.finer_retry.tries = {unsound, failed, sound};
  r.finer_retry.kept = 2;
  const nlohmann::json j = nlohmann::json::parse(report_json(r, PipelineOptions{}));
  const nlohmann::json& retry = j["coarse"]["finer_retry"];
  ASSERT_EQ(retry["tries"].size(), 3u);
  EXPECT_EQ(retry["kept"], 2);
  EXPECT_EQ(retry["tries"][0]["eps"], 0.4);
  EXPECT_EQ(retry["tries"][0]["inverted"], 1);
  EXPECT_TRUE(retry["tries"][0]["fold_repair_left"].get<bool>());
  EXPECT_FALSE(retry["tries"][2]["fold_repair_left"].get<bool>());
  EXPECT_TRUE(retry["tries"][1]["failed"].get<bool>());
  EXPECT_EQ(retry["tries"][1]["failure"], "tetgen: refused");
  EXPECT_EQ(retry["tries"][2]["min_scaled_jacobian"], 0.4);
  const std::string text = describe(r.finer_retry);
  EXPECT_NE(text.find("the mesh at eps 0.4 was unsound (min scaled Jacobian -0.01, 1 inverted, not conforming; fold repair left for a finer try)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("eps 0.28 (failed: tetgen: refused)"), std::string::npos) << text;
  EXPECT_NE(text.find("kept the mesh at eps 0.196"), std::string::npos) << text;
  EXPECT_NE(summary_table(r, PipelineOptions{}).find("finer eps: " + text), std::string::npos);
  EXPECT_EQ(describe(FinerRetryReport{}), "");
}

TEST(ReportJson, AFirstMeshSoundOnceItsFoldsWereRepairedIsSaidSo) {
  // The first mesh had folds only (repair left), the finer ones inverted hexes: the first was
  // kept, repaired last, and its report is the repaired mesh's.
  FinerRetryReport retry;
  retry.ran = true;
  using dthex::testing::mesh_try;
  retry.tries = {mesh_try(0.1, 0, 0.0197, true, false), mesh_try(0.07, 10, -1.2e-8, false, true)};
  retry.kept = 0;
  const std::string text = describe(retry);
  EXPECT_NE(text.find("the mesh at eps 0.1 had boundary faces folded into it (fold repair left for a finer try), "
                      "so the input was meshed again"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("was unsound"), std::string::npos) << text;
  EXPECT_NE(text.find("kept the mesh at eps 0.1, sound once its folds were repaired (min scaled Jacobian 0.0197)"),
            std::string::npos)
      << text;
}
