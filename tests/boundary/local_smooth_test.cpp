// SPDX-License-Identifier: MIT
#include <dthex/boundary/local_smooth.h>

#include "boundary_fixtures.h"
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/split_crowded_vertices.h>

#include <gtest/gtest.h>

using namespace dthex;
using namespace dthex::testing;

// A 4^3 block whose interior nodes are pushed into near-flat corners: the smoother lifts
// every hex to the target, the boundary (a box: feature edges and corners everywhere, flat
// faces) stays on the box, and corner and edge nodes do not move.
TEST(LocalSmooth, LiftsDistortedBlockToTarget) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const TriSurface box = box_surface(lo, hi, 4);
  HexMesh mesh = hex_block(lo, hi, 4, 4, 4);
  label_boundary(mesh, box);
  const std::vector<Vec3> original = mesh.nodes;
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (!mesh.is_boundary_node(int(v))) mesh.nodes[v] += Vec3(0.057, -0.051, 0.054) * ((v % 3) == 0 ? 1.0 : -0.4);
  const double before = measure_hex_quality(mesh).scaled_jacobian_stats.min;
  ASSERT_GT(before, 0);
  ASSERT_LT(before, 0.3);

  const TriangleBvh bvh(box);
  const LocalSmoothReport report = smooth_worst_hexes(mesh, bvh);
  const HexQuality q = measure_hex_quality(mesh);
  EXPECT_DOUBLE_EQ(report.min_scaled_jacobian_before, before);
  EXPECT_DOUBLE_EQ(report.min_scaled_jacobian_after, q.scaled_jacobian_stats.min);
  EXPECT_GE(q.scaled_jacobian_stats.min, 0.3 - 1e-12);
  EXPECT_GT(q.shape_stats.avg, 0.8);
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    if (!mesh.is_boundary_node(int(v))) continue;
    EXPECT_LT(std::sqrt(bvh.closest_point(mesh.nodes[v]).distance_sq), 1e-12) << "node " << v;
    int on_faces = 0;
    for (int c = 0; c < 3; ++c) on_faces += std::abs(original[v][c]) < 1e-12 || std::abs(original[v][c] - 1) < 1e-12;
    if (on_faces >= 2) EXPECT_LT((mesh.nodes[v] - original[v]).norm(), 1e-12) << "feature node " << v << " moved";
  }
}

// The lift: after the pass to the target (0.3), the target rises by 0.05 at a time while the
// minimum keeps rising. On the banded sphere coned to its centre, the centre split until no
// vertex is in more than 28 tets (split_crowded_vertices.h), THexed and diced, the worst hexes
// stop at the target without the lift and reach 0.45 with it (to 0.5; the last step falls short).
TEST(LocalSmooth, LiftRaisesTheWorstHexesPastTheTarget) {
  const TriSurface sphere = staggered_sphere(8, 5);
  TetMesh tets = star_tets(sphere, Vec3::Zero());
  SplitCrowdedVerticesOptions split;
  split.max_tets = 28;
  split.min_quality_ratio = 0.7;
  split_crowded_vertices(tets, split);
  HexMesh plain = dice(thex(tets), 2);
  HexMesh lifted = plain;
  const TriangleBvh bvh(sphere);
  LocalSmoothOptions without, with;
  without.lift_step = 0;
  with.lift_to_scaled_jacobian = 0.5;
  const LocalSmoothReport plain_report = smooth_worst_hexes(plain, bvh, without);
  const LocalSmoothReport lifted_report = smooth_worst_hexes(lifted, bvh, with);
  const HexQuality plain_q = measure_hex_quality(plain), lifted_q = measure_hex_quality(lifted);
  EXPECT_EQ(plain_report.lifted_to, 0.0);
  EXPECT_GE(lifted_report.lifted_to, 0.45 - 1e-12);
  EXPECT_LT(plain_q.scaled_jacobian_stats.min, 0.32);
  EXPECT_GE(lifted_q.scaled_jacobian_stats.min, 0.44);
  EXPECT_EQ(lifted_q.inverted, 0u);
  EXPECT_DOUBLE_EQ(lifted_report.min_scaled_jacobian_after, lifted_q.scaled_jacobian_stats.min);
}

// The smoother never lowers the smallest scaled Jacobian, even when it cannot reach the target.
TEST(LocalSmooth, NeverLowersTheMinimum) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const TriSurface box = box_surface(lo, hi, 2);
  HexMesh mesh = hex_block(lo, hi, 2, 2, 2);
  label_boundary(mesh, box);
  const TriangleBvh bvh(box);
  LocalSmoothOptions options;
  options.target_scaled_jacobian = 0.99;  // a unit block is already at 1: nothing to raise
  const LocalSmoothReport report = smooth_worst_hexes(mesh, bvh, options);
  EXPECT_EQ(report.moves, 0u);
  EXPECT_NEAR(measure_hex_quality(mesh).scaled_jacobian_stats.min, 1.0, 1e-12);
}

// The shape sweeps (Laplacian guess, compass search where it fails) raise the mean shape
// well above what the scaled-Jacobian pass alone leaves, and never take a hex below
// min(its scaled Jacobian before, target).
TEST(LocalSmooth, ShapeSweepsRaiseMeanShapeAndKeepTheFloor) {
  const TriSurface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 6);
  const TriangleBvh bvh(box);
  const HexMesh start = perturbed_block(box, 6, 0.25);
  const HexQuality before = measure_hex_quality(start);
  ASSERT_GT(before.scaled_jacobian_stats.min, 0);
  ASSERT_LT(before.shape_stats.avg, 0.88);

  LocalSmoothOptions no_sweeps;
  no_sweeps.shape_sweeps = 0;
  HexMesh raised = start;
  smooth_worst_hexes(raised, bvh, no_sweeps);
  HexMesh swept = start;
  const LocalSmoothReport report = smooth_worst_hexes(swept, bvh);
  const HexQuality q_raised = measure_hex_quality(raised), q_swept = measure_hex_quality(swept);
  EXPECT_GT(q_swept.shape_stats.avg, q_raised.shape_stats.avg + 0.05);
  EXPECT_GT(q_swept.shape_stats.avg, 0.9);  // a perturbed grid relaxes back towards cubes
  EXPECT_NEAR(report.avg_shape_after, q_swept.shape_stats.avg, 1e-12);
  EXPECT_GE(q_swept.scaled_jacobian_stats.min,
            std::min(before.scaled_jacobian_stats.min, LocalSmoothOptions{}.target_scaled_jacobian) - 1e-12);
  // The boundary stays on the box (its faces are flat: nodes slide in them, edges stay).
  for (size_t v = 0; v < swept.nodes.size(); ++v)
    if (swept.is_boundary_node(int(v))) EXPECT_LT(std::sqrt(bvh.closest_point(swept.nodes[v]).distance_sq), 1e-12);
  // Deterministic: the same input gives the same mesh.
  HexMesh again = start;
  smooth_worst_hexes(again, bvh);
  for (size_t v = 0; v < swept.nodes.size(); ++v) EXPECT_EQ(again.nodes[v], swept.nodes[v]) << "node " << v;
}

// The shape sweeps run colour by colour, several threads within a colour: on a block big
// enough for the threads to share the colours, two runs give the same nodes bit for bit,
// and the floor holds.
TEST(LocalSmooth, ColouredSweepsAreDeterministic) {
  const TriSurface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 14);
  const TriangleBvh bvh(box);
  const HexMesh start = perturbed_block(box, 14, 0.2);
  const HexQuality start_quality = measure_hex_quality(start);
  const double before = start_quality.scaled_jacobian_stats.min;
  ASSERT_GT(before, 0);
  HexMesh first = start, second = start;
  const LocalSmoothReport report = smooth_worst_hexes(first, bvh);
  smooth_worst_hexes(second, bvh);
  EXPECT_GT(report.moves, 200u);
  for (size_t v = 0; v < first.nodes.size(); ++v) ASSERT_EQ(first.nodes[v], second.nodes[v]) << "node " << v;
  const HexQuality q = measure_hex_quality(first);
  EXPECT_GE(q.scaled_jacobian_stats.min, std::min(before, LocalSmoothOptions{}.target_scaled_jacobian) - 1e-12);
  EXPECT_GT(q.shape_stats.avg, start_quality.shape_stats.avg + 0.01);
}

// Around an inverted hex the smoother's floor is negative. It may still never turn a valid
// hex into an inverted one or push it below min(its value, target): moves that only kept the
// worst hex once walked nodes of a tangled region far across the mesh.
TEST(LocalSmooth, ValidHexesStayValidAroundAnInvertedOne) {
  const TriSurface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 8);
  const TriangleBvh bvh(box);
  HexMesh mesh = perturbed_block(box, 8, 0.3);
  // Two interior nodes pushed through their neighbours: a cluster of inverted hexes the
  // smoother alone cannot repair.
  for (int node : {(3 * 9 + 3) * 9 + 3, (4 * 9 + 4) * 9 + 5}) {
    ASSERT_FALSE(mesh.is_boundary_node(node));
    mesh.nodes[size_t(node)] += Vec3(0.21, 0.19, 0.2);
  }
  const HexQuality before = measure_hex_quality(mesh);
  ASSERT_GT(before.inverted, 0u);
  smooth_worst_hexes(mesh, bvh);
  const HexQuality after = measure_hex_quality(mesh);
  const double target = LocalSmoothOptions{}.target_scaled_jacobian;
  size_t lowered = 0;
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    if (before.scaled_jacobian[h] > 0 && after.scaled_jacobian[h] < std::min(before.scaled_jacobian[h], target) - 1e-12)
      ++lowered;
  EXPECT_EQ(lowered, 0u);
  EXPECT_LE(after.inverted, before.inverted);
}

// The queue's budget: on a distorted block, with room for 20 queue entries in all
// (attempts per hex x at least 1 hex), the scaled-Jacobian pass stops after 20, where it
// needs more to finish; the worst hexes came first, so the minimum still rose.
TEST(LocalSmooth, AttemptBudgetBoundsTheQueueAndTheWorstComeFirst) {
  const Vec3 lo(0, 0, 0), hi(1, 1, 1);
  const TriSurface box = box_surface(lo, hi, 4);
  // Every interior node of a 6^3 block pushed a third of the spacing along a direction
  // that changes from node to node: most hexes end below the target.
  auto distorted = [&] {
    HexMesh mesh = hex_block(lo, hi, 6, 6, 6);
    label_boundary(mesh, box);
    for (size_t v = 0; v < mesh.nodes.size(); ++v)
      if (!mesh.is_boundary_node(int(v)))
        mesh.nodes[v] += 0.055 * Vec3(std::cos(2.4 * double(v)), std::sin(2.4 * double(v)), std::cos(1.3 * double(v)))
                                     .normalized();
    return mesh;
  };
  const TriangleBvh bvh(box);
  LocalSmoothOptions options;
  options.shape_sweeps = 0;  // one scaled-Jacobian pass: report.sweeps counts its queue entries
  options.target_scaled_jacobian = 0.7;  // most hexes of the block are below it
  HexMesh free_mesh = distorted();
  const LocalSmoothReport unbounded = smooth_worst_hexes(free_mesh, bvh, options);
  ASSERT_GT(unbounded.sweeps, 20);
  ASSERT_GT(measure_hex_quality(distorted()).scaled_jacobian_stats.min, 0.0);

  options.attempt_budget_fraction = 0;
  options.attempt_budget_hexes = 1;
  HexMesh mesh = distorted();
  const LocalSmoothReport bounded = smooth_worst_hexes(mesh, bvh, options);
  EXPECT_LE(bounded.sweeps, 20);
  EXPECT_GT(bounded.min_scaled_jacobian_after, bounded.min_scaled_jacobian_before);
  EXPECT_DOUBLE_EQ(bounded.min_scaled_jacobian_after, measure_hex_quality(mesh).scaled_jacobian_stats.min);
}

// A node on a crease line moves along it only with slide_along_creases, and stays on it. A
// row of 4 x 1 x 1 hexes in the unit box has every node on an edge of the box; with the node
// at (0.25, 0, 0) pushed along its edge to (0.45, 0, 0) its two hexes are skewed, and held on
// the creases nothing can move. Sliding, the nodes move along the edges and the hexes are
// nearly cubes again; every edge node stays on its edge's line, and the corners stay.
TEST(LocalSmooth, CreaseNodesSlideAlongTheirLineOnlyWhenAsked) {
  const Vec3 lo(0, 0, 0), hi(1, 0.25, 0.25);
  const TriSurface box = box_surface(lo, hi, {4, 1, 1});
  HexMesh pushed = hex_block(lo, hi, 4, 1, 1);
  label_boundary(pushed, box);
  const size_t edge_node = 1;  // (0.25, 0, 0): hex_block numbers x fastest
  ASSERT_LT((pushed.nodes[edge_node] - Vec3(0.25, 0, 0)).norm(), 1e-15);
  pushed.nodes[edge_node] = Vec3(0.45, 0, 0);
  const double before = measure_hex_quality(pushed).scaled_jacobian_stats.min;
  ASSERT_GT(before, 0);
  ASSERT_LT(before, 0.75);
  const TriangleBvh bvh(box);
  LocalSmoothOptions options;
  options.target_scaled_jacobian = 0.95;
  options.lift_step = 0;
  options.shape_sweeps = 0;

  HexMesh held = pushed, slid = pushed;
  smooth_worst_hexes(held, bvh, options);
  options.slide_along_creases = true;
  smooth_worst_hexes(slid, bvh, options);
  EXPECT_EQ(held.nodes, pushed.nodes);  // held: nothing moves
  EXPECT_GE(measure_hex_quality(slid).scaled_jacobian_stats.min, 0.95 - 1e-12);
  EXPECT_LT(slid.nodes[edge_node].x(), 0.35);  // back along the edge
  for (size_t v = 0; v < slid.nodes.size(); ++v) {
    const Vec3& was = pushed.nodes[v];
    const bool corner = (was.x() == lo.x() || was.x() == hi.x());
    if (corner) EXPECT_EQ(slid.nodes[v], was) << "corner " << v << " moved";
    EXPECT_NEAR(slid.nodes[v].y(), was.y(), 1e-12) << "node " << v << " left its edge";
    EXPECT_NEAR(slid.nodes[v].z(), was.z(), 1e-12) << "node " << v << " left its edge";
  }
}
