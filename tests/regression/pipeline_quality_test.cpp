// SPDX-License-Identifier: MIT
// The "done when" criteria of the projection issue, asserted through the pipeline API on
// three bundled biological meshes (the liver at the eps 0.1; the heart and the CT
// femur at eps 0.2, which keeps them to seconds each): no inverted hex, min scaled Jacobian >= 0.2, conforming with a
// closed boundary, Hausdorff <= 1% of the bounding-box diagonal, volume within 2%, average
// shape at least 0.1 above classic THex of the same input, with fewer nodes.
#include <dthex/pipeline/pipeline.h>

#include <dthex/hexes/conformity.h>
#include <dthex/io/read_surface.h>
#include <dthex/io/write_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/surface/surface_distance.h>
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

using namespace dthex;

namespace {

// Every edge of the boundary quads is used by exactly two of them: the boundary is closed.
bool boundary_closed(const HexMesh& mesh) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& q : boundary_quads(mesh))
    for (int i = 0; i < 4; ++i) ++uses[std::minmax(q[size_t(i)], q[size_t((i + 1) % 4)])];
  for (const auto& [edge, n] : uses)
    if (n != 2) return false;
  return !uses.empty();
}

void expect_done_when(const std::string& mesh, double eps, int dice) {
  const std::string path = std::string(DTHEX_SOURCE_DIR "/meshes/") + mesh;
  Progress quiet;
  PipelineOptions thex_options;
  thex_options.thex_only = true;
  const PipelineResult thex = run_pipeline(path, thex_options, quiet);

  PipelineOptions options;
  options.eps = eps;
  options.dice = dice;
  const PipelineResult r = run_pipeline(path, options, quiet);
  SCOPED_TRACE(mesh);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GE(r.quality.scaled_jacobian_stats.min, 0.2);
  EXPECT_TRUE(r.conforming);
  EXPECT_TRUE(boundary_closed(r.hexes));
  EXPECT_LE(r.hausdorff, 0.01 * r.input_summary.bbox_diagonal);
  EXPECT_NEAR(r.hex_volume, r.input_summary.volume, 0.02 * r.input_summary.volume);
  EXPECT_GE(r.quality.shape_stats.avg, thex.quality.shape_stats.avg + 0.1);
  EXPECT_LT(r.hexes.nodes.size(), thex.hexes.nodes.size());
}

}  // namespace

TEST(PipelineQuality, LiverMeetsDoneWhen) { expect_done_when("liver.off", 0.1, 2); }

TEST(PipelineQuality, PapersSphereDicedByThreeIsSmallAndWellShaped) {
  // Issue 5: sphere728, eps 0.1, dice 3: at most 3000 nodes, avg shape >= 0.85, min shape
  // >= 0.6, no inverted hex (paper: 2473 nodes, avg 0.8298, min 0.5332), at default options
  // (collapse bounds judged after smoothing: 14 coarse vertices; in place: 20, 4441 nodes).
  // The coarse sphere must be meshed around one centre point: one tet per coarse triangle.
  Progress quiet;
  PipelineOptions options;
  options.dice = 3;
  const PipelineResult r = run_pipeline(DTHEX_SOURCE_DIR "/meshes/sphere728.off", options, quiet);
  EXPECT_EQ(r.tets, r.coarse.triangles.size());
  EXPECT_EQ(r.hexes.hexes.size(), 4u * 27u * r.tets);
  EXPECT_LE(r.hexes.nodes.size(), 3000u);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_GE(r.quality.shape_stats.avg, 0.85);
  EXPECT_GE(r.quality.shape_stats.min, 0.6);
  EXPECT_TRUE(r.conforming);
}

TEST(PipelineQuality, HeartMeetsDoneWhen) { expect_done_when("heart.off", 0.1, 2); }

TEST(PipelineQuality, DTHexTetsTakeTheLooserBoundAndFewerNodes) {
  // THex keeps the paper's TetGen bound (radius-edge 1.2); DTHex's coarse tets take 1.5 unless
  // switches are given. On the liver that is 16,135 nodes against 16,723, every hex still
  // above 0.2: the interior points a tight bound adds each become 8 hexes after dicing (the
  // looser bound's crowded vertices, which the split of crowded vertices then takes apart, cost
  // some of that back).
  PipelineOptions dthex, thex, given;
  thex.thex_only = true;
  given.tetgen_switches = "pq1.2Y";
  EXPECT_EQ(tetgen_switches_for(thex), std::string("pq1.2Y"));
  EXPECT_EQ(tetgen_switches_for(dthex), std::string("pq1.5Y"));
  EXPECT_EQ(tetgen_switches_for(given), std::string("pq1.2Y"));
  Progress quiet;
  const std::string liver = DTHEX_SOURCE_DIR "/meshes/liver.off";
  const PipelineResult loose = run_pipeline(liver, dthex, quiet);
  const PipelineResult tight = run_pipeline(liver, given, quiet);
  EXPECT_LT(loose.tets, tight.tets);
  EXPECT_LT(loose.hexes.nodes.size(), tight.hexes.nodes.size());
  EXPECT_GE(loose.quality.scaled_jacobian_stats.min, 0.2);
  EXPECT_EQ(loose.quality.inverted, 0u);
}
//! Slivers bound the worst hexes: a hex corner at a tet's edge has the tet's dihedral angle
//! there, and at a tet vertex its solid angle, which no smoothing of the hexes undoes. With the
//! coarse tets' dihedral angles bounded (--min-dihedral 18) and the smoother's target raised
//! with it, the liver's worst hex rises from 0.40 at the defaults to 0.44, and its average
//! shape from 0.68 to 0.74.
TEST(PipelineQuality, BoundedDihedralAnglesLiftTheWorstHex) {
  PipelineOptions plain, bounded;
  bounded.min_dihedral_deg = 18;
  EXPECT_EQ(tetgen_switches_for(bounded), std::string("pq1.5/18Y"));
  bounded.tetgen_switches = "pq1.2Y";
  EXPECT_EQ(tetgen_switches_for(bounded), std::string("pq1.2Y"));  // given switches win
  bounded.tetgen_switches.clear();
  Progress quiet;
  const std::string liver = DTHEX_SOURCE_DIR "/meshes/liver.off";
  const PipelineResult before = run_pipeline(liver, plain, quiet);
  const PipelineResult after = run_pipeline(liver, bounded, quiet);
  EXPECT_GE(after.quality.scaled_jacobian_stats.min, 0.43);
  EXPECT_GT(after.quality.scaled_jacobian_stats.min, before.quality.scaled_jacobian_stats.min + 0.03);
  EXPECT_GE(after.quality.shape_stats.avg, before.quality.shape_stats.avg);
  EXPECT_EQ(after.quality.inverted, 0u);
  EXPECT_EQ(after.quality.gauss_inverted, 0u);
  EXPECT_TRUE(after.conforming);
  // The price: more nodes, but far fewer than the classic THex of the same surface (44,133).
  EXPECT_GT(after.hexes.nodes.size(), before.hexes.nodes.size());
  EXPECT_LT(double(after.hexes.nodes.size()), 1.3 * double(before.hexes.nodes.size()));
}
//! The worst hexes go past the smoother's target: the smoother lifts them where it can, and the
//! regions around those it leaves behind are optimized as a whole (a narrow corner at a crowded
//! tet vertex needs the nodes around it moved together). On the liver the smoother stops at
//! 0.34 and the regions, 90 worst hexes in batches, take the minimum to their 0.4 target, without
//! drawing nodes together: the scaled Jacobian is blind to length, and the regions' solve
//! without its edge floor left the liver's worst hex at Verdict shape 0.026 (0.033 with it).
TEST(PipelineQuality, TheWorstHexesGoPastTheSmoothersTarget) {
  Progress quiet;
  const PipelineResult r = run_pipeline(DTHEX_SOURCE_DIR "/meshes/liver.off", PipelineOptions(), quiet);
  const auto* smoothed = r.stage_report<LocalSmoothReport>("smooth worst");
  const auto* regions = r.stage_report<OptimizeWorstRegionsReport>("optimize worst regions");
  ASSERT_NE(smoothed, nullptr);
  ASSERT_NE(regions, nullptr);
  EXPECT_GT(smoothed->min_scaled_jacobian_after, 0.3);
  EXPECT_DOUBLE_EQ(regions->min_before, smoothed->min_scaled_jacobian_after);
  EXPECT_GT(regions->min_after, regions->min_before + 0.01);
  EXPECT_GE(r.quality.scaled_jacobian_stats.min, regions->min_after);
  EXPECT_GE(r.quality.scaled_jacobian_stats.min, 0.399);
  // The scaled Jacobian is blind to length: the smoother once slid boundary nodes onto their
  // neighbours for it (the liver's shortest edge 0.022 of its hex's longest, worst Verdict shape
  // 0.033). No smoother move may take a hex under 0.05 now, and the regions hold each edge
  // above half of where they found it.
  double shortest_ratio = 1;
  for (size_t h = 0; h < r.hexes.hexes.size(); ++h)
    shortest_ratio = std::min(shortest_ratio, std::sqrt(hex_edge_ratio_squared(hex_corners(r.hexes, h))));
  EXPECT_GE(shortest_ratio, 0.04);
  EXPECT_GE(r.quality.shape_stats.min, 0.045);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_TRUE(r.conforming);
}
TEST(PipelineQuality, FemurMeetsDoneWhen) { expect_done_when("femur_proximal_ct.off", 0.2, 2); }

//! A hollow body (a bone's marrow cavity, a heart's chamber) is a second, inner surface;
//! TetGen fills what it encloses unless told otherwise, so the hexes must leave it empty:
//! the volume is the shell's, and the inner surface is part of the boundary (a filled
//! cavity made the volume +14% and the Hausdorff distance 1.5 radii of the inner sphere).
namespace {

//! The bundled sphere (r = 1) with the same sphere at r = 0.5 inside it, facing inwards, written
//! to a fresh folder named `folder`; returns its path.
std::string sphere_in_sphere(const std::string& folder) {
  TriSurface shell = read_surface(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  const int offset = int(shell.points.size());
  const size_t outer_triangles = shell.triangles.size();
  for (int v = 0; v < offset; ++v) shell.points.push_back(0.5 * shell.points[size_t(v)]);
  for (size_t t = 0; t < outer_triangles; ++t) {
    const auto tri = shell.triangles[t];
    shell.triangles.push_back({tri[0] + offset, tri[2] + offset, tri[1] + offset});  // facing the cavity
  }
  const std::string path = (dthex_test::fresh_dir(folder) / "shell.off").string();
  write_surface(shell, path);
  return path;
}

//! A wall a quarter of the diameter: sized by its thickness and at eps 0.05 (0.5 s; the
//! defaults mesh it twice, 7 s, and the inner sphere's 58-vertex coarse version ends at
//! Hausdorff 1.07%).
PipelineOptions sphere_in_sphere_options() {
  PipelineOptions options;
  options.eps = 0.05;
  options.thickness_ratio = 1;
  return options;
}

}  // namespace

TEST(PipelineQuality, HollowSphereLeavesItsCavityEmpty) {
  const std::string path = sphere_in_sphere("hollow_sphere");
  Progress quiet;
  const PipelineResult r = run_pipeline(path, sphere_in_sphere_options(), quiet);
  EXPECT_EQ(r.input_summary.cavities, 1u);
  EXPECT_NEAR(r.hex_volume, r.input_summary.volume, 0.02 * r.input_summary.volume);
  EXPECT_LE(r.hausdorff, 0.01 * r.input_summary.bbox_diagonal);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_TRUE(r.conforming);
  EXPECT_TRUE(boundary_closed(r.hexes));
  // No node in the cavity: every one at radius 0.5 or more (less the facets' sagitta).
  for (const Vec3& p : r.hexes.nodes) ASSERT_GT(p.norm(), 0.49);
}

//! --nested material: the inner sphere's inside is a second region, meshed conformingly with the
//! shell around it: the two share their interface nodes, which lie on the inner sphere, each
//! region is closed and valid on its own, and the core fills the inner sphere (in cavity mode,
//! above, no node lies inside it).
TEST(PipelineQuality, SphereInASphereAsASecondMaterialSharesItsInterface) {
  const std::string path = sphere_in_sphere("sphere_in_sphere");
  PipelineOptions options = sphere_in_sphere_options();
  options.nested = PipelineOptions::Nested::material;
  Progress quiet;
  const PipelineResult r = run_pipeline(path, options, quiet);
  const HexMesh& mesh = r.hexes;
  ASSERT_EQ(mesh.region.size(), mesh.hexes.size());
  ASSERT_EQ(r.regions.size(), 2u);
  for (const RegionMeasure& region : r.regions) {
    EXPECT_TRUE(region.conforming);
    EXPECT_EQ(region.inverted, 0u);
    EXPECT_GE(region.min_scaled_jacobian, 0.2);
  }
  EXPECT_TRUE(r.conforming);
  EXPECT_EQ(r.quality.gauss_inverted, 0u);
  EXPECT_LE(r.hausdorff, 0.01 * r.input_summary.bbox_diagonal);  // the interface measured too

  // Region 0 is the shell, region 1 the core: the core's nodes lie within the inner sphere, and
  // the nodes both use (the interface) on it.
  std::vector<char> used[2] = {std::vector<char>(mesh.nodes.size(), 0), std::vector<char>(mesh.nodes.size(), 0)};
  double volume[2] = {0, 0};
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    for (int v : mesh.hexes[h]) used[mesh.region[h]][size_t(v)] = 1;
  for (int region = 0; region < 2; ++region) {
    const HexMesh alone = region_submesh(mesh, region);
    volume[region] = enclosed_volume(quads_to_triangles(alone.nodes, boundary_quads(alone)));
  }
  // The interface lies on the input: the worst regions let boundary nodes a little off a
  // curved input, never the nodes two materials share.
  const TriangleBvh input(read_surface(path));
  size_t shared = 0;
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    const double radius = mesh.nodes[v].norm();
    if (used[1][v]) ASSERT_LT(radius, 0.5 + 1e-9);
    if (used[0][v] && used[1][v]) {
      ++shared;
      EXPECT_GT(radius, 0.49) << "interface node " << v << " off the inner sphere";
      EXPECT_LT(std::sqrt(input.closest_point(mesh.nodes[v]).distance_sq), 1e-9 * r.input_summary.bbox_diagonal)
          << "interface node " << v << " off the input";
      EXPECT_GE(mesh.boundary_facet[v], 0);
    }
  }
  const std::vector<std::array<int, 4>> interface = interface_quads(mesh);
  EXPECT_GT(shared, 0u);
  ASSERT_GT(interface.size(), 0u);
  // The core's boundary is exactly the interface: its boundary quads are as many, and every
  // node of them is shared.
  EXPECT_EQ(boundary_quads(region_submesh(mesh, 1)).size(), interface.size());
  // The core fills the inner sphere (volume 4/3 pi 0.125 less the facets' sagitta), and the
  // two regions together the outer one.
  EXPECT_NEAR(volume[1], 0.125 / (1 - 0.125) * r.input_summary.volume, 0.03 * volume[1]);
  EXPECT_NEAR(volume[0] + volume[1], r.input_summary.volume / (1 - 0.125), 0.02 * (volume[0] + volume[1]));
}

namespace {

// A lens of diameter 2 whose two spherical faces meet at its rim at `rim_degrees` (an ear
// drum, a cut bone's grazing edge): a knife edge all round. `rings` rings of `per_ring`
// vertices on each face, the rim shared.
TriSurface lens(double rim_degrees, int per_ring, int rings) {
  const double half = rim_degrees / 2 * M_PI / 180, radius = 1 / std::sin(half), drop = radius * std::cos(half);
  TriSurface s;
  for (int i = 0; i < per_ring; ++i) {
    const double a = 2 * M_PI * i / per_ring;
    s.points.emplace_back(std::cos(a), std::sin(a), 0);
  }
  for (double side : {1.0, -1.0}) {
    std::vector<int> outer(static_cast<size_t>(per_ring));
    for (int i = 0; i < per_ring; ++i) outer[size_t(i)] = i;
    for (int k = rings - 1; k >= 0; --k) {
      const double r = double(k) / rings, z = side * (std::sqrt(radius * radius - r * r) - drop);
      std::vector<int> inner;
      if (k == 0) {
        inner.assign(size_t(per_ring), int(s.points.size()));
        s.points.emplace_back(0, 0, z);
      } else {
        for (int i = 0; i < per_ring; ++i) {
          const double a = 2 * M_PI * (i + 0.5 * ((rings - k) % 2)) / per_ring;
          inner.push_back(int(s.points.size()));
          s.points.emplace_back(r * std::cos(a), r * std::sin(a), z);
        }
      }
      for (int i = 0; i < per_ring; ++i) {
        const int j = (i + 1) % per_ring;
        // Outward: counter-clockwise seen from above on the top face, clockwise below.
        auto add = [&](int a, int b, int c) {
          if (side > 0) s.triangles.push_back({a, b, c});
          else s.triangles.push_back({a, c, b});
        };
        const bool shifted = (rings - k) % 2 == 1;
        if (k == 0) {
          add(outer[size_t(i)], outer[size_t(j)], inner[0]);
        } else if (shifted) {
          add(outer[size_t(i)], outer[size_t(j)], inner[size_t(i)]);
          add(outer[size_t(j)], inner[size_t(j)], inner[size_t(i)]);
        } else {
          add(outer[size_t(i)], inner[size_t(j)], inner[size_t(i)]);
          add(outer[size_t(i)], outer[size_t(j)], inner[size_t(j)]);
        }
      }
      outer = inner;
    }
  }
  return s;
}

}  // namespace

// The lens's rim is a 24-degree knife edge. Held there, its nodes leave THex corners in the
// wedge no smoother can open; free to slide off it by half a percent of the diagonal, the
// worst hexes rise, and the rim is rounded off by no more than that.
TEST(PipelineQuality, KnifeEdgeNodesSlideABoundedWay) {
  const std::string path = (dthex_test::fresh_dir("lens") / "lens.off").string();
  write_surface(lens(24, 32, 4), path);
  PipelineOptions options;
  options.thickness_ratio = 1;
  options.repair_worst_hexes = false;  // the smoother alone: seconds, not half a minute
  Progress quiet;
  options.knife_edge_slide = 0;
  const PipelineResult held = run_pipeline(path, options, quiet);
  options.knife_edge_slide = 0.005;
  const PipelineResult slid = run_pipeline(path, options, quiet);
  EXPECT_EQ(slid.quality.inverted, 0u);
  EXPECT_TRUE(slid.conforming);
  EXPECT_GE(slid.quality.scaled_jacobian_stats.min, held.quality.scaled_jacobian_stats.min + 0.02);
  EXPECT_LE(slid.hausdorff, held.hausdorff + 0.005 * slid.input_summary.bbox_diagonal);
}
//! Spot's worst corner is at a boundary node where the input curves under it, which no slide on
//! the input widens: the regions' second continuation, with the boundary allowed within a fifth
//! of a hex edge (and 0.2% of the diagonal) of the input, takes the worst hex from 0.346 to 0.4.
//! Every boundary node stays within that cap of the input, and the Hausdorff distance does not grow.
TEST(PipelineQuality, BoundarySlackLiftsSpotsWorstHexAndKeepsTheBoundaryNearTheInput) {
  Progress quiet;
  const std::string spot = DTHEX_SOURCE_DIR "/meshes/spot.off";
  PipelineOptions on_input;
  on_input.boundary_slack = 0;
  const PipelineResult held = run_pipeline(spot, on_input, quiet);
  const PipelineOptions defaults;
  const PipelineResult slack = run_pipeline(spot, defaults, quiet);
  ASSERT_LT(held.quality.scaled_jacobian_stats.min, 0.35);
  EXPECT_GE(slack.quality.scaled_jacobian_stats.min, 0.35);
  EXPECT_EQ(slack.quality.inverted, 0u);
  EXPECT_TRUE(slack.conforming);
  EXPECT_LE(slack.hausdorff, held.hausdorff * (1 + 1e-9));
  const double diagonal = slack.input_summary.bbox_diagonal;
  const TriangleBvh input(read_surface(spot));
  double largest = 0, held_largest = 0;
  for (size_t v = 0; v < slack.hexes.nodes.size(); ++v)
    if (slack.hexes.is_boundary_node(int(v)))
      largest = std::max(largest, std::sqrt(input.closest_point(slack.hexes.nodes[v]).distance_sq));
  for (size_t v = 0; v < held.hexes.nodes.size(); ++v)
    if (held.hexes.is_boundary_node(int(v)))
      held_largest = std::max(held_largest, std::sqrt(input.closest_point(held.hexes.nodes[v]).distance_sq));
  EXPECT_LT(held_largest, 1e-9 * diagonal);
  EXPECT_GT(largest, 1e-6 * diagonal);  // some node is off the input: the slack was used
  EXPECT_LE(largest, defaults.boundary_slack_cap * diagonal * (1 + 1e-9));
  // The regions' reports say so: their second continuation ran, within the cap.
  int off_surface_steps = 0;
  for (const StageRecord& stage : slack.stages)
    if (const auto* regions = std::get_if<OptimizeWorstRegionsReport>(&stage.report)) {
      off_surface_steps += regions->off_surface_steps;
      EXPECT_LE(regions->largest_offset, defaults.boundary_slack_cap * diagonal * (1 + 1e-9));
    }
  EXPECT_GT(off_surface_steps, 0);
}

//! A boundary vertex on a crease that too many tets share: THex gives each a hex corner
//! there, and no smoothing widens them past the even split of the crease's solid angle. On the
//! shared fandisk (a CAD part of 90-degree creases) one such vertex held the worst hex at 0.275
//! (docs/CASE_STUDIES.md); the tet clean-up now takes an interior edge there out by a flip, and
//! the worst hex passes 0.3.
TEST(PipelineQuality, ACrowdedVertexOnACreaseIsThinnedAndTheWorstHexRises) {
  const std::string path = std::string(DTHEX_SHARED_DIR) + "/meshes/fandisk.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  Progress quiet;
  const PipelineResult r = run_pipeline(path, PipelineOptions(), quiet);
  const auto* thinned = r.stage_report<ThinCrowdedBoundaryStarsReport>("thin boundary stars");
  ASSERT_NE(thinned, nullptr);
  EXPECT_GE(thinned->crowded_before, 1u);
  EXPECT_GE(thinned->edges_removed, 1u);
  EXPECT_EQ(thinned->crowded_after, 0u);
  EXPECT_GT(thinned->lowest_bound_after, thinned->lowest_bound_before);
  EXPECT_GE(thinned->lowest_bound_after, ThinCrowdedBoundaryStarsOptions().target_bound);
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_TRUE(r.conforming);
  EXPECT_GE(r.quality.scaled_jacobian_stats.min, 0.3);
}
