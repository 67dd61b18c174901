// SPDX-License-Identifier: MIT
#include <dthex/mesh/surface_mesh.h>

#include <dthex/modules/ModCurvatureSizingT.hh>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <limits>
#include <random>
#include <set>

using namespace dthex;

namespace {

//! Icosphere of the given radius: icosahedron, each triangle split in 4, `levels` times.
SurfaceMesh icosphere(double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[size_t(a)] + p[size_t(b)]) / 2);
      return mid[key] = int(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f = g;
  }
  for (Vec3& q : p) q = q.normalized() * radius;
  return to_openmesh(TriSurface{p, f});
}

//! Regular grid with n x n quads over [0, size]^2, z = height(x, y), quads split along a diagonal.
template <class Height>
SurfaceMesh grid(int n, double size, Height height) {
  TriSurface s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = size * i / n, y = size * j / n;
      s.points.push_back({x, y, height(x, y)});
    }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return to_openmesh(s);
}

//! Open tube of radius r along z: rings of m vertices, quads split along a diagonal.
SurfaceMesh cylinder(double r, int m, int rings, double height) {
  TriSurface s;
  for (int k = 0; k < rings; ++k)
    for (int i = 0; i < m; ++i) {
      const double phi = 2 * M_PI * i / m;
      s.points.push_back({r * std::cos(phi), r * std::sin(phi), height * k / (rings - 1)});
    }
  for (int k = 0; k + 1 < rings; ++k)
    for (int i = 0; i < m; ++i) {
      const int a = k * m + i, b = k * m + (i + 1) % m, c = a + m, d = b + m;
      s.triangles.push_back({a, b, d});
      s.triangles.push_back({a, d, c});
    }
  return to_openmesh(s);
}

}  // namespace

TEST(CurvatureSizing, SphereRadiusWithinFivePercentEverywhere) {
  const double r = 2.5;
  const SurfaceMesh mesh = icosphere(r, 3);
  const auto rho = osculating_radii(mesh);
  ASSERT_EQ(rho.size(), mesh.n_vertices());
  for (double x : rho) EXPECT_NEAR(x, r, 0.05 * r);
}

TEST(CurvatureSizing, SphereSizingIsAlphaTimesRadius) {
  const double r = 1.0;
  const SurfaceMesh mesh = icosphere(r, 3);
  CurvatureSizingOptions options;
  options.eps = 0.1;
  options.h_min = 1e-3;
  options.h_max = 100;
  const auto h = curvature_sizing(mesh, options);
  for (double x : h) EXPECT_NEAR(x, sizing_alpha(0.1) * r, 0.05 * sizing_alpha(0.1) * r);
}

TEST(CurvatureSizing, ChordOfAlphaRhoHasSagittaEpsRho) {
  for (double eps : {0.01, 0.1, 0.5}) {
    const double rho = 3.0, chord = sizing_alpha(eps) * rho;
    const double sagitta = rho - std::sqrt(rho * rho - chord * chord / 4);
    EXPECT_NEAR(sagitta, eps * rho, 1e-12);
  }
}

TEST(CurvatureSizing, PlaneGetsHmax) {
  const SurfaceMesh mesh = grid(10, 5.0, [](double, double) { return 1.0; });
  CurvatureSizingOptions options;
  options.h_min = 0.1;
  options.h_max = 3.0;
  const auto h = curvature_sizing(mesh, options);
  for (double x : h) EXPECT_DOUBLE_EQ(x, 3.0);
  const auto [h_min_auto, h_max_auto] = sizing_bounds(mesh, CurvatureSizingOptions{});
  EXPECT_NEAR(h_max_auto, 0.5 * std::sqrt(50.0), 1e-12);  // half the bbox diagonal
  EXPECT_GT(h_min_auto, 0.5);                              // the mean edge (edges 0.5 and 0.71)
  EXPECT_LT(h_min_auto, 0.71);
}

TEST(CurvatureSizing, CylinderRadiusAcrossInfiniteAlong) {
  const double r = 1.5;
  const SurfaceMesh mesh = cylinder(r, 48, 12, 4.0);
  const auto rho = osculating_radii(mesh);
  for (double x : rho) EXPECT_NEAR(x, r, 1e-9 * r);
  // Along the axis the edge is tangent: infinite radius, so h = h_max there.
  const auto v = mesh.vertex_handle(48 * 5);
  const auto n = vertex_normal(mesh, v);
  const auto up = mesh.point(mesh.vertex_handle(48 * 6));
  EXPECT_TRUE(std::isinf(osculating_radius(mesh.point(v), n, up)));
  const auto around = mesh.point(mesh.vertex_handle(48 * 5 + 1));
  EXPECT_NEAR(osculating_radius(mesh.point(v), n, around), r, 1e-9);
}

TEST(CurvatureSizing, GradationLimitsJumpsAndOnlyLowers) {
  const SurfaceMesh mesh = grid(20, 10.0, [](double, double) { return 0.0; });
  std::vector<double> h(mesh.n_vertices(), 5.0);
  h[220] = 0.1;  // centre vertex (10, 10) of the 21 x 21 grid
  const auto before = h;
  limit_gradation(mesh, h, 0.5);
  for (size_t i = 0; i < h.size(); ++i) EXPECT_LE(h[i], before[i]);
  for (auto e : mesh.edges()) {
    const auto a = mesh.to_vertex_handle(mesh.halfedge_handle(e, 0));
    const auto b = mesh.to_vertex_handle(mesh.halfedge_handle(e, 1));
    EXPECT_LE(std::fabs(h[size_t(a.idx())] - h[size_t(b.idx())]), 0.5 * mesh.calc_edge_length(e) + 1e-12);
  }
  EXPECT_DOUBLE_EQ(h[221], 0.1 + 0.5 * 0.5);  // neighbour at distance 0.5
  EXPECT_NEAR(h[0], 0.1 + 0.5 * std::sqrt(50.0), 1e-12);  // along the diagonal edges
  EXPECT_DOUBLE_EQ(h[20], 5.0);  // corner (10, 0): path length 10, 0.1 + 5 > 5, unchanged
}

// The gradation's fixed point by plain sweeps (Bellman-Ford): every edge relaxed until no
// size falls. limit_gradation (Dijkstra, only some vertices queued) must end at the same
// sizes bit for bit.
std::vector<double> gradation_by_sweeps(const SurfaceMesh& mesh, std::vector<double> h, double beta) {
  for (bool changed = true; changed;) {
    changed = false;
    for (auto v : mesh.vertices())
      for (auto q : mesh.vv_range(v)) {
        const double candidate = h[size_t(v.idx())] + beta * (mesh.point(q) - mesh.point(v)).norm();
        if (candidate < h[size_t(q.idx())]) h[size_t(q.idx())] = candidate, changed = true;
      }
  }
  return h;
}

TEST(CurvatureSizing, GradationEqualsItsFixedPointBitForBit) {
  // Sizes of every scale at random (a few tiny, most clamped at one large value, as on a
  // fine input), on a mesh small enough for one core and on one above the parallel size.
  for (int levels : {3, 7}) {
    const SurfaceMesh mesh = icosphere(2.0, levels);
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<double> h(mesh.n_vertices());
    for (double& x : h) {
      const double u = uniform(random);
      x = u < 0.01 ? 1e-3 * uniform(random) : u < 0.3 ? 0.5 * uniform(random) : 1.0;
    }
    const std::vector<double> expected = gradation_by_sweeps(mesh, h, 0.5);
    limit_gradation(mesh, h, 0.5);
    size_t lowered = 0, differ = 0;
    for (size_t v = 0; v < h.size(); ++v) {
      differ += h[v] != expected[v];
      lowered += expected[v] < 1.0;
    }
    EXPECT_EQ(differ, 0u) << levels << " levels";
    EXPECT_GT(lowered, h.size() / 2);  // the test lowers most sizes, through long chains
  }
}

TEST(CurvatureSizing, GradationOfSignedSizesEqualsItsFixedPointBitForBit) {
  // The queue orders sizes by their bits: negative sizes, both zeros and infinities must come
  // out in the order of their values, or the sizes would differ from the fixed point.
  const SurfaceMesh mesh = icosphere(1.0, 4);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> h(mesh.n_vertices());
  for (double& x : h) x = uniform(random);
  h[0] = -0.0, h[1] = 0.0, h[2] = std::numeric_limits<double>::infinity(), h[3] = -3.0;
  const std::vector<double> expected = gradation_by_sweeps(mesh, h, 0.25);
  limit_gradation(mesh, h, 0.25);
  size_t differ = 0;
  for (size_t v = 0; v < h.size(); ++v) differ += std::memcmp(&h[v], &expected[v], sizeof(double)) != 0;
  EXPECT_EQ(differ, 0u);
  EXPECT_LT(h[2], 0.0);  // the infinite size fell below zero through its neighbours
}

TEST(CurvatureSizing, LargeMeshGetsEveryRadiusAtItsOwnVertex) {
  // 163,842 vertices: above the size from which the radii are computed on all cores. Every
  // vertex gets its own radius (about the sphere's), written at its own index:
  // the radius of a vertex depends on its one-ring only, so a vertex moved far away changes
  // its own radius and its neighbours' only.
  SurfaceMesh mesh = icosphere(2.0, 7);
  ASSERT_GE(mesh.n_vertices(), 65536u);
  const std::vector<double> rho = osculating_radii(mesh);
  ASSERT_EQ(rho.size(), mesh.n_vertices());
  for (double r : rho) ASSERT_NEAR(r, 2.0, 0.1);
  const auto moved = mesh.vertex_handle(100000);
  mesh.set_point(moved, mesh.point(moved) * 1.01);
  const std::vector<double> again = osculating_radii(mesh);
  std::set<int> ring{moved.idx()};
  for (auto q : mesh.vv_range(moved)) ring.insert(q.idx());
  size_t changed = 0;
  for (size_t v = 0; v < rho.size(); ++v) {
    if (ring.count(int(v))) continue;
    changed += again[v] != rho[v];
  }
  EXPECT_EQ(changed, 0u);
  EXPECT_NE(again[size_t(moved.idx())], rho[size_t(moved.idx())]);
}
