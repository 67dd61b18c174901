// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/collapse_interior_vertices.h>

#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tetrahedralize.h>
#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace dthex;
using namespace dthex::tet_fixtures;

namespace {

// A regular tetrahedron A B C D coned from an interior point u, with the tet u A B C split
// 1-4 at a point v inside it: 7 tets, two interior points.
TetMesh tetrahedron_with_two_interior_points() {
  TetMesh m;
  m.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}, {0, 0, 0}, {0.3, 0.3, -0.1}};
  const int A = 0, B = 1, C = 2, D = 3, U = 4, V = 5;
  add_positive(m, U, B, C, D);
  add_positive(m, U, A, C, D);
  add_positive(m, U, A, B, D);
  add_positive(m, V, A, B, C);
  add_positive(m, V, U, B, C);
  add_positive(m, V, A, U, C);
  add_positive(m, V, A, B, U);
  m.boundary_faces = {{B, C, D}, {A, D, C}, {A, B, D}, {A, C, B}};
  m.boundary_face_source = {0, 1, 2, 3};
  return m;
}

}  // namespace

// Each merge keeps the local worst shape, so both interior points go and the regular tet is
// left: one tet, the four corners renumbered 0-3, the boundary faces still its faces.
TEST(CollapseInteriorVertices, TetrahedronWithTwoInteriorPointsBecomesOneTet) {
  TetMesh m = tetrahedron_with_two_interior_points();
  const double volume = total_volume(m);
  const CollapseInteriorVerticesReport report = collapse_interior_vertices(m);
  EXPECT_EQ(report.collapsed, 2u);
  EXPECT_EQ(report.tets_before, 7u);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.points.size(), 4u);
  std::array<int, 4> t = m.tets[0];
  std::sort(t.begin(), t.end());
  EXPECT_EQ(t, (std::array<int, 4>{0, 1, 2, 3}));
  expect_valid(m, volume);
  EXPECT_EQ(m.boundary_face_source, (std::vector<int>{0, 1, 2, 3}));
}

// With a kept neighbour allowed no more than 3 tets (a boundary corner 1), neither point can go,
// where without the bound both do (the test above): merging v into u leaves u in 4 tets, u into
// v leaves v in 4, and either into a corner leaves the corner in more than 1.
TEST(CollapseInteriorVertices, NoNeighbourIsCrowdedPastTheBound) {
  TetMesh m = tetrahedron_with_two_interior_points();
  const double volume = total_volume(m);
  CollapseInteriorVerticesOptions options;
  options.max_tets_at_kept_vertex = 3;
  const CollapseInteriorVerticesReport report = collapse_interior_vertices(m, options);
  EXPECT_EQ(report.collapsed, 0u);
  EXPECT_EQ(m.tets.size(), 7u);
  EXPECT_EQ(m.points.size(), 6u);
  expect_valid(m, volume);
}

// Asked for new tets ten times better than the worst they replace, nothing is merged; and
// where every neighbour is a boundary vertex (the fixture's r0) every merge would make an
// interior face of three boundary vertices or an inverted tet.
TEST(CollapseInteriorVertices, RefusedWhenWorseOrWhenItJoinsBoundaryVertices) {
  TetMesh m = tetrahedron_with_two_interior_points();
  CollapseInteriorVerticesOptions strict;
  strict.min_shape_ratio = 10;
  const auto original = m.tets;
  EXPECT_EQ(collapse_interior_vertices(m, strict).collapsed, 0u);
  EXPECT_EQ(m.tets, original);
  EXPECT_EQ(m.points.size(), 6u);

  TetMesh ring = edge_with_an_interior_ring_vertex();
  const auto before = ring.tets;
  EXPECT_EQ(collapse_interior_vertices(ring).collapsed, 0u);
  EXPECT_EQ(ring.tets, before);
}

// The coarse bundled vertebra as the pipeline prepares it: interior points go, one point less
// each, every point left is used, the mesh is valid with no interior edge or face between
// boundary vertices, and the worst tet shape does not fall.
TEST(CollapseInteriorVertices, CoarseVertebraKeepsItsWorstShape) {
  TetMesh tets = coarse_vertebra_without_boundary_edges();
  flip_three_tet_edges(tets);
  const double volume = total_volume(tets);
  const std::vector<double> shapes_before = tet_shapes(tets);
  const size_t points_before = tets.points.size(), tets_before = tets.tets.size();
  const CollapseInteriorVerticesReport report = collapse_interior_vertices(tets);
  EXPECT_GT(report.collapsed, 10u);
  EXPECT_EQ(tets.points.size(), points_before - report.collapsed);
  EXPECT_LT(tets.tets.size(), tets_before);
  std::vector<char> used(tets.points.size(), 0);
  for (const auto& t : tets.tets)
    for (int v : t) used[size_t(v)] = 1;
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](char u) { return u != 0; }));
  expect_valid(tets, volume);
  EXPECT_EQ(bad_entities(tets).edges, 0u);
  EXPECT_EQ(bad_entities(tets).faces, 0u);
  const std::vector<double> shapes_after = tet_shapes(tets);
  EXPECT_GE(*std::min_element(shapes_after.begin(), shapes_after.end()),
            *std::min_element(shapes_before.begin(), shapes_before.end()));
}
