// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/repair/repair_orientation.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

using dthex::RepairOrientationReport;
using dthex::TriSurface;
using dthex::Vec3;
using dthex::repair_orientation;

namespace {

TriSurface sphere() { return dthex::read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off"); }

void turn(TriSurface& s, size_t t) { std::swap(s.triangles[t][1], s.triangles[t][2]); }

//! Box [0,sx] x [0,sy] x [0,sz], two outward triangles per face, faces in the order
//! -z, +z, -y, +y, -x, +x.
TriSurface box(double sx, double sy, double sz) {
  TriSurface s;
  for (int i = 0; i < 8; ++i) s.points.push_back(Vec3(sx * (i & 1), sy * ((i >> 1) & 1), sz * ((i >> 2) & 1)));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return s;
}

}  // namespace

TEST(RepairOrientation, OneReversedTriangleOfTheSphereIsTurnedBack) {
  const TriSurface original = sphere();
  TriSurface s = original;
  turn(s, 366);
  const RepairOrientationReport report = repair_orientation(s);
  EXPECT_EQ(report.triangles_turned, 1u);
  EXPECT_EQ(report.components_repaired, 1u);
  ASSERT_EQ(report.first_turned.size(), 1u);
  EXPECT_EQ(report.first_turned[0], 366);
  EXPECT_EQ(s.triangles, original.triangles);
  EXPECT_EQ(s.points, original.points);
  EXPECT_NO_THROW(dthex::verify_surface(s, "repaired sphere"));
}

TEST(RepairOrientation, AReversedCapIsTurnedNotTheRest) {
  const TriSurface original = sphere();
  // The cap above z = 0.3 r (a third of the area or less) reversed: the smaller class.
  double zmax = -1e300, zmin = 1e300;
  for (const Vec3& p : original.points) zmax = std::max(zmax, p.z()), zmin = std::min(zmin, p.z());
  const double cut = zmin + 0.65 * (zmax - zmin);
  TriSurface s = original;
  std::vector<bool> in_cap(s.triangles.size(), false);
  size_t cap = 0;
  int first = -1;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& tri = s.triangles[t];
    if ((s.points[size_t(tri[0])] + s.points[size_t(tri[1])] + s.points[size_t(tri[2])]).z() / 3 > cut) {
      turn(s, t);
      in_cap[t] = true;
      ++cap;
      if (first < 0) first = int(t);
    }
  }
  ASSERT_GT(cap, 20u);
  ASSERT_LT(2 * cap, s.triangles.size());
  const RepairOrientationReport report = repair_orientation(s);
  EXPECT_EQ(report.triangles_turned, cap);
  EXPECT_EQ(report.first_turned.front(), first);
  EXPECT_EQ(s.triangles, original.triangles);
  // Everything but the cap reversed instead: the cap is still the minority, and it is turned
  // to agree with the reversed majority (verification then turns the whole sphere outward).
  TriSurface rest = original;
  for (size_t t = 0; t < rest.triangles.size(); ++t)
    if (!in_cap[t]) turn(rest, t);
  const RepairOrientationReport again = repair_orientation(rest);
  EXPECT_EQ(again.triangles_turned, cap);
  for (size_t t = 0; t < rest.triangles.size(); ++t) {
    auto reversed = original.triangles[t];
    std::swap(reversed[1], reversed[2]);
    EXPECT_EQ(rest.triangles[t], reversed) << t;
  }
}

TEST(RepairOrientation, EqualCountsTurnTheSmallerArea) {
  // A 1 x 1 x 3 box, its two end faces (area 1 each) and one side (area 3) reversed: six
  // triangles each way, 5 against 9 in area, so the reversed ones are turned back.
  const TriSurface original = box(1, 1, 3);
  TriSurface s = original;
  for (size_t t : {0u, 1u, 2u, 3u, 8u, 9u}) turn(s, t);
  const RepairOrientationReport report = repair_orientation(s);
  EXPECT_EQ(report.triangles_turned, 6u);
  EXPECT_EQ(s.triangles, original.triangles);
  // The same six reversed on a 3 x 3 x 1 box (end faces 9 each, side 3): the other six turn.
  const TriSurface flat = box(3, 3, 1);
  TriSurface f = flat;
  for (size_t t : {0u, 1u, 2u, 3u, 8u, 9u}) turn(f, t);
  const RepairOrientationReport other = repair_orientation(f);
  EXPECT_EQ(other.triangles_turned, 6u);
  EXPECT_EQ(other.first_turned, (std::vector<int>{4, 5, 6, 7, 10}));
  for (size_t t = 0; t < 12; ++t) {
    auto reversed = flat.triangles[t];
    std::swap(reversed[1], reversed[2]);
    EXPECT_EQ(f.triangles[t], reversed) << t;
  }
}

TEST(RepairOrientation, EachComponentOnItsOwn) {
  // Two boxes apart, one reversed triangle in each: two turned, two components repaired.
  TriSurface s = box(1, 1, 1);
  const TriSurface other = box(1, 1, 1);
  for (const Vec3& p : other.points) s.points.push_back(p + Vec3(5, 0, 0));
  for (auto t : other.triangles) s.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  const TriSurface original = s;
  turn(s, 4);
  turn(s, 12 + 7);
  const RepairOrientationReport report = repair_orientation(s);
  EXPECT_EQ(report.triangles_turned, 2u);
  EXPECT_EQ(report.components_repaired, 2u);
  EXPECT_EQ(report.first_turned, (std::vector<int>{4, 19}));
  EXPECT_EQ(s.triangles, original.triangles);
}

TEST(RepairOrientation, LeavesANonManifoldOrOpenSurfaceAlone) {
  TriSurface open = box(1, 1, 1);
  open.triangles.pop_back();
  turn(open, 0);
  const TriSurface before = open;
  const RepairOrientationReport report = repair_orientation(open);
  EXPECT_TRUE(report.skipped_not_manifold);
  EXPECT_EQ(report.triangles_turned, 0u);
  EXPECT_EQ(open.triangles, before.triangles);
  TriSurface bad = box(1, 1, 1);
  bad.triangles[0][0] = 99;  // out of range: left to verification
  EXPECT_TRUE(repair_orientation(bad).skipped_not_manifold);
}
