// SPDX-License-Identifier: MIT
#include <dthex/tets/relax_interior_points.h>

#include <dthex/mesh/quality.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tets/split_surface_tets.h>
#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

using namespace dthex;
using namespace dthex::tet_fixtures;

namespace {

// A regular tetrahedron A B C D coned from one interior point u (4 tets, u = point 4).
TetMesh regular_tetrahedron_coned_from(const Vec3& u) {
  TetMesh m;
  m.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}, u};
  const int A = 0, B = 1, C = 2, D = 3, U = 4;
  add_positive(m, U, B, C, D);
  add_positive(m, U, A, C, D);
  add_positive(m, U, A, B, D);
  add_positive(m, U, A, B, C);
  m.boundary_faces = {{B, C, D}, {A, D, C}, {A, B, D}, {A, C, B}};
  m.boundary_face_source = {0, 1, 2, 3};
  return m;
}

double worst_tet(const TetMesh& m) {
  const auto shapes = tet_shapes(m);
  return *std::min_element(shapes.begin(), shapes.end());
}

double inverse_shape_sum(const TetMesh& m) {
  double sum = 0;
  for (double s : tet_shapes(m)) sum += 1 / s;
  return sum;
}

}  // namespace

// The interior point just above the boundary face B C D (the flat tet THex would turn into
// flat hexes) goes back to the centre, where by symmetry the worst of the four tets is best.
TEST(RelaxInteriorPoints, PointJustAboveABoundaryFaceGoesToTheCentre) {
  const Vec3 face_centre = (Vec3(1, -1, -1) + Vec3(-1, 1, -1) + Vec3(-1, -1, 1)) / 3.0;
  const Vec3 towards_a = Vec3(1, 1, 1) - face_centre;
  TetMesh m = regular_tetrahedron_coned_from(face_centre + 0.002 * towards_a + Vec3(0.05, -0.02, 0.01));
  const TetMesh before = m;
  const double centred = worst_tet(regular_tetrahedron_coned_from(Vec3::Zero()));
  ASSERT_LT(worst_tet(m), 0.1);

  const RelaxInteriorPointsReport report = relax_interior_points(m);

  EXPECT_EQ(report.moved, 1u);
  EXPECT_NEAR(report.worst_before, worst_tet(before), 1e-12);
  EXPECT_NEAR(report.worst_after, worst_tet(m), 1e-12);
  EXPECT_GT(report.worst_after, 0.95 * centred);
  EXPECT_LT(m.points[4].norm(), 0.05);  // the centre; the corners are sqrt(3) from it
  for (int v = 0; v < 4; ++v) EXPECT_EQ(m.points[size_t(v)], before.points[size_t(v)]);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  expect_valid(m, total_volume(before));
}

// A point already where its star is best does not wander (ties and round-off are no gain).
TEST(RelaxInteriorPoints, CentredPointStays) {
  TetMesh m = regular_tetrahedron_coned_from(Vec3::Zero());
  RelaxInteriorPointsOptions options;
  options.relax_below = 1;
  options.max_min_below = 1;
  const RelaxInteriorPointsReport report = relax_interior_points(m, options);
  EXPECT_EQ(report.moved, 0u);
  EXPECT_EQ(m.points[4], Vec3::Zero());
}

// Points whose tets are all better than the thresholds are left exactly where they are.
TEST(RelaxInteriorPoints, GoodStarsAreLeftAlone) {
  TetMesh m = regular_tetrahedron_coned_from(Vec3(0.1, 0.05, -0.05));
  const double worst = worst_tet(m);
  ASSERT_GT(worst, 0.1);
  RelaxInteriorPointsOptions options;
  options.relax_below = worst;  // strictly below: this point is not taken
  options.max_min_below = worst;
  const Vec3 at = m.points[4];
  EXPECT_EQ(relax_interior_points(m, options).moved, 0u);
  EXPECT_EQ(m.points[4], at);
}

// On the coarse vertebra as THex would get it, with every interior point relaxed: the mesh
// stays a valid triangulation of the same domain with the same tets and boundary, boundary
// points do not move, the worst tet does not fall, and the first relaxation (alone) lowers
// the sum of the inverse shapes, which each of its moves lowers around the moved point.
TEST(RelaxInteriorPoints, CoarseVertebraKeepsItsBoundaryAndGetsBetter) {
  TetMesh m = coarse_vertebra_before_worst_tet_edits();
  const TetMesh before = m;
  std::vector<char> on_boundary(m.points.size(), 0);
  for (const auto& f : m.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;

  RelaxInteriorPointsOptions options;
  options.relax_below = 1;
  options.max_min_below = 0;
  const RelaxInteriorPointsReport report = relax_interior_points(m, options);

  EXPECT_GT(report.moved, 10u);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  EXPECT_EQ(m.boundary_face_source, before.boundary_face_source);
  ASSERT_EQ(m.points.size(), before.points.size());
  size_t moved = 0;
  for (size_t v = 0; v < m.points.size(); ++v) {
    if (on_boundary[v]) EXPECT_EQ(m.points[v], before.points[v]);
    moved += m.points[v] != before.points[v];
  }
  EXPECT_EQ(moved, report.moved);
  expect_valid(m, total_volume(before));
  EXPECT_GE(worst_tet(m), worst_tet(before));
  EXPECT_LT(inverse_shape_sum(m), inverse_shape_sum(before));

  // The second relaxation raises the worst tet further, or keeps it.
  TetMesh again = m;
  options.relax_below = 0;
  options.max_min_below = 1;
  relax_interior_points(again, options);
  expect_valid(again, total_volume(before));
  EXPECT_GE(worst_tet(again), worst_tet(m));
}
