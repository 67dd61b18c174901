// SPDX-License-Identifier: MIT
// The pipeline's own decisions around the coarsening: a coarsening that fails at a large eps
// falls back to a smaller one, for a given eps and in the --target-nodes search.
#include <dthex/io/read_surface.h>
#include <dthex/io/write_surface.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report.h>
#include <dthex/surface/coarsen.h>

#include <gtest/gtest.h>

#include "scratch_dir.h"

#include <filesystem>
#include <string>

namespace {

using namespace dthex;

// The bundled sphere (r = 1) with a cavity off its centre: the sphere at 0.95 moved 0.0495
// along x, so the wall is 0.0005 thick at +x and 0.1 at -x. At eps 0.5 and above the
// coarsening still self-intersects after its repair rounds; at 0.35 it does not.
std::string eccentric_shell_file() {
  const TriSurface sphere = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  TriSurface shell = sphere;
  const int n = int(sphere.points.size());
  for (const Vec3& p : sphere.points) shell.points.push_back(0.95 * p + Vec3(0.0495, 0, 0));
  for (const auto& t : sphere.triangles) shell.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  const std::string path = (dthex_test::fresh_dir("eccentric_shell") / "shell.off").string();
  write_surface(shell, path);
  return path;
}

// No projection and no dicing: the coarsening is what is tested, and the rest stays fast.
PipelineOptions fast_options() {
  PipelineOptions options;
  options.project = false;
  options.dice = 1;
  return options;
}

}  // namespace

TEST(PipelineEpsFallback, GivenEpsWhoseCoarseningFailsIsRetriedSmaller) {
  const std::string path = eccentric_shell_file();
  {  // The input does make the coarsening fail at eps 0.5.
    Progress quiet;
    const PipelineResult verified = read_and_verify(path, quiet);
    CoarsenOptions coarsen_options;
    coarsen_options.eps = 0.5;
    EXPECT_THROW(coarsen(verified.input, coarsen_options), MeshingError);
  }
  PipelineOptions options = fast_options();
  options.eps = 0.5;
  Progress quiet;
  PipelineResult result;
  ASSERT_NO_THROW(result = run_pipeline(path, options, quiet));
  EXPECT_DOUBLE_EQ(result.eps, 0.5 * 0.7);
  const CoarsenStageReport* coarsen_report = result.stage_report<CoarsenStageReport>("coarsen");
  ASSERT_NE(coarsen_report, nullptr);
  ASSERT_EQ(coarsen_report->failed.size(), 1u);
  EXPECT_DOUBLE_EQ(coarsen_report->failed[0].eps, 0.5);
  EXPECT_NE(coarsen_report->failed[0].failure.find("self-intersecting triangle pairs remain"), std::string::npos)
      << coarsen_report->failed[0].failure;
  EXPECT_DOUBLE_EQ(coarsen_report->eps, result.eps);
  // One coarsen record: the failed attempt's is not kept beside it.
  size_t coarsen_stages = 0;
  for (const StageRecord& s : result.stages) coarsen_stages += s.name == "coarsen";
  EXPECT_EQ(coarsen_stages, 1u);
  EXPECT_EQ(result.coarse_summary.components, 2u);
  EXPECT_EQ(result.quality.inverted, 0u);
  EXPECT_TRUE(result.conforming);
  const std::string summary = summary_table(result, options);
  EXPECT_NE(summary.find("eps 0.5 failed: coarsening:"), std::string::npos) << summary;
  EXPECT_NE(summary.find("used 0.35:"), std::string::npos) << summary;
  EXPECT_NE(summary.find("(eps 0.35, dice 1"), std::string::npos) << summary;
}

TEST(PipelineEpsFallback, TargetNodesSearchTakesAFailedCoarseningAsTooCoarse) {
  const std::string path = eccentric_shell_file();
  PipelineOptions options = fast_options();
  options.target_nodes = 11400;  // what the coarsest eps that works gives, about
  Progress quiet;
  PipelineResult result;
  ASSERT_NO_THROW(result = run_pipeline(path, options, quiet));
  const ChooseEpsReport* choose = result.stage_report<ChooseEpsReport>("choose eps");
  ASSERT_NE(choose, nullptr);
  // 0.9, 0.63 and 0.441 fail; 0.3087 is the coarse end of the search.
  EXPECT_GE(choose->failed_probes, 3u);
  EXPECT_NE(choose->first_failure.find("self-intersecting"), std::string::npos) << choose->first_failure;
  EXPECT_NEAR(choose->coarsest_eps, 0.9 * 0.7 * 0.7 * 0.7, 1e-12);
  EXPECT_LE(result.eps, choose->coarsest_eps);
  EXPECT_EQ(result.dice, 1);
  // The chosen eps coarsens at once.
  const CoarsenStageReport* coarsen_report = result.stage_report<CoarsenStageReport>("coarsen");
  ASSERT_NE(coarsen_report, nullptr);
  EXPECT_TRUE(coarsen_report->failed.empty());
  EXPECT_NEAR(double(result.hexes.nodes.size()), double(options.target_nodes), 0.1 * double(options.target_nodes));
}

// The shell keeps about 11,400 nodes with dice 1 at every eps and several times that with
// dice 2: a budget between the two is refused naming both ranges, not "even with --dice 1".
TEST(PipelineEpsFallback, TargetNodesBetweenTwoDicingsIsRefusedNamingBoth) {
  const std::string path = eccentric_shell_file();
  PipelineOptions options = fast_options();
  options.target_nodes = 30000;
  Progress quiet;
  try {
    run_pipeline(path, options, quiet);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("between what --dice 1 reaches"), std::string::npos) << message;
    EXPECT_NE(message.find("what --dice 2 needs"), std::string::npos) << message;
  }
}

// A shared CAD part (remeshed first, as a CAD export is) whose coarsening still
// self-intersects after its repair rounds at the finest eps, 0.001: the search starts from the
// nearest larger eps that works instead of failing, and meets the budget (with dice 1).
TEST(PipelineEpsFallback, TargetNodesSearchPassesOverAFailingFineEnd) {
  const std::string path = std::string(DTHEX_SHARED_DIR) + "/meshes/fandisk.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  PipelineOptions options;
  options.project = false;
  options.target_nodes = 15000;
  Progress quiet;
  PipelineResult result;
  ASSERT_NO_THROW(result = run_pipeline(path, options, quiet));
  const ChooseEpsReport* choose = result.stage_report<ChooseEpsReport>("choose eps");
  ASSERT_NE(choose, nullptr);
  EXPECT_GE(choose->failed_probes, 1u);
  EXPECT_NE(choose->first_failure.find("eps 0.001000: coarsening:"), std::string::npos) << choose->first_failure;
  EXPECT_GT(choose->finest_eps, 0.001);
  EXPECT_GE(result.eps, choose->finest_eps);
  EXPECT_NEAR(double(result.hexes.nodes.size()), double(options.target_nodes), 0.1 * double(options.target_nodes));
}
