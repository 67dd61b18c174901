// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/flip_worst_tets.h>

#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tets/split_surface_tets.h>
#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace dthex;
using namespace dthex::tet_fixtures;

namespace {

double worst_tet(const TetMesh& m) {
  const auto shapes = tet_shapes(m);
  return *std::min_element(shapes.begin(), shapes.end());
}

bool has_edge(const TetMesh& m, int a, int b) {
  return std::any_of(m.tets.begin(), m.tets.end(), [&](const std::array<int, 4>& t) {
    return std::count(t.begin(), t.end(), a) && std::count(t.begin(), t.end(), b);
  });
}

// An equilateral triangle a b c (circumradius 1) with d just above it and e just below:
// the two flat tets on face a b c (shape 0.26) are worse than the three around d e (0.33).
// With e_interior, e is inside a pyramid from a b c down to f, coned from e, so d e may
// be an edge; without, the mesh is the two tets alone and d e would join two boundary
// vertices.
enum { A = 0, B, C, D, E, F };
TetMesh flat_pair_on_a_face(bool e_interior) {
  TetMesh m;
  m.points = {{1, 0, 0}, {-0.5, 0.8660254, 0}, {-0.5, -0.8660254, 0}, {0, 0, 0.1}, {0, 0, -0.1}, {0, 0, -1}};
  add_positive(m, A, B, C, D);
  add_positive(m, A, B, C, E);
  m.boundary_faces = {{A, B, D}, {B, C, D}, {C, A, D}};
  if (e_interior) {
    add_positive(m, E, A, B, F);
    add_positive(m, E, B, C, F);
    add_positive(m, E, C, A, F);
    m.boundary_faces.insert(m.boundary_faces.end(), {{A, F, B}, {B, F, C}, {C, F, A}});
  } else {
    m.points.pop_back();
    m.boundary_faces.insert(m.boundary_faces.end(), {{A, E, B}, {B, E, C}, {C, E, A}});
  }
  m.boundary_face_source.resize(m.boundary_faces.size(), 0);
  return m;
}

}  // namespace

TEST(FlipWorstTets, FlatPairBecomesThreeTetsAroundTheNewEdge) {
  TetMesh m = flat_pair_on_a_face(true);
  const TetMesh before = m;
  expect_valid(m, total_volume(before));  // the fixture itself
  FlipWorstTetsOptions options;
  options.below = 0.3;
  const FlipWorstTetsReport report = flip_worst_tets(m, options);
  EXPECT_EQ(report.face_flips, 1u);
  EXPECT_EQ(report.edge_removals, 0u);
  EXPECT_EQ(m.tets.size(), before.tets.size() + 1);
  EXPECT_TRUE(has_edge(m, D, E));
  EXPECT_NEAR(report.worst_before, worst_tet(before), 1e-12);
  EXPECT_NEAR(report.worst_after, worst_tet(m), 1e-12);
  EXPECT_GT(report.worst_after, report.worst_before + 0.05);
  EXPECT_EQ(m.points, before.points);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  expect_valid(m, total_volume(before));
}

// The same flip would join d and e, both on the boundary: not taken (split_surface_tets'
// rule), and nothing else improves, so the mesh stays as it is.
TEST(FlipWorstTets, NoNewEdgeBetweenTwoBoundaryVertices) {
  TetMesh m = flat_pair_on_a_face(false);
  const TetMesh before = m;
  FlipWorstTetsOptions options;
  options.below = 1;
  const FlipWorstTetsReport report = flip_worst_tets(m, options);
  EXPECT_EQ(report.face_flips + report.edge_removals, 0u);
  EXPECT_EQ(m.tets, before.tets);
}

// Three tets around a long interior edge p q whose ring is wide: their worst (0.34) is below
// the two tets of the 3-2 flip (0.87), so the edge goes.
TEST(FlipWorstTets, LongEdgeWithThreeTetsIsRemoved) {
  TetMesh m = edge_with_an_interior_ring_vertex();
  for (int v : {P, Q}) m.points[size_t(v)].z() *= 2;  // p q from length 2 to 4
  const TetMesh before = m;
  expect_valid(m, total_volume(before));
  const double around_pq = [&] {
    double worst = 1;
    for (const auto& t : m.tets)
      if (std::count(t.begin(), t.end(), P) && std::count(t.begin(), t.end(), Q))
        worst = std::min(worst, tet_shape(m.points[size_t(t[0])], m.points[size_t(t[1])], m.points[size_t(t[2])],
                                          m.points[size_t(t[3])]));
    return worst;
  }();
  FlipWorstTetsOptions options;
  options.below = 0.5;
  ASSERT_LT(around_pq, options.below);
  const FlipWorstTetsReport report = flip_worst_tets(m, options);
  EXPECT_GE(report.edge_removals, 1u);
  EXPECT_FALSE(has_edge(m, P, Q));
  EXPECT_GE(report.worst_after, report.worst_before);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  expect_valid(m, total_volume(before));
}

// On the coarse vertebra as THex would get it, flipping around every tet below 0.4: the same
// domain, boundary faces and points, still no interior edge or face of boundary vertices
// only, and the worst tet does not fall.
TEST(FlipWorstTets, CoarseVertebraKeepsItsBoundaryAndTheRule) {
  TetMesh m = coarse_vertebra_before_worst_tet_edits();
  const TetMesh before = m;
  ASSERT_EQ(bad_entities(m).edges + bad_entities(m).faces, 0u);
  FlipWorstTetsOptions options;
  options.below = 0.4;
  const FlipWorstTetsReport report = flip_worst_tets(m, options);
  EXPECT_GT(report.edge_removals + report.face_flips, 0u);
  EXPECT_EQ(m.points, before.points);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  EXPECT_EQ(m.boundary_face_source, before.boundary_face_source);
  expect_valid(m, total_volume(before));
  const BadEntities bad = bad_entities(m);
  EXPECT_EQ(bad.edges, 0u);
  EXPECT_EQ(bad.faces, 0u);
  EXPECT_GE(worst_tet(m), worst_tet(before));
}
