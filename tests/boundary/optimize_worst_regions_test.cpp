// SPDX-License-Identifier: MIT
#include <dthex/boundary/optimize_worst_regions.h>

#include <dthex/boundary/local_smooth.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include "boundary_fixtures.h"

#include <gtest/gtest.h>

using namespace dthex;
using namespace dthex::testing;

namespace {

// The banded sphere coned to its centre (64 tets there), THexed, diced, and smoothed node by
// node towards 0.6: the smoother stops at the corners around the centre, where only a joint
// move of the nodes around it widens the narrowest.
HexMesh smoothed_coned_sphere(const TriSurface& sphere) {
  HexMesh hexes = dice(thex(star_tets(sphere, Vec3::Zero())), 2);
  LocalSmoothOptions smooth;
  smooth.lift_step = 0;
  smooth.target_scaled_jacobian = 0.6;
  smooth_worst_hexes(hexes, TriangleBvh(sphere), smooth);
  return hexes;
}

}  // namespace

// The regions around the worst hexes, optimized as a whole, lift the minimum where the node-by-
// node smoother stopped; the boundary does not move, nothing is inverted, and the report's
// figures are the mesh's.
TEST(OptimizeWorstRegions, RaisesTheMinimumWhereTheNodeByNodeSmootherStopped) {
  const TriSurface sphere = staggered_sphere(8, 5);
  HexMesh mesh = smoothed_coned_sphere(sphere);
  const std::vector<Vec3> before = mesh.nodes;
  const double min_before = measure_hex_quality(mesh).scaled_jacobian_stats.min;
  ASSERT_LT(min_before, 0.3);
  OptimizeWorstRegionsOptions options;
  options.target = 0.6;
  options.max_seeds = 256;  // the centre's 64 corners are all near the minimum: seed them all
  const OptimizeWorstRegionsReport report = optimize_worst_regions(mesh, options);
  const HexQuality q = measure_hex_quality(mesh);
  EXPECT_DOUBLE_EQ(report.min_before, min_before);
  EXPECT_DOUBLE_EQ(report.min_after, q.scaled_jacobian_stats.min);
  EXPECT_GE(report.steps, 1);
  EXPECT_GT(report.moved_nodes, 0u);
  // 64 corners share the sphere at the centre, which bounds them at 0.33: the region gets part of the
  // way from where the smoother stopped (0.299) towards that bound.
  EXPECT_GT(q.scaled_jacobian_stats.min, min_before + 0.005);
  EXPECT_EQ(q.inverted, 0u);
  const std::vector<char> on_boundary = [&] {
    std::vector<char> b(mesh.nodes.size(), 0);
    for (size_t v = 0; v < mesh.nodes.size(); ++v) b[v] = mesh.is_boundary_node(int(v));
    return b;
  }();
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (on_boundary[v]) EXPECT_EQ(mesh.nodes[v], before[v]) << "boundary node " << v << " moved";
}

// The worst hexes above one half only with the regions: the sphere of 36 triangles coned to a
// point off its centre, (0.6, 0.3, 0.18), THexed and diced. Node by node the smoother stops at
// 0.462 (a second run: 0.464), the corners at the cone's apex widened one node at a
// time as far as each alone can go; the regions move the nodes around it together, to the
// same 0.508 as from the centred cone (the apex's 36 corners share its sphere evenly there).
TEST(OptimizeWorstRegions, LiftsTheWorstHexAboveOneHalfWhereTheSmootherStopsBelow) {
  const TriSurface sphere = staggered_sphere(6, 4);
  ASSERT_EQ(sphere.triangles.size(), 36u);
  HexMesh mesh = dice(thex(star_tets(sphere, Vec3(0.6, 0.3, 0.18))), 2);
  LocalSmoothOptions smooth;
  smooth.lift_step = 0;
  smooth.target_scaled_jacobian = 0.7;
  const TriangleBvh surface(sphere);
  smooth_worst_hexes(mesh, surface, smooth);
  const double smoothed = measure_hex_quality(mesh).scaled_jacobian_stats.min;
  smooth_worst_hexes(mesh, surface, smooth);
  const double smoothed_again = measure_hex_quality(mesh).scaled_jacobian_stats.min;
  EXPECT_LT(smoothed, 0.48);
  EXPECT_LT(smoothed_again, smoothed + 0.01);
  const std::vector<Vec3> before = mesh.nodes;
  OptimizeWorstRegionsOptions options;
  options.target = 0.7;
  options.max_seeds = 256;  // the apex's corners are all near the minimum: seed them all
  const OptimizeWorstRegionsReport report = optimize_worst_regions(mesh, options);
  const HexQuality q = measure_hex_quality(mesh);
  std::printf("off-centre cone: smoothed %.3f, again %.3f, regions %.3f\n", smoothed, smoothed_again,
              q.scaled_jacobian_stats.min);
  EXPECT_DOUBLE_EQ(report.min_after, q.scaled_jacobian_stats.min);
  EXPECT_GT(q.scaled_jacobian_stats.min, 0.5);
  EXPECT_EQ(q.inverted, 0u);
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (mesh.is_boundary_node(int(v))) EXPECT_EQ(mesh.nodes[v], before[v]) << "boundary node " << v << " moved";
}

// Poor hexes (below poor_below) are worth more steps: the continuation goes on past `steps`
// while each step gains and the minimum stays below poor_below, up to steps_while_poor, and
// stops taking extra steps once the minimum is above it.
TEST(OptimizeWorstRegions, TakesMoreStepsWhileTheWorstHexesArePoor) {
  const TriSurface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 6);
  const HexMesh start = perturbed_block(box, 6, 0.35);
  const double min_before = measure_hex_quality(start).scaled_jacobian_stats.min;
  OptimizeWorstRegionsOptions options;
  options.target = 0.9;
  options.steps = 1;
  options.poor_below = -1;  // no extra steps
  HexMesh one_step = start;
  const OptimizeWorstRegionsReport plain = optimize_worst_regions(one_step, options);
  options.poor_below = 0.2;
  options.steps_while_poor = 48;
  HexMesh more = start;
  const OptimizeWorstRegionsReport extra = optimize_worst_regions(more, options);
  ASSERT_LT(min_before, 0);  // some hexes start inverted
  EXPECT_EQ(plain.steps, 1);
  EXPECT_LT(plain.min_after, options.poor_below);
  // The extra steps gained, up to above poor_below, and then stopped though the target is
  // far (not for want of a gain).
  EXPECT_GT(extra.steps, 1);
  EXPECT_LE(extra.steps, options.steps_while_poor);
  EXPECT_GE(extra.min_after, options.poor_below);
  EXPECT_GT(extra.min_after, plain.min_after + 0.1);
  EXPECT_EQ(extra.seeds_without_gain, 0u);
  const HexQuality q = measure_hex_quality(more);
  EXPECT_DOUBLE_EQ(q.scaled_jacobian_stats.min, extra.min_after);
  EXPECT_EQ(q.inverted, 0u);
}

// A mesh with no hex below the target is not touched.
TEST(OptimizeWorstRegions, LeavesAMeshAboveTheTargetAlone) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const TriSurface box = box_surface(lo, hi, 3);
  HexMesh mesh = perturbed_block(box, 3, 0.1);
  const std::vector<Vec3> before = mesh.nodes;
  OptimizeWorstRegionsOptions options;
  options.target = 0.3;
  ASSERT_GT(measure_hex_quality(mesh).scaled_jacobian_stats.min, options.target);
  const OptimizeWorstRegionsReport report = optimize_worst_regions(mesh, options);
  EXPECT_EQ(report.steps, 0);
  EXPECT_EQ(report.seeds, 0u);
  EXPECT_EQ(mesh.nodes, before);
}

// A worst hex with no interior node (here a lone, skewed hex: every node on the boundary) cannot
// be raised by the interior nodes around it: nothing moves, and the report says how many
// worst hexes were left so, instead of reading like a mesh without any.
TEST(OptimizeWorstRegions, SaysWhenTheInteriorNodesAroundTheWorstCannotRaiseThem) {
  HexMesh mesh;
  mesh.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1.8, 1, 1}, {0.8, 1, 1}};
  mesh.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
  const std::vector<Vec3> before = mesh.nodes;
  const double min_before = measure_hex_quality(mesh).scaled_jacobian_stats.min;
  OptimizeWorstRegionsOptions options;
  options.target = 0.9;
  ASSERT_LT(min_before, options.target);
  const OptimizeWorstRegionsReport report = optimize_worst_regions(mesh, options);
  EXPECT_EQ(report.steps, 0);
  EXPECT_EQ(report.seeds, 0u);
  EXPECT_EQ(report.seeds_without_gain, 1u);
  EXPECT_DOUBLE_EQ(report.min_after, min_before);
  EXPECT_EQ(mesh.nodes, before);
}

// More worst hexes than one solve takes (the centre's 64 corners against 32 seeds a solve) are
// taken in batches, worst first: the minimum rises where a single batch would end the run.
TEST(OptimizeWorstRegions, TakesManyWorstHexesInBatches) {
  const TriSurface sphere = staggered_sphere(8, 5);
  const HexMesh start = smoothed_coned_sphere(sphere);
  const double min_before = measure_hex_quality(start).scaled_jacobian_stats.min;
  OptimizeWorstRegionsOptions options;
  options.target = 0.6;
  HexMesh batched = start;
  const OptimizeWorstRegionsReport report = optimize_worst_regions(batched, options);
  EXPECT_GT(report.seeds, options.max_seeds);
  EXPECT_GT(measure_hex_quality(batched).scaled_jacobian_stats.min, min_before + 0.005);
  EXPECT_EQ(measure_hex_quality(batched).inverted, 0u);
  options.max_batches = 1;
  HexMesh single = start;
  const OptimizeWorstRegionsReport one = optimize_worst_regions(single, options);
  EXPECT_TRUE(one.too_many_seeds);
  EXPECT_EQ(one.steps, 0);
  EXPECT_EQ(single.nodes, start.nodes);
}

// A slab one hex thick has no interior node: where a node of its flat top is pushed aside, only
// the boundary nodes can straighten the hexes. Given the surface they slide on it, off its
// edges and corners, and stay on it; without it nothing moves.
TEST(OptimizeWorstRegions, SlidesBoundaryNodesOnTheSurfaceWhereNoInteriorNodeCanHelp) {
  const Vec3 lo(0, 0, 0), hi(3, 3, 1);
  const TriSurface slab = box_surface(lo, hi, {3, 3, 1});
  HexMesh start = hex_block(lo, hi, 3, 3, 1);
  const size_t pushed = size_t((1 * 4 + 1) * 4 + 1);  // the top's node (1, 1, 1)
  ASSERT_EQ(start.nodes[pushed], Vec3(1, 1, 1));
  start.nodes[pushed] = Vec3(1.7, 1.6, 1);
  const double min_before = measure_hex_quality(start).scaled_jacobian_stats.min;
  ASSERT_LT(min_before, 0.8);
  OptimizeWorstRegionsOptions options;
  options.target = 0.9;
  HexMesh fixed = start;
  const OptimizeWorstRegionsReport without = optimize_worst_regions(fixed, options);
  EXPECT_EQ(without.steps, 0);
  EXPECT_EQ(fixed.nodes, start.nodes);
  const TriangleBvh surface(slab);
  options.surface = &surface;
  HexMesh slid = start;
  const OptimizeWorstRegionsReport with = optimize_worst_regions(slid, options);
  EXPECT_GE(with.steps, 1);
  EXPECT_GT(measure_hex_quality(slid).scaled_jacobian_stats.min, min_before + 0.1);
  for (size_t v = 0; v < slid.nodes.size(); ++v) {
    const Vec3& x = slid.nodes[v];
    EXPECT_NEAR(surface.closest_point(x).distance_sq, 0.0, 1e-20) << "node " << v << " left the surface";
    const Vec3& s = start.nodes[v];
    const bool on_edge = (s.x() == 0 || s.x() == 3) + (s.y() == 0 || s.y() == 3) + (s.z() == 0 || s.z() == 1) >= 2;
    if (on_edge) EXPECT_EQ(x, s) << "node " << v << " on an edge or corner of the slab moved";
  }
}

namespace {

// A slab [0, 3] x [0, 3] x [0, 1] whose top has a smooth dimple under the point (1, 1), fine
// triangles, and the block of 3 x 3 x 1 hexes with its top nodes on it.
struct DimpledSlab {
  TriSurface surface;
  HexMesh hexes;
};
DimpledSlab dimpled_slab() {
  const Vec3 lo(0, 0, 0), hi(3, 3, 1);
  const double depth = 0.85, width = 0.5;
  auto dimpled = [&](const Vec3& p) {
    if (p.z() != hi.z()) return p;
    const double r2 = (p.x() - 1) * (p.x() - 1) + (p.y() - 1) * (p.y() - 1);
    return Vec3(p.x(), p.y(), hi.z() - depth * std::exp(-r2 / (width * width)));
  };
  DimpledSlab slab{box_surface(lo, hi, {30, 30, 10}), hex_block(lo, hi, 3, 3, 1)};
  for (Vec3& p : slab.surface.points) p = dimpled(p);
  for (Vec3& p : slab.hexes.nodes) p = dimpled(p);
  return slab;
}

}  // namespace

// The dimpled slab: the four hexes around the node (1, 1, 1) are flattened at that corner,
// and no node can help on the input (none is inside, the dimple's bottom is where a slide
// would stay). With surface_slack the node rises off the input, by no more than the slack, and
// the worst hex rises with it; edges and corners stay, and the minimum is the same or higher
// than without, as the stage promises.
TEST(OptimizeWorstRegions, LetsBoundaryNodesOffTheInputWithinTheSlackWhereOnItNothingGains) {
  const DimpledSlab slab = dimpled_slab();
  const HexMesh& start = slab.hexes;
  const TriangleBvh surface(slab.surface);
  const double min_before = measure_hex_quality(start).scaled_jacobian_stats.min;
  ASSERT_LT(min_before, 0.8);
  OptimizeWorstRegionsOptions options;
  options.target = 0.95;
  options.steps = 100;  // till the minimum on the input gains no more
  options.surface = &surface;
  HexMesh on_input = start;
  const OptimizeWorstRegionsReport without = optimize_worst_regions(on_input, options);
  EXPECT_GT(without.seeds_without_gain, 0u);
  EXPECT_EQ(without.off_surface_steps, 0);
  EXPECT_EQ(without.nodes_off_surface, 0u);
  options.surface_slack = 0.2;
  HexMesh off_input = start;
  const OptimizeWorstRegionsReport with = optimize_worst_regions(off_input, options);
  EXPECT_DOUBLE_EQ(with.min_on_surface, without.min_after);
  EXPECT_GE(with.off_surface_steps, 1);
  EXPECT_GE(with.nodes_off_surface, 1u);
  const double min_without = measure_hex_quality(on_input).scaled_jacobian_stats.min;
  const HexQuality q = measure_hex_quality(off_input);
  EXPECT_DOUBLE_EQ(with.min_after, q.scaled_jacobian_stats.min);
  EXPECT_GT(q.scaled_jacobian_stats.min, min_without + 0.05);
  EXPECT_EQ(q.inverted, 0u);
  double largest = 0;
  for (size_t v = 0; v < off_input.nodes.size(); ++v) {
    const Vec3& x = off_input.nodes[v];
    const double offset = std::sqrt(surface.closest_point(x).distance_sq);
    largest = std::max(largest, offset);
    // The slack is a fraction of the node's mean distance to its hexes' nodes, under 2 here.
    EXPECT_LE(offset, options.surface_slack * 2) << "node " << v << " left the input by more than the slack";
    const Vec3& s = start.nodes[v];
    const bool on_edge = (s.x() == 0 || s.x() == 3) + (s.y() == 0 || s.y() == 3) + (s.z() == 0 || s.z() > 0.5) >= 2;
    if (on_edge) EXPECT_EQ(x, s) << "node " << v << " on an edge or corner of the slab moved";
  }
  EXPECT_NEAR(with.largest_offset, largest, 1e-12);
}

// Where two materials meet (HexMesh::region), the nodes they share stay on the input: the
// dimpled slab with its hexes at x > 1 a second material keeps the dimple's node (1, 1, 1),
// which then has hexes of both, where it is, while in one material the slack lifts it.
TEST(OptimizeWorstRegions, KeepsTheNodesTwoMaterialsShareOnTheInput) {
  const DimpledSlab slab = dimpled_slab();
  const TriangleBvh surface(slab.surface);
  const size_t dimple = size_t((1 * 4 + 1) * 4 + 1);  // the top's node (1, 1, 1)
  ASSERT_EQ(slab.hexes.nodes[dimple].x(), 1.0);
  ASSERT_EQ(slab.hexes.nodes[dimple].y(), 1.0);
  OptimizeWorstRegionsOptions options;
  options.target = 0.95;
  options.steps = 100;
  options.surface = &surface;
  options.surface_slack = 0.2;
  HexMesh one = slab.hexes;
  optimize_worst_regions(one, options);
  EXPECT_GT(std::sqrt(surface.closest_point(one.nodes[dimple]).distance_sq), 0.01);
  HexMesh two = slab.hexes;
  two.region.assign(two.hexes.size(), 0);
  for (size_t h = 0; h < two.hexes.size(); ++h)
    if (two.nodes[size_t(two.hexes[h][6])].x() > 1.5) two.region[h] = 1;  // the hexes at x > 1
  optimize_worst_regions(two, options);
  EXPECT_LT(std::sqrt(surface.closest_point(two.nodes[dimple]).distance_sq), 1e-12);
  EXPECT_EQ(measure_hex_quality(two).inverted, 0u);
}
