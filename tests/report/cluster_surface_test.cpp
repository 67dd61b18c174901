// SPDX-License-Identifier: MIT
// Vertex clustering: the reduced surface fits the budget, stays closed (no edge used by
// one triangle only), keeps the area, orientation and thin sheets of the input, and keeps
// flagged faces unchanged.
#include <dthex/report/cluster_surface.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace dthex;

namespace {

struct Surface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
};

// An icosahedron subdivided `levels` times and pushed onto the unit sphere: 20 * 4^levels triangles.
Surface icosphere(int levels) {
  Surface s;
  const double t = (1 + std::sqrt(5.0)) / 2;
  s.points = {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t), Vec3(0, 1, t),
              Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)};
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& p : s.points) p.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      s.points.push_back((s.points[size_t(a)] + s.points[size_t(b)]).normalized());
      return midpoint[key] = int(s.points.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : s.triangles) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    s.triangles = std::move(finer);
  }
  return s;
}

// The surface of the box [0,sx]x[0,sy]x[0,sz] as n x n quads per side, outward oriented.
struct QuadBox {
  std::vector<Vec3> points;
  std::vector<std::array<int, 4>> quads;
};
QuadBox quad_box(const Vec3& size, int n) {
  QuadBox box;
  std::map<std::array<long, 3>, int> index;  // shared nodes on the box edges
  auto node = [&](const Vec3& unit) {
    const std::array<long, 3> key{std::lround(unit.x() * n), std::lround(unit.y() * n), std::lround(unit.z() * n)};
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    box.points.push_back(unit.cwiseProduct(size));
    return index[key] = int(box.points.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<int, 4> q;
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            Vec3 p = Vec3::Zero();
            p[axis] = side;
            p[u] = double(i + di[k]) / n;
            p[v] = double(j + dj[k]) / n;
            q[size_t(k)] = node(p);
          }
          if (side == 0) std::swap(q[1], q[3]);  // (u, v, axis) is right-handed: flip the low side
          box.quads.push_back(q);
        }
    }
  return box;
}

double area(const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& triangles) {
  double a = 0;
  for (const auto& t : triangles)
    a += 0.5 * (p[size_t(t[1])] - p[size_t(t[0])]).cross(p[size_t(t[2])] - p[size_t(t[0])]).norm();
  return a;
}

double volume(const std::vector<Vec3>& p, const std::vector<std::array<int, 3>>& triangles) {
  double v = 0;
  for (const auto& t : triangles) v += p[size_t(t[0])].dot(p[size_t(t[1])].cross(p[size_t(t[2])])) / 6.0;
  return v;
}

// Edges (undirected) used by fewer than two triangles: the holes of the surface.
size_t open_edges(const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[size_t(k)], t[size_t((k + 1) % 3)])];
  size_t open = 0;
  for (const auto& [edge, count] : uses) open += count < 2;
  return open;
}

}  // namespace

TEST(ClusterSurface, SphereFitsTheBudgetClosedWithItsAreaAndVolume) {
  const Surface sphere = icosphere(5);  // 20,480 triangles
  ClusterSurfaceOptions options;
  options.max_triangles = 2000;
  const ClusteredSurface r = cluster_surface(sphere.points, sphere.triangles, {}, {}, options);
  EXPECT_LE(r.triangles.size(), options.max_triangles);
  EXPECT_GT(r.triangles.size(), options.max_triangles / 2);  // the grid is not needlessly coarse
  EXPECT_GT(r.grid_cells, 0u);
  EXPECT_EQ(open_edges(r.triangles), 0u);
  const double a = area(sphere.points, sphere.triangles), v = volume(sphere.points, sphere.triangles);
  EXPECT_NEAR(area(r.points, r.triangles) / a, 1.0, 0.03);
  EXPECT_NEAR(volume(r.points, r.triangles) / v, 1.0, 0.05);  // positive: orientation kept
  // Each cluster is the mean of nearby sphere points: within a cell of the sphere.
  const double cell = 2.0 / double(r.grid_cells);
  for (const Vec3& p : r.points) EXPECT_NEAR(p.norm(), 1.0, std::sqrt(3.0) * cell);
  ASSERT_EQ(r.source_face.size(), r.triangles.size());
  for (size_t s : r.source_face) EXPECT_LT(s, sphere.triangles.size());
  // A smooth patch is not split: no more clusters than occupied grid cells (the grid
  // spans the bounding box, grid_cells along its longest side).
  Vec3 lo = sphere.points.front(), hi = lo;
  for (const Vec3& p : sphere.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double h = (hi - lo).maxCoeff() / double(r.grid_cells);
  std::set<std::array<long, 3>> occupied;
  for (const Vec3& p : sphere.points) {
    std::array<long, 3> c;
    for (int k = 0; k < 3; ++k) c[size_t(k)] = std::min(long(r.grid_cells) - 1, long(std::floor((p[k] - lo[k]) / h)));
    occupied.insert(c);
  }
  EXPECT_LE(r.points.size(), occupied.size());
}

TEST(ClusterSurface, WithinTheBudgetTheSurfaceComesBackUnchanged) {
  const Surface sphere = icosphere(2);
  ClusterSurfaceOptions options;
  options.max_triangles = sphere.triangles.size();
  const ClusteredSurface r = cluster_surface(sphere.points, sphere.triangles, {}, {}, options);
  EXPECT_EQ(r.grid_cells, 0u);
  EXPECT_EQ(r.triangles, sphere.triangles);
  EXPECT_EQ(r.points, sphere.points);
}

TEST(ClusterSurface, FlaggedFacesSurviveUnchangedAndEachTriangleShowsTheWorstSource) {
  const Surface sphere = icosphere(5);
  std::vector<double> priority(sphere.triangles.size());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0.3, 1.0);
  for (double& p : priority) p = uniform(random);
  std::vector<char> keep(sphere.triangles.size(), 0);
  std::vector<size_t> flagged;
  for (size_t f = 0; f < sphere.triangles.size(); f += 211) {
    keep[f] = 1;
    priority[f] = 0.01;  // poor
    flagged.push_back(f);
  }
  ClusterSurfaceOptions options;
  options.max_triangles = 3000;
  const ClusteredSurface r = cluster_surface(sphere.points, sphere.triangles, priority, keep, options);
  EXPECT_LE(r.triangles.size(), options.max_triangles);
  EXPECT_EQ(open_edges(r.triangles), 0u);
  EXPECT_EQ(r.kept_faces, flagged.size());
  // Every flagged face is there with its own corners, its orientation and itself as source.
  std::map<std::array<double, 9>, size_t> by_corners;
  for (size_t t = 0; t < r.triangles.size(); ++t) {
    std::array<double, 9> key;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) key[size_t(3 * k + c)] = r.points[size_t(r.triangles[t][size_t(k)])][c];
    by_corners[key] = t;
  }
  for (size_t f : flagged) {
    bool found = false;
    for (int rotation = 0; rotation < 3 && !found; ++rotation) {
      std::array<double, 9> key;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c)
          key[size_t(3 * k + c)] = sphere.points[size_t(sphere.triangles[f][size_t((k + rotation) % 3)])][c];
      const auto it = by_corners.find(key);
      if (it != by_corners.end()) {
        found = true;
        EXPECT_EQ(r.source_face[it->second], f);
      }
    }
    EXPECT_TRUE(found) << "flagged face " << f;
  }
  // A triangle's source is the worst face mapped onto it: no triangle shows a better
  // value than a flagged face next to it would, and the poor values stay where they were.
  size_t poor_shown = 0;
  for (size_t s : r.source_face) poor_shown += priority[s] < 0.1;
  EXPECT_EQ(poor_shown, flagged.size());
}

TEST(ClusterSurface, TooManyFlaggedFacesAreCappedWorstFirst) {
  const Surface sphere = icosphere(5);
  std::vector<double> priority(sphere.triangles.size());
  for (size_t f = 0; f < priority.size(); ++f) priority[f] = double(f % 1000) / 1000.0;
  const std::vector<char> keep(sphere.triangles.size(), 1);  // all of them: far beyond the budget
  ClusterSurfaceOptions options;
  options.max_triangles = 2000;
  const ClusteredSurface r = cluster_surface(sphere.points, sphere.triangles, priority, keep, options);
  EXPECT_LE(r.triangles.size(), options.max_triangles);
  EXPECT_EQ(open_edges(r.triangles), 0u);
  EXPECT_GT(r.kept_faces, 0u);
  EXPECT_LE(r.kept_faces, size_t(options.max_kept_share * double(options.max_triangles)));
  // Kept faces are the worst ones: the faces of value 0 (every 1000th) are all kept, and a
  // kept face is the only source that maps onto its three unmerged corners.
  size_t zero_faces = 0, zero_shown = 0;
  for (double p : priority) zero_faces += p == 0.0;
  for (size_t s : r.source_face) zero_shown += priority[s] == 0.0;
  ASSERT_LT(zero_faces, r.kept_faces);
  EXPECT_EQ(zero_shown, zero_faces);
}

TEST(ClusterSurface, ThinSheetKeepsBothSidesAndQuadsBecomeClosedTriangles) {
  // 100 x 100 x 0.05: far thinner than a grid cell. Merging the two sides would cancel them.
  const QuadBox slab = quad_box(Vec3(100, 100, 0.05), 60);  // 21,600 quads, 43,200 triangles
  ClusterSurfaceOptions options;
  options.max_triangles = 4000;
  const ClusteredSurface r = cluster_surface(slab.points, slab.quads, {}, {}, options);
  EXPECT_LE(r.triangles.size(), options.max_triangles);
  EXPECT_GT(r.grid_cells, 0u);
  EXPECT_GT(100.0 / double(r.grid_cells), 0.05 * 10);  // cells far thicker than the sheet
  EXPECT_EQ(open_edges(r.triangles), 0u);
  const double slab_area = 2 * 100 * 100 + 4 * 100 * 0.05;
  EXPECT_NEAR(area(r.points, r.triangles) / slab_area, 1.0, 0.03);
  EXPECT_GT(volume(r.points, r.triangles), 0.0);  // outward: the two sides did not swap
  for (size_t s : r.source_face) EXPECT_LT(s, slab.quads.size());
}
