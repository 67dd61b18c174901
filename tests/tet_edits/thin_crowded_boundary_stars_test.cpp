// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/thin_crowded_boundary_stars.h>

#include "tet_edit_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace dthex;
using namespace dthex::tet_fixtures;

namespace {

// Solid angle at t[0] of tet t by its spherical excess (the sum of the three dihedral angles
// at the edges through t[0], less pi): another formula than the stage's.
double solid_angle_by_excess(const TetMesh& m, const std::array<int, 4>& t) {
  const Vec3 a = m.points[size_t(t[0])];
  const Vec3 e[3] = {m.points[size_t(t[1])] - a, m.points[size_t(t[2])] - a, m.points[size_t(t[3])] - a};
  double sum = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec3& x = e[i];
    const Vec3& y = e[(i + 1) % 3];
    const Vec3& z = e[(i + 2) % 3];
    // Dihedral angle at edge x between the faces (x, y) and (x, z).
    const Vec3 ny = x.cross(y).normalized(), nz = x.cross(z).normalized();
    sum += std::acos(std::clamp(ny.dot(nz), -1.0, 1.0));
  }
  return sum - M_PI;
}

// The lowest corner bound over the boundary vertices, and how many are below `target`.
std::pair<double, size_t> lowest_bound(const TetMesh& m, double target) {
  std::vector<char> on_boundary(m.points.size(), 0);
  for (const auto& f : m.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  std::vector<double> angle(m.points.size(), 0);
  std::vector<int> tets(m.points.size(), 0);
  for (const auto& t : m.tets)
    for (int i = 0; i < 4; ++i) {
      std::array<int, 4> at = t;
      std::swap(at[0], at[size_t(i)]);
      angle[size_t(t[size_t(i)])] += solid_angle_by_excess(m, at);
      ++tets[size_t(t[size_t(i)])];
    }
  double lowest = 1;
  size_t below = 0;
  for (size_t v = 0; v < m.points.size(); ++v)
    if (on_boundary[v]) {
      const double b = corner_scaled_jacobian_bound(angle[v] / tets[v]);
      lowest = std::min(lowest, b);
      below += b < target;
    }
  return {lowest, below};
}

}  // namespace

// Known corners: the cube's (pi / 2 sr) is perfect, the regular tet's (0.5513 sr, edges 60
// degrees apart) has scaled Jacobian sqrt(1/2), and the even split of the sphere among 60
// corners (docs/METHOD.md: 0.35) and 28 (0.62).
TEST(ThinCrowdedBoundaryStars, CornerBoundOfKnownCorners) {
  EXPECT_NEAR(corner_scaled_jacobian_bound(M_PI / 2), 1.0, 1e-9);
  EXPECT_NEAR(corner_scaled_jacobian_bound(2 * M_PI), 1.0, 1e-9);
  const double regular_tet_corner = 3 * std::acos(1.0 / 3.0) - M_PI;  // 0.5513 sr
  EXPECT_NEAR(corner_scaled_jacobian_bound(regular_tet_corner), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(corner_scaled_jacobian_bound(4 * M_PI / 60), 0.35, 0.01);
  EXPECT_NEAR(corner_scaled_jacobian_bound(4 * M_PI / 28), 0.62, 0.01);
  EXPECT_EQ(corner_scaled_jacobian_bound(0), 0.0);
  // Rising with the solid angle.
  EXPECT_LT(corner_scaled_jacobian_bound(0.2), corner_scaled_jacobian_bound(0.3));
}

// The coarse vertebra as the pipeline hands it on: at a target above what its boundary
// vertices reach, edges go by both kinds of change, the lowest bound (measured here by another
// solid-angle formula) rises and fewer vertices are below the target, while the mesh stays a
// valid tet mesh of the same domain with the same boundary faces and points, and no interior
// edge or face of boundary vertices appears.
TEST(ThinCrowdedBoundaryStars, RaisesTheLowestCornerBoundAndKeepsTheMeshValid) {
  TetMesh m = coarse_vertebra_before_worst_tet_edits();
  const TetMesh before = m;
  const double volume = total_volume(m);
  ThinCrowdedBoundaryStarsOptions options;
  options.target_bound = 0.55;
  const auto [lowest_before, below_before] = lowest_bound(m, options.target_bound);
  ASSERT_GT(below_before, 0u);
  const ThinCrowdedBoundaryStarsReport report = thin_crowded_boundary_stars(m, options);
  const auto [lowest_after, below_after] = lowest_bound(m, options.target_bound);
  EXPECT_NEAR(report.lowest_bound_before, lowest_before, 1e-9);
  EXPECT_NEAR(report.lowest_bound_after, lowest_after, 1e-9);
  EXPECT_EQ(report.crowded_before, below_before);
  EXPECT_EQ(report.crowded_after, below_after);
  EXPECT_GT(report.edges_removed, 0u);
  EXPECT_GT(report.merged, 0u);
  EXPECT_LT(below_after, below_before);
  EXPECT_GE(lowest_after, lowest_before);
  EXPECT_EQ(report.tets_before, before.tets.size());
  EXPECT_EQ(report.tets_after, m.tets.size());
  // Merged interior points are dropped; the boundary's points and faces stay as they were.
  EXPECT_EQ(m.points.size(), before.points.size() - report.merged);
  EXPECT_EQ(m.boundary_faces, before.boundary_faces);
  for (const auto& f : m.boundary_faces)
    for (int v : f) EXPECT_EQ(m.points[size_t(v)], before.points[size_t(v)]);
  const BadEntities bad_before = bad_entities(before), bad_after = bad_entities(m);
  EXPECT_EQ(bad_after.edges, bad_before.edges);
  EXPECT_EQ(bad_after.faces, bad_before.faces);
  expect_valid(m, volume);
}

// Below every vertex's bound nothing is crowded, and nothing changes.
TEST(ThinCrowdedBoundaryStars, LeavesAMeshWithNoCrowdedVertexAsItWas) {
  TetMesh m = coarse_vertebra_before_worst_tet_edits();
  const TetMesh before = m;
  ThinCrowdedBoundaryStarsOptions options;
  options.target_bound = lowest_bound(m, 1).first - 1e-6;
  const ThinCrowdedBoundaryStarsReport report = thin_crowded_boundary_stars(m, options);
  EXPECT_EQ(report.crowded_before, 0u);
  EXPECT_EQ(report.edges_removed, 0u);
  EXPECT_EQ(m.tets, before.tets);
}

// The merges thin where edge removals alone cannot: without them the same target leaves more
// vertices crowded.
TEST(ThinCrowdedBoundaryStars, MergesThinWhereEdgeRemovalsCannot) {
  ThinCrowdedBoundaryStarsOptions options;
  options.target_bound = 0.55;
  TetMesh with = coarse_vertebra_before_worst_tet_edits(), without = with;
  const ThinCrowdedBoundaryStarsReport merged = thin_crowded_boundary_stars(with, options);
  options.merge_interior_neighbours = false;
  const ThinCrowdedBoundaryStarsReport removals_only = thin_crowded_boundary_stars(without, options);
  EXPECT_EQ(removals_only.merged, 0u);
  EXPECT_GT(merged.merged, 0u);
  EXPECT_LT(merged.crowded_after, removals_only.crowded_after);
  EXPECT_EQ(with.points.size(), without.points.size() - merged.merged);
}
