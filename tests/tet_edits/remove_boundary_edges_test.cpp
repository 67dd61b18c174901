// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/remove_boundary_edges.h>

#include <dthex/hexes/node_count.h>
#include <dthex/io/read_surface.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tetrahedralize.h>
#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <set>

using namespace dthex;
using namespace dthex::tet_fixtures;

// The 3-2 flip: the three tets around p-q become r0 r1 r2 joined to p and to q. No point is
// added, and the result has 6 tets where the midpoint split gives 10.
TEST(RemoveBoundaryEdges, ThreeTetsAroundAnEdgeBecomeTwo) {
  TetMesh m = edge_with_an_interior_ring_vertex();
  const double volume = total_volume(m);
  ASSERT_EQ(bad_entities(m).edges, 1u);
  const RemoveBoundaryEdgesReport report = remove_boundary_edges(m);
  EXPECT_EQ(report.candidates, 1u);
  EXPECT_EQ(report.removed, 1u);
  EXPECT_EQ(report.split, 0u);
  EXPECT_EQ(m.points.size(), 6u);
  ASSERT_EQ(m.tets.size(), 6u);
  std::set<std::set<int>> tets;
  for (const auto& t : m.tets) tets.insert(std::set<int>(t.begin(), t.end()));
  EXPECT_TRUE(tets.count({R0, R1, R2, P}));
  EXPECT_TRUE(tets.count({R0, R1, R2, Q}));
  expect_valid(m, volume);
  EXPECT_EQ(bad_entities(m).edges, 0u);
  EXPECT_EQ(bad_entities(m).faces, 0u);

  TetMesh split = edge_with_an_interior_ring_vertex();
  split_surface_tets(split);
  EXPECT_EQ(split.tets.size(), 10u);
  EXPECT_EQ(bad_entities(split).edges, 0u);
}

// With r0 on the boundary too, the flip's face r0 r1 r2 would be an interior face of three
// boundary vertices: no flip. Without the fallback nothing changes; with it the edge is split.
TEST(RemoveBoundaryEdges, NoFlipMakesAFaceOfThreeBoundaryVertices) {
  TetMesh m = edge_with_an_interior_ring_vertex(false);
  const double volume = total_volume(m);
  const auto original = m.tets;
  RemoveBoundaryEdgesOptions no_split;
  no_split.split_when_stuck = false;
  const RemoveBoundaryEdgesReport report = remove_boundary_edges(m, no_split);
  EXPECT_EQ(report.candidates, 1u);
  EXPECT_EQ(report.removed, 0u);
  EXPECT_EQ(m.tets, original);

  const RemoveBoundaryEdgesReport with_split = remove_boundary_edges(m);
  EXPECT_EQ(with_split.removed, 0u);
  EXPECT_EQ(with_split.split, 1u);
  EXPECT_EQ(m.tets.size(), 6u);
  EXPECT_EQ(m.points.size(), 6u);
  expect_valid(m, volume);
  EXPECT_EQ(bad_entities(m).edges, 0u);
}

// The flip's tets here have shape 0.9447 and the midpoint split's worst 0.6364 (Verdict tet
// shape): the flip is taken when it is at least min_shape_ratio times the split's worst and
// at least min_shape, and refused otherwise.
TEST(RemoveBoundaryEdges, FlipIsJudgedAgainstTheSplitsWorstTet) {
  RemoveBoundaryEdgesOptions options;
  options.split_when_stuck = false;
  auto removed_with = [&](double ratio, double floor) {
    TetMesh m = edge_with_an_interior_ring_vertex();
    options.min_shape_ratio = ratio;
    options.min_shape = floor;
    return remove_boundary_edges(m, options).removed;
  };
  EXPECT_EQ(removed_with(1.4, 0), 1u);    // 0.891 needed
  EXPECT_EQ(removed_with(1.5, 0), 0u);    // 0.955 needed
  EXPECT_EQ(removed_with(0, 0.94), 1u);
  EXPECT_EQ(removed_with(0, 0.95), 0u);
}

// The coarse bundled liver and vertebra at the default options: cones, flips and splits
// leave no interior edge or face between boundary vertices and a valid mesh, with fewer tets
// and fewer diced THex nodes than cones and midpoint splits alone.
TEST(RemoveBoundaryEdges, CoarseBundledMeshesGetFewerTetsThanSplits) {
  for (const std::string name : {"liver.off", "vertebra_L1.off"}) {
    SCOPED_TRACE(name);
    TriSurface coarse = coarsen(read_surface(std::string(DTHEX_SOURCE_DIR "/meshes/") + name)).surface;
    verify_surface(coarse, name);
    const TetMesh tets = tetrahedralize(coarse);
    const double volume = total_volume(tets);
    TetMesh split_only = tets;
    split_surface_tets(split_only);
    TetMesh flipped = tets;
    cone_edge_clusters(flipped);
    const RemoveBoundaryEdgesReport report = remove_boundary_edges(flipped);
    EXPECT_GT(report.removed, 0u);
    split_surface_tets(flipped);
    expect_valid(flipped, volume);
    EXPECT_EQ(bad_entities(flipped).edges, 0u);
    EXPECT_EQ(bad_entities(flipped).faces, 0u);
    EXPECT_LT(flipped.tets.size(), split_only.tets.size());
    EXPECT_LT(diced_thex_nodes(count_tet_entities(flipped), 2), diced_thex_nodes(count_tet_entities(split_only), 2));
  }
}
