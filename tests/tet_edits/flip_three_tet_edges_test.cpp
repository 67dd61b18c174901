// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/flip_three_tet_edges.h>

#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tetrahedralize.h>
#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace dthex;
using namespace dthex::tet_fixtures;

// In the fixture only p-q has three tets around it (the other interior edge, s-r0, has
// four): one flip, the three tets (worst shape 0.6125) become r0 r1 r2 joined to p and to q
// (shape 0.9447 both).
TEST(FlipThreeTetEdges, TheOnlyThreeTetEdgeIsFlipped) {
  TetMesh m = edge_with_an_interior_ring_vertex();
  const double volume = total_volume(m);
  const FlipThreeTetEdgesReport report = flip_three_tet_edges(m);
  EXPECT_EQ(report.flips, 1u);
  EXPECT_EQ(report.tets_before, 7u);
  EXPECT_EQ(report.tets_after, 6u);
  ASSERT_EQ(m.tets.size(), 6u);
  std::set<std::set<int>> tets;
  for (const auto& t : m.tets) tets.insert(std::set<int>(t.begin(), t.end()));
  EXPECT_TRUE(tets.count({R0, R1, R2, P}));
  EXPECT_TRUE(tets.count({R0, R1, R2, Q}));
  expect_valid(m, volume);
}

// Refused when the new tets are below the asked fraction of the old worst (0.9447 / 0.6125 =
// 1.54), and when the new face would join three boundary vertices (r0 on the boundary).
TEST(FlipThreeTetEdges, RefusedWhenWorseOrWhenItMakesAFaceOfThreeBoundaryVertices) {
  FlipThreeTetEdgesOptions options;
  options.min_shape_ratio = 1.5;
  TetMesh m = edge_with_an_interior_ring_vertex();
  EXPECT_EQ(flip_three_tet_edges(m, options).flips, 1u);
  options.min_shape_ratio = 1.6;
  m = edge_with_an_interior_ring_vertex();
  const auto original = m.tets;
  EXPECT_EQ(flip_three_tet_edges(m, options).flips, 0u);
  EXPECT_EQ(m.tets, original);

  TetMesh all_boundary = edge_with_an_interior_ring_vertex(false);
  const auto before = all_boundary.tets;
  EXPECT_EQ(flip_three_tet_edges(all_boundary).flips, 0u);
  EXPECT_EQ(all_boundary.tets, before);
}

// The coarse bundled vertebra as the pipeline prepares it: the flips remove one tet each,
// leave a valid mesh with no interior edge or face between boundary vertices, and the worst
// tet shape does not fall.
TEST(FlipThreeTetEdges, CoarseVertebraLosesOneTetPerFlip) {
  TetMesh tets = coarse_vertebra_without_boundary_edges();
  ASSERT_EQ(bad_entities(tets).edges, 0u);
  const double volume = total_volume(tets);
  const std::vector<double> shapes_before = tet_shapes(tets);
  const size_t before = tets.tets.size();
  const FlipThreeTetEdgesReport report = flip_three_tet_edges(tets);
  EXPECT_GT(report.flips, 20u);
  EXPECT_EQ(tets.tets.size(), before - report.flips);
  expect_valid(tets, volume);
  EXPECT_EQ(bad_entities(tets).edges, 0u);
  EXPECT_EQ(bad_entities(tets).faces, 0u);
  const std::vector<double> shapes_after = tet_shapes(tets);
  EXPECT_GE(*std::min_element(shapes_after.begin(), shapes_after.end()),
            *std::min_element(shapes_before.begin(), shapes_before.end()));
}
