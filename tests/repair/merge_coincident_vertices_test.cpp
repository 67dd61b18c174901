// SPDX-License-Identifier: MIT
#include <dthex/repair/merge_coincident_vertices.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include <limits>

using dthex::MergeCoincidentVerticesReport;
using dthex::TriSurface;
using dthex::Vec3;
using dthex::merge_coincident_vertices;

namespace {

//! The unit cube as a soup: each of its 12 triangles with its own three vertices.
TriSurface cube_soup() {
  Vec3 corner[8];
  for (int i = 0; i < 8; ++i) corner[i] = Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  TriSurface s;
  for (const auto& q : quads)
    for (const std::array<int, 3>& tri : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      const int base = int(s.points.size());
      for (int v : tri) s.points.push_back(corner[v]);
      s.triangles.push_back({base, base + 1, base + 2});
    }
  return s;
}

}  // namespace

TEST(MergeCoincidentVertices, ASoupBecomesTheClosedCube) {
  TriSurface s = cube_soup();
  TriSurface unmerged = s;
  EXPECT_THROW(dthex::verify_surface(unmerged, "soup"), dthex::InputError);  // open before
  const MergeCoincidentVerticesReport report = merge_coincident_vertices(s);
  EXPECT_EQ(report.vertices_merged, 36u - 8u);
  ASSERT_EQ(report.first_merged.size(), 5u);
  // Vertex 0 is corner 0 and vertex 3 its first copy (the second triangle's first corner).
  EXPECT_EQ(report.first_merged[0], 3);
  EXPECT_EQ(report.first_kept[0], 0);
  EXPECT_EQ(report.first_places[0], Vec3(0, 0, 0));
  EXPECT_EQ(s.points.size(), 36u);  // nothing renumbered: the copies are left unused
  const dthex::SurfaceStats stats = dthex::verify_surface(s, "merged soup");
  EXPECT_EQ(stats.vertices, 8u);
  EXPECT_EQ(stats.unreferenced_vertices, 28u);
  EXPECT_NEAR(stats.volume, 1.0, 1e-12);
}

TEST(MergeCoincidentVertices, SignedZerosMergeNonFiniteAndOutOfRangeDoNot) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  TriSurface s;
  s.points = {Vec3(0, 1, 2), Vec3(-0.0, 1, 2), Vec3(nan, 0, 0), Vec3(nan, 0, 0), Vec3(0, 1, 2.0000000000000004)};
  s.triangles = {{1, 2, 3}, {4, 0, 7}};
  const MergeCoincidentVerticesReport report = merge_coincident_vertices(s);
  EXPECT_EQ(report.vertices_merged, 1u);
  EXPECT_EQ(s.triangles, (std::vector<std::array<int, 3>>{{0, 2, 3}, {4, 0, 7}}));
}

TEST(MergeCoincidentVertices, NothingToMergeChangesNothing) {
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  s.triangles = {{0, 1, 2}};
  const TriSurface before = s;
  EXPECT_EQ(merge_coincident_vertices(s).vertices_merged, 0u);
  EXPECT_EQ(s.triangles, before.triangles);
}
