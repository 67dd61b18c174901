// SPDX-License-Identifier: MIT
#include <dthex/tets/refine_flat_needles.h>

#include <dthex/surface/surface_distance.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace dthex;

namespace {

// A closed drum: the points of a unit circle at `angles` (radians, increasing) at z = 0 and
// their copies at z = height, each cap a fan from its vertex 0 (every vertex on the outline,
// needles at the fan's apex, as hole filling closes a cut), and the side quads split into two
// triangles each. Outward oriented.
TriSurface fan_capped_drum_at(const std::vector<double>& angles, double height) {
  TriSurface s;
  const int n = int(angles.size());
  for (int k = 0; k < 2; ++k)
    for (double a : angles) s.points.push_back({std::cos(a), std::sin(a), k * height});
  for (int i = 1; i + 1 < n; ++i) {
    s.triangles.push_back({0, i + 1, i});              // bottom, facing -z
    s.triangles.push_back({n, n + i, n + i + 1});      // top, facing +z
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    s.triangles.push_back({i, j, n + j});
    s.triangles.push_back({i, n + j, n + i});
  }
  return s;
}

// The same with a regular n-gon for caps (needles of 180/n degrees at the fan's apex).
TriSurface fan_capped_drum(int n, double height) {
  std::vector<double> angles;
  for (int i = 0; i < n; ++i) angles.push_back(2 * M_PI * i / n);
  return fan_capped_drum_at(angles, height);
}

double smallest_angle_deg(const TriSurface& s, int t) {
  const auto& f = s.triangles[size_t(t)];
  double smallest = 180;
  for (int i = 0; i < 3; ++i) {
    const Vec3 p = s.points[size_t(f[size_t(i)])];
    const Vec3 u = s.points[size_t(f[size_t((i + 1) % 3)])] - p, w = s.points[size_t(f[size_t((i + 2) % 3)])] - p;
    smallest = std::min(smallest, std::acos(std::clamp(u.dot(w) / (u.norm() * w.norm()), -1.0, 1.0)) * 180 / M_PI);
  }
  return smallest;
}

bool in_cap(const TriSurface& s, int t, double z) {
  for (int v : s.triangles[size_t(t)])
    if (std::abs(s.points[size_t(v)].z() - z) > 1e-12) return false;
  return true;
}

}  // namespace

// The fans' needles (7.5 degrees at n = 24) are refined within the caps: the smallest cap
// angle grows past the 15-degree bound's neighbourhood, every new point lies in its cap's
// plane, the surface stays closed with the same volume, and the side strips (needles of
// 7.4 degrees between two feature lines, which no split can widen) are left as they were.
TEST(RefineFlatNeedles, FanCapsGetInnerPointsAndTheSidesStay) {
  const int n = 24;
  const double height = 2.0;
  TriSurface s = fan_capped_drum(n, height);
  const double volume = enclosed_volume(s);
  double cap_before = 180;
  for (int t = 0; t < int(s.triangles.size()); ++t)
    if (in_cap(s, t, 0) || in_cap(s, t, height)) cap_before = std::min(cap_before, smallest_angle_deg(s, t));
  EXPECT_NEAR(cap_before, 180.0 / n, 1e-9);

  const RefineFlatNeedlesReport report = refine_flat_needles(s);
  // Per cap n - 2 fan triangles; the first and last have an outline edge at the apex.
  EXPECT_EQ(report.needles_before, 2u * (n - 4));
  EXPECT_LT(report.needles_after, report.needles_before / 4);
  EXPECT_GT(report.vertices_added, 0u);

  const SurfaceStats stats = verify_surface(s, "refined drum");
  EXPECT_EQ(stats.flipped_components, 0u);
  EXPECT_NEAR(enclosed_volume(s), volume, 1e-12 * std::abs(volume));
  size_t side = 0;
  double cap_after = 180;
  for (int t = 0; t < int(s.triangles.size()); ++t) {
    if (in_cap(s, t, 0) || in_cap(s, t, height)) {
      cap_after = std::min(cap_after, smallest_angle_deg(s, t));
    } else {
      ++side;
      for (int v : s.triangles[size_t(t)]) EXPECT_LT(v, 2 * n) << "a point was added on the side";
    }
  }
  EXPECT_EQ(side, size_t(2 * n));
  for (size_t v = 2 * n; v < s.points.size(); ++v) {
    const double z = s.points[v].z();
    EXPECT_TRUE(z == 0.0 || z == height) << "new point " << v << " left its cap: z = " << z;
    EXPECT_LT(s.points[v].head<2>().norm(), 1.0);
  }
  EXPECT_GT(cap_after, 3 * cap_before);
}

// A surface without flat regions (an octahedron: every edge a 109-degree crease) or without
// needles (a cube split into right isosceles triangles) is returned exactly as it came.
TEST(RefineFlatNeedles, LeavesSurfacesWithoutFlatNeedlesUntouched) {
  TriSurface octahedron;
  octahedron.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        std::array<int, 3> t{sx, 2 + sy, 4 + sz};
        if ((sx + sy + sz) % 2 == 0) std::swap(t[1], t[2]);
        octahedron.triangles.push_back(t);
      }
  TriSurface drum = fan_capped_drum(4, 1.0);  // a box: its caps' triangles are right isosceles
  for (TriSurface* s : {&octahedron, &drum}) {
    const TriSurface before = *s;
    const RefineFlatNeedlesReport report = refine_flat_needles(*s);
    EXPECT_EQ(report.needles_before, 0u);
    EXPECT_EQ(report.vertices_added, 0u);
    EXPECT_EQ(s->points, before.points);
    EXPECT_EQ(s->triangles, before.triangles);
  }
}

// A cap whose outline is dense along one arc (40 points within 30 degrees) and sparse along the
// rest (8 points): the splits of its needles make new needles against the dense arc faster than
// they remove old ones. The round that left more is taken back, and with no round leaving fewer
// the surface is returned exactly as it came. Kept, that round would leave 102 needles of the
// 76 and 64 points added.
TEST(RefineFlatNeedles, RoundsThatLeaveMoreNeedlesAreTakenBack) {
  std::vector<double> angles;
  const double arc = 30 * M_PI / 180;
  for (int i = 0; i < 40; ++i) angles.push_back(arc * i / 40);
  for (int i = 0; i < 8; ++i) angles.push_back(arc + (2 * M_PI - arc) * i / 8);
  TriSurface s = fan_capped_drum_at(angles, 2.0);
  const TriSurface before = s;
  const RefineFlatNeedlesReport report = refine_flat_needles(s);
  EXPECT_EQ(report.needles_before, 76u);
  EXPECT_GE(report.rounds_taken_back, 1u);
  EXPECT_EQ(report.needles_after, report.needles_before);
  EXPECT_EQ(report.vertices_added, 0u);
  EXPECT_EQ(s.points, before.points);
  EXPECT_EQ(s.triangles, before.triangles);

  // Where the first rounds help and later ones would not, the best round is kept: never more
  // needles than before, and fewer here.
  std::vector<double> uneven;
  const double wide = 60 * M_PI / 180;
  for (int i = 0; i < 20; ++i) uneven.push_back(wide * i / 20);
  for (int i = 0; i < 10; ++i) uneven.push_back(wide + (2 * M_PI - wide) * i / 10);
  TriSurface t = fan_capped_drum_at(uneven, 2.0);
  const RefineFlatNeedlesReport helped = refine_flat_needles(t);
  EXPECT_LT(helped.needles_after, helped.needles_before);
  EXPECT_GT(helped.vertices_added, 0u);
  const SurfaceStats stats = verify_surface(t, "refined uneven drum");
  EXPECT_EQ(stats.flipped_components, 0u);
}
