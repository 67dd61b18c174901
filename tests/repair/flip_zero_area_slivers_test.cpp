// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/repair/flip_zero_area_slivers.h>

#include <dthex/mesh/triangle_crossing.h>
#include <dthex/repair/remove_redundant_triangles.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include "repair_fixtures.h"

#include <string>
#include <tuple>
#include <vector>

using dthex::FlipZeroAreaSliversReport;
using dthex::InputError;
using dthex::TriSurface;
using dthex::testing::unit_cube;
using dthex::Vec3;
using dthex::flip_zero_area_slivers;

namespace {


double area(const TriSurface& s) {
  double sum = 0;
  for (const auto& t : s.triangles)
    sum += 0.5 * (s.points[size_t(t[1])] - s.points[size_t(t[0])]).cross(s.points[size_t(t[2])] - s.points[size_t(t[0])]).norm();
  return sum;
}

//! The cube with a vertex c at `fraction` along the edge 0-1: the bottom face's triangle
//! {0, 3, 1} (traversing 1 -> 0) split at c, the front face's {0, 1, 5} not, and the crack
//! closed by the sliver (1, 0, c), as a T-junction mended by an exporter. Returns its id.
int add_sliver(TriSurface& s, double fraction) {
  const int c = int(s.points.size());
  s.points.push_back((1 - fraction) * s.points[0] + fraction * s.points[1]);
  s.triangles[1] = {0, 3, c};
  s.triangles.push_back({c, 3, 1});
  s.triangles.push_back({1, 0, c});
  return int(s.triangles.size()) - 1;
}

}  // namespace

TEST(FlipZeroAreaSlivers, ASliverBesideAT_JunctionIsFlippedAndTheShapeIsUnchanged) {
  TriSurface s = unit_cube();
  const int sliver = add_sliver(s, 0.25);
  ASSERT_TRUE(dthex::is_closed_manifold(s.triangles, s.points.size()));
  {
    TriSurface copy = s;
    EXPECT_THROW(dthex::verify_surface(copy, "sliver"), InputError);  // refused as it is
  }
  const double area_before = area(s);
  const size_t triangles_before = s.triangles.size();
  const FlipZeroAreaSliversReport report = flip_zero_area_slivers(s);
  EXPECT_EQ(report.slivers_flipped, 1u);
  EXPECT_EQ(report.left_in_place, 0u);
  ASSERT_EQ(report.first_flipped, std::vector<int>{sliver});
  EXPECT_EQ(report.first_places[0], Vec3(0.25, 0, 0));
  EXPECT_EQ(s.triangles.size(), triangles_before);  // replaced in place, none removed
  EXPECT_NEAR(area(s), area_before, 1e-14);
  for (const auto& t : s.triangles) EXPECT_FALSE(dthex::has_zero_area(s.points[size_t(t[0])], s.points[size_t(t[1])], s.points[size_t(t[2])]));
  const dthex::SurfaceStats stats = dthex::verify_surface(s, "flipped");
  EXPECT_NEAR(stats.volume, 1.0, 1e-14);
  EXPECT_EQ(stats.flipped_components, 0u);  // the flip kept the orientation
  EXPECT_EQ(stats.components, 1u);
}

TEST(FlipZeroAreaSlivers, NothingWithoutASliverOrOnAnOpenSurface) {
  TriSurface s = unit_cube();
  const TriSurface before = s;
  EXPECT_EQ(flip_zero_area_slivers(s).slivers_flipped, 0u);
  EXPECT_EQ(s.triangles, before.triangles);
  TriSurface open = unit_cube();
  add_sliver(open, 0.5);
  open.triangles.erase(open.triangles.begin() + 3);
  const TriSurface open_before = open;
  EXPECT_EQ(flip_zero_area_slivers(open).slivers_flipped, 0u);
  EXPECT_EQ(open.triangles, open_before.triangles);
}

TEST(FlipZeroAreaSlivers, AFlipThatWouldDuplicateAnEdgeIsLeftForVerification) {
  // A flat closed fan: the triangle (0, 1, d) both ways, one side split at c on the edge
  // 0-1 and closed by the sliver (1, 0, c). Flipping it would make the edge c-d, which the
  // split side has already.
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, 0, 0)};  // d = 2, c = 3
  s.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 1}, {1, 0, 3}};
  ASSERT_TRUE(dthex::is_closed_manifold(s.triangles, s.points.size()));
  const TriSurface before = s;
  const FlipZeroAreaSliversReport report = flip_zero_area_slivers(s);
  EXPECT_EQ(report.slivers_flipped, 0u);
  EXPECT_EQ(report.left_in_place, 1u);
  EXPECT_EQ(s.triangles, before.triangles);
}

TEST(FlipZeroAreaSlivers, SeveralSliversOnTheSphereAreAllFlippedWithVolumeAndAreaKept) {
  // A T-junction sliver on one edge of each of five triangles of the bundled sphere, two of
  // them on the same triangle's two edges (the second split is of a triangle the first made).
  TriSurface s = dthex::read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  TriSurface copy = s;
  const dthex::SurfaceStats before = dthex::verify_surface(copy, "sphere");
  const double area_before = area(s);
  for (const auto& [t, e, f] : std::vector<std::tuple<int, int, double>>{{0, 0, 0.3}, {150, 1, 0.5}, {300, 2, 0.7},
                                                                          {450, 0, 0.4}, {728, 1, 0.6}}) {
    const auto tri = s.triangles[size_t(t)];
    const int u = tri[size_t(e)], v = tri[size_t((e + 1) % 3)], w = tri[size_t((e + 2) % 3)];
    const int c = int(s.points.size());
    s.points.push_back((1 - f) * s.points[size_t(u)] + f * s.points[size_t(v)]);
    s.triangles[size_t(t)] = {u, c, w};
    s.triangles.push_back({c, v, w});
    s.triangles.push_back({u, v, c});  // against the split halves and the triangle across u-v
  }
  const FlipZeroAreaSliversReport report = flip_zero_area_slivers(s);
  EXPECT_EQ(report.slivers_flipped, 5u);
  EXPECT_EQ(report.left_in_place, 0u);
  EXPECT_EQ(report.first_flipped.size(), 5u);
  EXPECT_NEAR(area(s), area_before, 1e-12);
  const dthex::SurfaceStats after = dthex::verify_surface(s, "flipped");
  EXPECT_NEAR(after.volume, before.volume, 1e-12);
  EXPECT_EQ(after.triangles, before.triangles + 10);
}
