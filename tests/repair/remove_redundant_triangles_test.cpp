// SPDX-License-Identifier: MIT
#include <dthex/repair/remove_redundant_triangles.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include "repair_fixtures.h"

using dthex::RemoveRedundantTrianglesReport;
using dthex::TriSurface;
using dthex::testing::unit_cube;
using dthex::Vec3;
using dthex::remove_redundant_triangles;

TEST(RemoveRedundantTriangles, DuplicatesAndCollapsedOnesGoWhereTheCubeStaysClosed) {
  const TriSurface original = unit_cube();
  TriSurface s = original;
  s.triangles.insert(s.triangles.begin() + 3, std::array<int, 3>{0, 0, 5});  // collapsed, at id 3
  s.triangles.push_back({s.triangles[5][2], s.triangles[5][1], s.triangles[5][0]});  // triangle 5 reversed
  s.triangles.push_back(s.triangles[7]);                              // triangle 7 again
  const RemoveRedundantTrianglesReport report = remove_redundant_triangles(s);
  EXPECT_EQ(report.collapsed_removed, 1u);
  EXPECT_EQ(report.duplicates_removed, 2u);
  EXPECT_EQ(report.left_in_place, 0u);
  EXPECT_EQ(report.first_removed, (std::vector<int>{3, 13, 14}));
  EXPECT_EQ(s.triangles, original.triangles);  // the lower id of each pair is kept, in order
  EXPECT_TRUE(dthex::is_closed_manifold(s.triangles, s.points.size()));
}

TEST(RemoveRedundantTriangles, AFaceTwoBodiesShareIsLeftForVerification) {
  // Two tetrahedra glued on face 0-1-2, each written whole: removing one copy of the shared
  // face leaves its edges on three triangles, so nothing is removed.
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 1, 2}, {0, 4, 1}, {1, 4, 2}, {2, 4, 0}};
  const TriSurface before = s;
  const RemoveRedundantTrianglesReport report = remove_redundant_triangles(s);
  EXPECT_EQ(report.duplicates_removed, 0u);
  EXPECT_EQ(report.left_in_place, 1u);
  EXPECT_EQ(s.triangles, before.triangles);
  EXPECT_THROW(dthex::verify_surface(s, "glued"), dthex::InputError);
}

TEST(RemoveRedundantTriangles, ZeroAreaTrianglesOnDistinctVerticesAreNotRemoved) {
  // Two back-to-back slivers on edge 0-1 of the cube: not collapsed (three distinct
  // vertices), and one is a duplicate of the other, but removing it would leave the other's
  // edges open, so both stay for verification to refuse as degenerate.
  TriSurface s = unit_cube();
  s.points.push_back(Vec3(0.5, 0, 0));
  s.triangles.push_back({0, 1, 8});
  s.triangles.push_back({1, 0, 8});
  const TriSurface before = s;
  const RemoveRedundantTrianglesReport report = remove_redundant_triangles(s);
  EXPECT_EQ(report.collapsed_removed + report.duplicates_removed, 0u);
  EXPECT_EQ(report.left_in_place, 1u);
  EXPECT_EQ(s.triangles, before.triangles);
}

TEST(RemoveRedundantTriangles, ClosedManifoldCheck) {
  const TriSurface c = unit_cube();
  EXPECT_TRUE(dthex::is_closed_manifold(c.triangles, c.points.size()));
  auto open = c.triangles;
  open.pop_back();
  EXPECT_FALSE(dthex::is_closed_manifold(open, c.points.size()));
  // Two cubes sharing corner 0 only: every edge on two triangles, two fans at vertex 0.
  TriSurface two = c;
  for (int i = 1; i < 8; ++i) two.points.push_back(-two.points[size_t(i)]);
  for (auto t : c.triangles) {
    for (int& v : t) v = v == 0 ? 0 : v + 7;
    two.triangles.push_back(t);
  }
  EXPECT_FALSE(dthex::is_closed_manifold(two.triangles, two.points.size()));
}
