// SPDX-License-Identifier: MIT
#include <dthex/boundary/untangle.h>

#include "boundary_fixtures.h"
#include <dthex/boundary/project_boundary.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>

#include <gtest/gtest.h>

using namespace dthex;
using namespace dthex::testing;

namespace {

double distance_to(const TriangleBvh& bvh, const Vec3& p) { return std::sqrt(bvh.closest_point(p).distance_sq); }

}  // namespace

// The paper's sphere case end to end: icosahedron around its centre, THex, dice 3, projected
// onto the 728-triangle sphere, untangled and smoothed. Paper: avg 0.8298, min 0.5332.
TEST(Untangle, SphereReachesTargetQuality) {
  const TriSurface coarse = read_off(DTHEX_SOURCE_DIR "/meshes/icosahedron.off");
  const TriSurface fine = read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  HexMesh mesh = dice(thex(star_tets(coarse, Vec3::Zero())), 3);
  const TriangleBvh bvh(fine);
  project_boundary(mesh, coarse, fine, bvh);
  const HexQuality projected = measure_hex_quality(mesh);
  const UntangleReport report = untangle_and_smooth(mesh, bvh);
  const HexQuality q = measure_hex_quality(mesh);
  std::printf("sphere: projected avg %.4f min %.4f; untangled avg %.4f min %.4f minSJ %.4f, %d rounds, %.2f s\n",
              projected.shape_stats.avg, projected.shape_stats.min, q.shape_stats.avg, q.shape_stats.min,
              q.scaled_jacobian_stats.min, report.rounds, report.seconds);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(report.inverted_after, 0u);
  EXPECT_GE(q.shape_stats.avg, 0.85);
  EXPECT_GE(q.shape_stats.min, 0.6);
  EXPECT_DOUBLE_EQ(report.min_scaled_jacobian, q.scaled_jacobian_stats.min);
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (mesh.is_boundary_node(int(v))) EXPECT_LT(distance_to(bvh, mesh.nodes[v]), 1e-9) << "node " << v;
}

// An interior node pushed through a face of its hexes: several hexes invert; the untangler
// must repair them all without moving the boundary off the cube.
TEST(Untangle, InteriorNodePushedThroughFace) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 4, 4);
  label_boundary(mesh, box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1));
  const int pushed = (1 * 5 + 1) * 5 + 1;  // node (1, 1, 1) at (0.25, 0.25, 0.25)
  ASSERT_FALSE(mesh.is_boundary_node(pushed));
  mesh.nodes[size_t(pushed)] = Vec3(0.6, 0.55, 0.62);  // beyond the far faces of its 8 hexes
  const std::vector<Vec3> before = mesh.nodes;
  const TriangleBvh bvh(cube);
  const UntangleReport report = untangle_and_smooth(mesh, bvh);
  EXPECT_GT(report.inverted_before, 0u);
  EXPECT_EQ(report.inverted_after, 0u);
  const HexQuality q = measure_hex_quality(mesh);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_GT(q.scaled_jacobian_stats.min, 0.5);  // a 4^3 grid has a much better optimum than that
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (mesh.is_boundary_node(int(v))) EXPECT_LT(distance_to(bvh, mesh.nodes[v]), 1e-9) << "node " << v;
}

// A boundary node dragged across its neighbour within the top face: the fixed-boundary phase
// cannot repair that, the sliding phase must, and the node stays on the cube.
TEST(Untangle, BoundaryNodesSlideOnTheSurface) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 4, 4);
  label_boundary(mesh, box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1));
  const int dragged = (4 * 5 + 2) * 5 + 1;  // top face node (0.25, 0.5, 1)
  ASSERT_TRUE(mesh.is_boundary_node(dragged));
  mesh.nodes[size_t(dragged)] = Vec3(0.6, 0.5, 1.0);  // past its neighbour at (0.5, 0.5, 1)
  const TriangleBvh bvh(cube);

  HexMesh fixed = mesh;
  UntangleOptions no_sliding;
  no_sliding.slide_boundary = false;
  EXPECT_GT(untangle_and_smooth(fixed, bvh, no_sliding).inverted_after, 0u);

  const UntangleReport report = untangle_and_smooth(mesh, bvh);
  EXPECT_GT(report.inverted_before, 0u);
  EXPECT_EQ(report.inverted_after, 0u);
  EXPECT_GT(report.sliding_boundary_nodes, 0u);
  // The interior-only repair sees it cannot get there and gives up early instead of
  // spending all its rounds before the sliding starts.
  std::printf("repair rounds with sliding: %d\n", report.rounds);
  EXPECT_LT(report.rounds, UntangleOptions{}.fixed_boundary_rounds);
  EXPECT_GT(report.min_scaled_jacobian, 0.0);
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (mesh.is_boundary_node(int(v))) EXPECT_LT(distance_to(bvh, mesh.nodes[v]), 1e-9) << "node " << v;
}

// Where no repair can succeed (boundary nodes of the top face thrown across each other,
// sliding off), a repaired part that ends worse than it began goes back: the untangler
// never hands on more inverted hexes than it was given.
TEST(Untangle, HopelessRepairNeverEndsWithMoreInvertedHexes) {
  for (const double throw_to : {0.6, 0.85, 0.95}) {
    const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
    HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 4, 4);
    label_boundary(mesh, box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1));
    for (int j = 1; j <= 3; ++j) {
      const int node = (4 * 5 + j) * 5 + 1;  // top face (0.25, j / 4, 1)
      mesh.nodes[size_t(node)] = Vec3(throw_to, 0.25 * j + 0.1 * (throw_to - 0.5), 1.0);
    }
    const TriangleBvh bvh(cube);
    UntangleOptions no_sliding;
    no_sliding.slide_boundary = false;
    const UntangleReport report = untangle_and_smooth(mesh, bvh, no_sliding);
    std::printf("thrown to %.2f: %zu inverted before, %zu after\n", throw_to, report.inverted_before,
                report.inverted_after);
    EXPECT_GT(report.inverted_before, 0u);
    EXPECT_LE(report.inverted_after, report.inverted_before) << "thrown to " << throw_to;
  }
}

namespace {

// A 4 x 4 x 4 block of the unit cube with three top-face nodes thrown across their neighbours,
// and options that hold every boundary node where it is: a fold no repair can undo.
HexMesh block_with_held_fold() {
  HexMesh thrown = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 4, 4);
  label_boundary(thrown, box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1));
  for (int j = 1; j <= 3; ++j) thrown.nodes[size_t((4 * 5 + j) * 5 + 1)] = Vec3(0.95, 0.25 * j + 0.045, 1.0);
  return thrown;
}
UntangleOptions holding_the_boundary() {
  UntangleOptions options;
  options.target_scaled_jacobian = 0;  // as the pipeline runs it
  options.held = [](size_t, const Vec3&) { return true; };
  return options;
}

}  // namespace

// A repair that cannot succeed gives way: with the thrown top-face nodes held where they
// are, no pass can undo the fold, so the first sliding pass that removes no inverted hex ends
// the repair (UntangleReport::stalled), where without the stall bound every pass and the
// repair towards the target run again on the same folds. The result is no worse for it.
TEST(Untangle, RepairThatStopsFallingStallsAndSaysSo) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  const HexMesh thrown = block_with_held_fold();
  const TriangleBvh bvh(cube);
  const UntangleOptions stalling = holding_the_boundary();
  UntangleOptions unbounded = stalling;
  unbounded.stall_work = 0;
  HexMesh a = thrown, b = thrown;
  const UntangleReport stalled = untangle_and_smooth(a, bvh, stalling);
  const UntangleReport endless = untangle_and_smooth(b, bvh, unbounded);
  std::printf("held fold: %zu -> %zu inverted in %d rounds (stall bound), %zu in %d rounds (none)\n",
              stalled.inverted_before, stalled.inverted_after, stalled.rounds, endless.inverted_after, endless.rounds);
  ASSERT_GT(endless.inverted_after, 0u) << "the fold must be beyond repair for the test to bite";
  EXPECT_TRUE(stalled.stalled);
  EXPECT_FALSE(endless.stalled);
  EXPECT_GT(stalled.stalled_after_seconds, 0.0);
  EXPECT_LT(stalled.rounds, endless.rounds);
  EXPECT_LE(stalled.inverted_after, stalled.inverted_before);
  EXPECT_EQ(stalled.inverted_after, endless.inverted_after);
}

// The stall bound counts work (hexes evaluated), not seconds: a run it stops stops at the same
// point every time, so its mesh is the same in every run, however busy the machine. Here the
// held fold keeps the inverted count from falling, and a small bound stops the repair part way
// through its rounds (fewer rounds than without the bound); two runs give identical nodes.
TEST(Untangle, StallBoundCountsWorkSoAStalledRunIsTheSameEveryTime) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  const HexMesh thrown = block_with_held_fold();
  const TriangleBvh bvh(cube);
  UntangleOptions bounded = holding_the_boundary();
  bounded.slide_boundary = false;  // only the interior repair, which the bound must stop
  bounded.stall_work = 20000;
  UntangleOptions unbounded = bounded;
  unbounded.stall_work = 0;
  HexMesh a = thrown, b = thrown, c = thrown;
  const UntangleReport first = untangle_and_smooth(a, bvh, bounded);
  const UntangleReport second = untangle_and_smooth(b, bvh, bounded);
  const UntangleReport endless = untangle_and_smooth(c, bvh, unbounded);
  std::printf("held fold, interior repair: %d rounds with the bound (%zu inverted after), %d without (%zu)\n",
              first.rounds, first.inverted_after, endless.rounds, endless.inverted_after);
  ASSERT_GT(endless.inverted_after, 0u) << "the fold must be beyond repair for the test to bite";
  EXPECT_TRUE(first.stalled);
  EXPECT_LT(first.rounds, endless.rounds);
  EXPECT_EQ(first.rounds, second.rounds);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t v = 0; v < a.nodes.size(); ++v) ASSERT_EQ(a.nodes[v], b.nodes[v]) << "node " << v;
}

// The repairs and the shape pass work where the mesh is poor, not everywhere: in a block
// that is smoothly distorted throughout (every hex fine, none a cube), one interior node
// pushed through a face is repaired without moving any node 8 or more hex layers away.
// The shape pass over the whole mesh (threshold 1) moves those nodes: the test bites.
TEST(Untangle, RepairOfOneNodeLeavesFarNodesAlone) {
  const int n = 14;
  const double h = 1.0 / n;
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), n, n, n);
  label_boundary(mesh, box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1));
  auto id = [&](int i, int j, int k) { return size_t((k * (n + 1) + j) * (n + 1) + i); };
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (!mesh.is_boundary_node(int(v))) {
      const Vec3 p = mesh.nodes[v];
      mesh.nodes[v] += 0.25 * h * Vec3(std::sin(2 * M_PI * p.y()), std::sin(2 * M_PI * p.z()), std::sin(2 * M_PI * p.x()));
    }
  const HexQuality distorted = measure_hex_quality(mesh);
  ASSERT_EQ(distorted.inverted, 0u);
  ASSERT_LT(distorted.shape_stats.avg, 0.99);  // most hexes are not optimal: they have room to move
  const size_t pushed = id(3, 3, 3);
  ASSERT_FALSE(mesh.is_boundary_node(int(pushed)));
  mesh.nodes[pushed] += h * Vec3(1.4, 1.2, 1.48);  // beyond the far faces of its 8 hexes
  const std::vector<Vec3> before = mesh.nodes;
  const TriangleBvh bvh(cube);

  auto far_nodes_moved = [&](const HexMesh& m) {
    size_t far = 0, moved = 0;
    for (int k = 0; k <= n; ++k)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
          if (std::max({std::abs(i - 3), std::abs(j - 3), std::abs(k - 3)}) >= 8) {
            ++far;
            if (m.nodes[id(i, j, k)] != before[id(i, j, k)]) ++moved;
          }
    EXPECT_GT(far, 1000u);
    return moved;
  };

  HexMesh local = mesh;
  const UntangleReport report = untangle_and_smooth(local, bvh);
  EXPECT_GT(report.inverted_before, 0u);
  EXPECT_EQ(report.inverted_after, 0u);
  EXPECT_EQ(measure_hex_quality(local).inverted, 0u);
  EXPECT_EQ(far_nodes_moved(local), 0u);

  UntangleOptions everywhere;
  everywhere.smoothing_shape_threshold = 1.0;
  HexMesh global = mesh;
  EXPECT_EQ(untangle_and_smooth(global, bvh, everywhere).inverted_after, 0u);
  EXPECT_GT(far_nodes_moved(global), 100u);
}

// The shape pass solves its pieces colour by colour, pieces of one colour on all threads at
// once. Pieces of one colour share no hex, so two runs give the same nodes bit for bit;
// the pass raises the mean shape and, being a barrier, inverts nothing.
TEST(Untangle, ShapePassInColouredPiecesIsDeterministic) {
  const TriSurface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 12);
  const TriangleBvh bvh(box);
  const HexMesh start = perturbed_block(box, 12, 0.2);
  const HexQuality before = measure_hex_quality(start);
  ASSERT_EQ(before.inverted, 0u);
  UntangleOptions options;
  options.smoothing_shape_threshold = 1.0;  // every interior node
  options.smoothing_part_nodes = 40;        // about 30 pieces, a few colours
  HexMesh first = start, second = start;
  const UntangleReport report = untangle_and_smooth(first, bvh, options);
  untangle_and_smooth(second, bvh, options);
  EXPECT_GE(report.rounds, 25);  // one round per piece at least
  for (size_t v = 0; v < first.nodes.size(); ++v) ASSERT_EQ(first.nodes[v], second.nodes[v]) << "node " << v;
  const HexQuality q = measure_hex_quality(first);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_GT(q.shape_stats.avg, before.shape_stats.avg + 0.02);
  for (size_t v = 0; v < first.nodes.size(); ++v)
    if (first.is_boundary_node(int(v))) EXPECT_EQ(first.nodes[v], start.nodes[v]) << "boundary node " << v << " moved";
}
