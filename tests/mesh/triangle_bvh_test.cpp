// SPDX-License-Identifier: MIT
#include <dthex/mesh/triangle_bvh.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

using dthex::TriangleBvh;
using dthex::TriSurface;
using dthex::Vec3;

namespace {

//! Latitude-longitude sphere of radius r: poles plus (rings x segments) vertices.
TriSurface uv_sphere(int rings, int segments, double r = 1.0) {
  TriSurface s;
  s.points.push_back(Vec3(0, 0, r));
  for (int i = 1; i <= rings; ++i) {
    const double theta = M_PI * i / (rings + 1);
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * M_PI * j / segments;
      s.points.push_back(r * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  s.points.push_back(Vec3(0, 0, -r));
  const int south = int(s.points.size()) - 1;
  auto at = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) s.triangles.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      s.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int j = 0; j < segments; ++j) s.triangles.push_back({south, at(rings, j + 1), at(rings, j)});
  return s;
}

double brute_distance_sq(const TriSurface& s, const Vec3& q, int* best_triangle = nullptr,
                         const std::function<bool(int)>& accept = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    if (accept && !accept(int(t))) continue;
    const auto& tri = s.triangles[t];
    const Vec3 p = dthex::closest_point_on_triangle(q, s.points[size_t(tri[0])], s.points[size_t(tri[1])],
                                                    s.points[size_t(tri[2])]);
    const double d = (p - q).squaredNorm();
    if (d < best) {
      best = d;
      if (best_triangle) *best_triangle = int(t);
    }
  }
  return best;
}

}  // namespace

TEST(TriangleBvh, ClosestPointOnTriangleRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(-1, -1, 3), a, b, c).isApprox(a));
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(2, -1, 0), a, b, c).isApprox(b));
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(0.5, -2, 1), a, b, c).isApprox(Vec3(0.5, 0, 0)));
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(1, 1, 0), a, b, c).isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(0.2, 0.3, -4), a, b, c).isApprox(Vec3(0.2, 0.3, 0)));
  // A zero-area triangle still yields a point on it.
  EXPECT_TRUE(dthex::closest_point_on_triangle(Vec3(0.5, 1, 0), a, b, Vec3(2, 0, 0)).isApprox(Vec3(0.5, 0, 0)));
}

TEST(TriangleBvh, ClosestPointEqualsBruteForceOnSphere) {
  const TriSurface sphere = uv_sphere(30, 48);
  const TriangleBvh bvh(sphere);
  ASSERT_EQ(bvh.size(), sphere.triangles.size());
  EXPECT_NEAR(bvh.bounds().max().z(), 1.0, 1e-15);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  for (int i = 0; i < 500; ++i) {
    const Vec3 q(u(rng), u(rng), u(rng));
    const auto hit = bvh.closest_point(q);
    ASSERT_GE(hit.triangle, 0);
    EXPECT_EQ(hit.distance_sq, brute_distance_sq(sphere, q)) << "query " << q.transpose();
    EXPECT_EQ(hit.distance_sq, (hit.point - q).squaredNorm());
    // The point lies on the reported triangle.
    const auto& t = sphere.triangles[size_t(hit.triangle)];
    const Vec3 on = dthex::closest_point_on_triangle(q, sphere.points[size_t(t[0])], sphere.points[size_t(t[1])],
                                                     sphere.points[size_t(t[2])]);
    EXPECT_EQ(on, hit.point);
  }
}

TEST(TriangleBvh, AcceptFilterRestrictsTheSearch) {
  const TriSurface sphere = uv_sphere(20, 32);
  const TriangleBvh bvh(sphere);
  // Accept only triangles in the lower hemisphere: a query above the north pole must land there.
  auto lower = [&](int t) {
    const auto& tri = sphere.triangles[size_t(t)];
    return (sphere.points[size_t(tri[0])] + sphere.points[size_t(tri[1])] + sphere.points[size_t(tri[2])]).z() < 0;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int i = 0; i < 200; ++i) {
    const Vec3 q(u(rng), u(rng), u(rng));
    const auto hit = bvh.closest_point(q, lower);
    ASSERT_GE(hit.triangle, 0);
    EXPECT_TRUE(lower(hit.triangle));
    EXPECT_EQ(hit.distance_sq, brute_distance_sq(sphere, q, nullptr, lower));
  }
  const auto north = bvh.closest_point(Vec3(0, 0, 2), lower);
  EXPECT_GT(north.distance_sq, 4.0 - 1e-9);  // nothing accepted above z = 0
  const auto none = bvh.closest_point(Vec3(0, 0, 2), [](int) { return false; });
  EXPECT_EQ(none.triangle, -1);
}

// A facing bound consistent with the accept test (only triangles facing against a direction)
// changes no answer, and the search then asks the accept test about far fewer triangles: the
// subtrees that face the other way are skipped whole.
TEST(TriangleBvh, FacingBoundSkipsSubtreesButChangesNoAnswer) {
  const TriSurface sphere = uv_sphere(40, 64);
  const TriangleBvh bvh(sphere);
  const TriangleBvh::NormalBounds bounds = bvh.normal_bounds();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.5, 1.5), radius(0.05, 2.0);
  size_t asked_with = 0, asked_without = 0;
  int found = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 direction = Vec3(u(rng), u(rng), u(rng)).normalized();
    const double max_cos = i % 2 ? -0.5 : 0.3;
    size_t* asked = nullptr;
    const std::function<bool(int)> facing_against = [&](int t) {
      ++*asked;
      const auto& tri = sphere.triangles[size_t(t)];
      const Vec3 a = sphere.points[size_t(tri[0])];
      const Vec3 n = (sphere.points[size_t(tri[1])] - a).cross(sphere.points[size_t(tri[2])] - a).normalized();
      return n.dot(direction) < max_cos;
    };
    const TriangleBvh::Facing facing{&bounds, direction, max_cos};
    const Vec3 q(u(rng), u(rng), u(rng));
    const double r = radius(rng);
    asked = &asked_without;
    const auto plain = bvh.closest_point_within(q, r, facing_against);
    asked = &asked_with;
    const auto pruned = bvh.closest_point_within(q, r, facing_against, &facing);
    ASSERT_EQ(pruned.triangle, plain.triangle) << "query " << i;
    EXPECT_EQ(pruned.distance_sq, plain.distance_sq);
    EXPECT_TRUE(pruned.point == plain.point);
    found += plain.triangle >= 0;
  }
  EXPECT_GT(found, 100);
  EXPECT_LT(2 * asked_with, asked_without);
}

TEST(TriangleBvh, SearchWithinARadiusFindsWhatIsInsideAndNothingElse) {
  const TriSurface sphere = uv_sphere(20, 32);
  const TriangleBvh bvh(sphere);
  auto lower = [&](int t) {
    const auto& tri = sphere.triangles[size_t(t)];
    return (sphere.points[size_t(tri[0])] + sphere.points[size_t(tri[1])] + sphere.points[size_t(tri[2])]).z() < 0;
  };
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.5, 1.5), radius(0.05, 2.0);
  int inside = 0, outside = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 q(u(rng), u(rng), u(rng));
    const double r = radius(rng);
    const double nearest = brute_distance_sq(sphere, q, nullptr, lower);
    const auto hit = bvh.closest_point_within(q, r, lower);
    if (nearest < r * r) {
      ++inside;
      ASSERT_GE(hit.triangle, 0);
      EXPECT_EQ(hit.distance_sq, nearest);
    } else {
      ++outside;
      EXPECT_EQ(hit.triangle, -1) << "nothing accepted lies within " << r << " of " << q.transpose();
    }
  }
  EXPECT_GT(inside, 30);
  EXPECT_GT(outside, 30);
}

TEST(TriangleBvh, OverlappingPairsEqualBruteForce) {
  // A small sphere plus a shifted copy so pairs also cross between the two bodies.
  TriSurface s = uv_sphere(6, 9);
  const size_t n = s.points.size(), m = s.triangles.size();
  for (size_t i = 0; i < n; ++i) s.points.push_back(s.points[i] * 0.7 + Vec3(0.9, 0.1, 0.05));
  for (size_t t = 0; t < m; ++t)
    s.triangles.push_back({s.triangles[t][0] + int(n), s.triangles[t][1] + int(n), s.triangles[t][2] + int(n)});

  auto box_of = [&](int t) {
    Eigen::AlignedBox3d b;
    for (int v : s.triangles[size_t(t)]) b.extend(s.points[size_t(v)]);
    return b;
  };
  std::set<std::pair<int, int>> brute;
  const int count = int(s.triangles.size());
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b) {
      const auto ba = box_of(a), bb = box_of(b);
      if ((ba.min().array() <= bb.max().array()).all() && (bb.min().array() <= ba.max().array()).all())
        brute.insert({a, b});
    }

  const TriangleBvh bvh(s);
  std::set<std::pair<int, int>> found;
  size_t calls = 0;
  bvh.for_each_overlapping_pair([&](int a, int b) {
    EXPECT_LT(a, b);
    found.insert({a, b});
    ++calls;
  });
  EXPECT_EQ(calls, found.size());  // each pair once
  EXPECT_EQ(found, brute);
  EXPECT_GT(brute.size(), size_t(3 * count));  // neighbours at least, and crossings

  // Cut into parts (as verification shares them over the cores): together they visit the
  // same pairs, each once.
  const auto parts = bvh.overlapping_pair_parts(16);
  EXPECT_GE(parts.size(), 16u);
  std::set<std::pair<int, int>> in_parts;
  size_t part_calls = 0;
  for (const auto& part : parts)
    bvh.for_each_overlapping_pair_in(part, [&](int a, int b) {
      in_parts.insert({a, b});
      ++part_calls;
    });
  EXPECT_EQ(part_calls, in_parts.size());
  EXPECT_EQ(in_parts, brute);

  // for_each_in_box agrees with brute force too.
  const Eigen::AlignedBox3d query(Vec3(0.2, -0.3, -0.2), Vec3(0.8, 0.4, 0.6));
  std::set<int> in_box, brute_box;
  bvh.for_each_in_box(query, [&](int t) { in_box.insert(t); });
  for (int t = 0; t < count; ++t)
    if (box_of(t).intersects(query)) brute_box.insert(t);
  EXPECT_EQ(in_box, brute_box);
  EXPECT_FALSE(in_box.empty());
}

TEST(TriangleBvh, EmptyAndCoincidentInput) {
  const TriangleBvh empty(std::vector<Vec3>{}, std::vector<std::array<int, 3>>{});
  EXPECT_EQ(empty.closest_point(Vec3::Zero()).triangle, -1);
  EXPECT_TRUE(empty.bounds().isEmpty());
  // Many identical triangles (all centroids equal) must still build small leaves and answer.
  std::vector<Vec3> pts{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  std::vector<std::array<int, 3>> tris(100, {0, 1, 2});
  const TriangleBvh same(pts, tris);
  EXPECT_DOUBLE_EQ(same.closest_point(Vec3(0.2, 0.2, 2)).distance_sq, 4.0);
  size_t pairs = 0;
  same.for_each_overlapping_pair([&](int, int) { ++pairs; });
  EXPECT_EQ(pairs, size_t(100 * 99 / 2));
}
