// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/repair/remove_small_islands.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include <cmath>

using dthex::RemoveSmallIslandsOptions;
using dthex::RemoveSmallIslandsReport;
using dthex::TriSurface;
using dthex::Vec3;
using dthex::remove_small_islands;

namespace {

//! Appends a closed, outward triangulated box [lo, lo + size]: 12 triangles.
void add_box(TriSurface& s, const Vec3& lo, const Vec3& size) {
  const int base = int(s.points.size());
  for (int i = 0; i < 8; ++i) s.points.push_back(lo + Vec3(size.x() * (i & 1), size.y() * ((i >> 1) & 1), size.z() * ((i >> 2) & 1)));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({base + q[0], base + q[1], base + q[2]});
    s.triangles.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

//! Appends an outward tetrahedron at p: 4 triangles.
void add_tet(TriSurface& s, const Vec3& p) {
  const int b = int(s.points.size());
  s.points.insert(s.points.end(), {p, p + Vec3(0.1, 0, 0), p + Vec3(0, 0.1, 0), p + Vec3(0, 0, 0.1)});
  s.triangles.insert(s.triangles.end(), {{b, b + 2, b + 1}, {b, b + 1, b + 3}, {b, b + 3, b + 2}, {b + 1, b + 2, b + 3}});
}

}  // namespace

TEST(RemoveSmallIslands, AnIslandOfTenTrianglesBesideTheSphereIsDropped) {
  // A noise island of 10 triangles (a pentagonal bipyramid) beside the bundled sphere.
  const TriSurface sphere = dthex::read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  TriSurface s = sphere;
  const int base = int(s.points.size());
  const Vec3 centre(5, 0, 0);
  for (int k = 0; k < 5; ++k)
    s.points.push_back(centre + 0.1 * Vec3(std::cos(2 * M_PI * k / 5), std::sin(2 * M_PI * k / 5), 0));
  s.points.push_back(centre + Vec3(0, 0, 0.1));
  s.points.push_back(centre - Vec3(0, 0, 0.1));
  for (int k = 0; k < 5; ++k) {
    const int a = base + k, b = base + (k + 1) % 5;
    s.triangles.push_back({a, b, base + 5});
    s.triangles.push_back({b, a, base + 6});
  }
  {
    TriSurface copy = s;
    ASSERT_EQ(dthex::verify_surface(copy, "with island").components, 2u);  // a valid second body
  }
  const TriSurface with_island = s;
  RemoveSmallIslandsOptions options;
  options.min_triangles = 11;
  const RemoveSmallIslandsReport report = remove_small_islands(s, options);
  EXPECT_EQ(report.islands_dropped, 1u);
  EXPECT_EQ(report.triangles_dropped, 10u);
  ASSERT_EQ(report.first_triangles.size(), 1u);
  EXPECT_EQ(report.first_triangles[0], int(sphere.triangles.size()));
  EXPECT_LT((report.first_places[0] - centre).norm(), 0.2);
  EXPECT_EQ(s.triangles, sphere.triangles);
  EXPECT_EQ(dthex::verify_surface(s, "without island").components, 1u);
  // At 10 the island is not below the threshold.
  TriSurface again = with_island;
  options.min_triangles = 10;
  EXPECT_EQ(remove_small_islands(again, options).islands_dropped, 0u);
  EXPECT_EQ(again.triangles, with_island.triangles);
}

TEST(RemoveSmallIslands, OffByDefaultAndTheLargestIsKept) {
  TriSurface s;
  add_box(s, Vec3::Zero(), Vec3::Ones());
  add_tet(s, Vec3(3, 0, 0));
  add_tet(s, Vec3(5, 0, 0));
  const TriSurface before = s;
  EXPECT_EQ(remove_small_islands(s, {}).triangles_dropped, 0u);  // min_triangles 0: off
  EXPECT_EQ(s.triangles, before.triangles);
  RemoveSmallIslandsOptions options;
  options.min_triangles = 1000;  // every island is below: the largest stays
  const RemoveSmallIslandsReport report = remove_small_islands(s, options);
  EXPECT_EQ(report.islands_dropped, 2u);
  EXPECT_EQ(report.triangles_dropped, 8u);
  EXPECT_EQ(report.first_triangles, (std::vector<int>{12, 16}));
  EXPECT_EQ(s.triangles.size(), 12u);
}

TEST(RemoveSmallIslands, ByVolumeATinyCubeBesideTheFemurIsDroppedBelowTheFraction) {
  // A cube enclosing 0.01% of the femur's volume, beside it: 12 triangles, as many as a real
  // bone fragment could have, so only its volume tells it from one.
  const TriSurface femur = dthex::read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/femur_proximal_ct.off");
  TriSurface copy = femur;
  const dthex::SurfaceStats stats = dthex::verify_surface(copy, "femur");
  const double side = std::cbrt(1e-4 * stats.volume);
  TriSurface s = femur;
  add_box(s, stats.bounds.max() + Vec3(1, 1, 1) * stats.bbox_diagonal * 0.1, Vec3::Ones() * side);
  const TriSurface with_cube = s;
  RemoveSmallIslandsOptions options;
  options.min_volume_fraction = 1e-3;  // --min-island 0.1%
  const RemoveSmallIslandsReport report = remove_small_islands(s, options);
  EXPECT_EQ(report.islands_dropped, 1u);
  EXPECT_EQ(report.dropped_by_volume, 1u);
  EXPECT_EQ(report.triangles_dropped, 12u);
  ASSERT_EQ(report.first_triangles.size(), 1u);
  EXPECT_EQ(report.first_triangles[0], int(femur.triangles.size()));
  EXPECT_EQ(s.triangles, femur.triangles);
  // At 0.001% the cube (0.01%) is above the fraction and kept; so is it by a triangle count.
  for (double fraction : {1e-5, 0.0}) {
    TriSurface again = with_cube;
    options.min_volume_fraction = fraction;
    EXPECT_EQ(remove_small_islands(again, options).islands_dropped, 0u) << fraction;
    EXPECT_EQ(again.triangles, with_cube.triangles);
  }
}

TEST(RemoveSmallIslands, ByVolumeTheVolumeIsMeasuredWithConsistentOrientation) {
  // A box of volume 1 and one of 0.008 (0.8%) with a triangle wound the wrong way, and an
  // inward box of 0.008: the reversed triangle and the winding must not change their volume.
  TriSurface s;
  add_box(s, Vec3::Zero(), Vec3::Ones());
  add_box(s, Vec3(3, 0, 0), Vec3::Ones() * 0.2);
  std::swap(s.triangles[14][1], s.triangles[14][2]);
  add_box(s, Vec3(5, 0, 0), Vec3::Ones() * 0.2);
  for (size_t t = 24; t < 36; ++t) std::swap(s.triangles[t][1], s.triangles[t][2]);
  const TriSurface before = s;
  RemoveSmallIslandsOptions options;
  options.min_volume_fraction = 0.0079;  // just below 0.8%: both kept
  EXPECT_EQ(remove_small_islands(s, options).islands_dropped, 0u);
  EXPECT_EQ(s.triangles, before.triangles);
  options.min_volume_fraction = 0.0081;  // just above: both dropped, the unit box kept
  const RemoveSmallIslandsReport report = remove_small_islands(s, options);
  EXPECT_EQ(report.dropped_by_volume, 2u);
  EXPECT_EQ(report.first_triangles, (std::vector<int>{12, 24}));
  EXPECT_EQ(s.triangles.size(), 12u);
}

TEST(RemoveSmallIslands, ByVolumeAnOpenIslandHasNoVolumeAndIsKept) {
  TriSurface s;
  add_box(s, Vec3::Zero(), Vec3::Ones());
  add_box(s, Vec3(3, 0, 0), Vec3::Ones() * 0.1);
  s.triangles.pop_back();  // the small box open
  RemoveSmallIslandsOptions options;
  options.min_volume_fraction = 0.5;
  EXPECT_EQ(remove_small_islands(s, options).islands_dropped, 0u);
  EXPECT_EQ(s.triangles.size(), 23u);
}
