// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/mesh/half_edges.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_crossing.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

#include "icosphere.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

using dthex::InputError;
using dthex::SurfaceStats;
using dthex::TriSurface;
using dthex::TriangleBvh;
using dthex::Vec3;
using dthex::VerifyOptions;
using dthex::verify_surface;

namespace {

//! Appends an axis-aligned cube [lo, lo + size]^3 with outward triangles.
void add_cube(TriSurface& s, const Vec3& lo, double size) {
  const int base = int(s.points.size());
  for (int i = 0; i < 8; ++i) s.points.push_back(lo + size * Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({base + q[0], base + q[1], base + q[2]});
    s.triangles.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

TriSurface cube(double size = 1.0) {
  TriSurface s;
  add_cube(s, Vec3::Zero(), size);
  return s;
}

void flip(TriSurface& s, size_t first = 0, size_t count = size_t(-1)) {
  for (size_t t = first; t < std::min(s.triangles.size(), first + count); ++t)
    std::swap(s.triangles[t][1], s.triangles[t][2]);
}

//! Appends a tetrahedron over existing point indices, outward.
void add_tet(TriSurface& s, std::array<int, 4> v) {
  const auto& P = s.points;
  const double volume = (P[size_t(v[1])] - P[size_t(v[0])])
                            .cross(P[size_t(v[2])] - P[size_t(v[0])])
                            .dot(P[size_t(v[3])] - P[size_t(v[0])]);
  if (volume < 0) std::swap(v[1], v[2]);
  s.triangles.push_back({v[0], v[2], v[1]});
  s.triangles.push_back({v[0], v[1], v[3]});
  s.triangles.push_back({v[0], v[3], v[2]});
  s.triangles.push_back({v[1], v[2], v[3]});
}

TriSurface tet_at(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  TriSurface s;
  s.points = {a, b, c, d};
  add_tet(s, {0, 1, 2, 3});
  return s;
}

TriSurface join(TriSurface a, const TriSurface& b) {
  const int base = int(a.points.size());
  a.points.insert(a.points.end(), b.points.begin(), b.points.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  return a;
}

TriSurface uv_sphere(int rings, int segments) {
  TriSurface s;
  s.points.push_back(Vec3(0, 0, 1));
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = M_PI * i / (rings + 1), phi = 2 * M_PI * j / segments;
      s.points.push_back(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  s.points.push_back(Vec3(0, 0, -1));
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

TriSurface torus(int n, int m, double R, double r) {
  TriSurface s;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      s.points.push_back(Vec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
    }
  auto at = [&](int i, int j) { return (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      s.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return s;
}

//! Expects verification to refuse with a message naming the rule and the element.
void expect_refused(TriSurface s, const std::string& rule, const std::string& element,
                    const dthex::VerifyOptions& options = {}) {
  try {
    verify_surface(s, "case.off", options);
    ADD_FAILURE() << "accepted, expected rule '" << rule << "'";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("case.off: " + rule + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(element), std::string::npos) << "missing '" << element << "' in: " << message;
  }
}

}  // namespace

TEST(VerifySurface, CubeStatistics) {
  TriSurface s = cube(2.0);
  const SurfaceStats stats = verify_surface(s, "cube");
  EXPECT_EQ(stats.vertices, 8u);
  EXPECT_EQ(stats.edges, 18u);
  EXPECT_EQ(stats.triangles, 12u);
  EXPECT_EQ(stats.components, 1u);
  EXPECT_EQ(stats.cavities, 0u);
  EXPECT_EQ(stats.genus, 0);
  EXPECT_EQ(stats.flipped_components, 0u);
  EXPECT_NEAR(stats.volume, 8.0, 1e-12);
  EXPECT_NEAR(stats.area, 24.0, 1e-12);
  EXPECT_NEAR(stats.bbox_diagonal, std::sqrt(12.0), 1e-12);
  EXPECT_EQ(stats.triangle_shape.count, 12u);
  EXPECT_NEAR(stats.triangle_shape.avg, 4 * std::sqrt(3.0) * 2 / (4 + 4 + 8), 1e-12);  // right isosceles
}

TEST(VerifySurface, RefusesEachRuleNamingTheFirstElement) {
  expect_refused(TriSurface{}, "empty", "no triangles");

  TriSurface nan_point = cube();
  nan_point.points[3].y() = std::nan("");
  expect_refused(nan_point, "non-finite coordinates", "vertex 3");
  TriSurface inf_point = cube();
  inf_point.points[5].z() = INFINITY;
  expect_refused(inf_point, "non-finite coordinates", "vertex 5");

  TriSurface out_of_range = cube();
  out_of_range.triangles[4][1] = 8;
  expect_refused(out_of_range, "face index out of range", "triangle 4");
  TriSurface negative = cube();
  negative.triangles[2][0] = -1;
  expect_refused(negative, "face index out of range", "triangle 2");

  TriSurface repeated = cube();
  repeated.triangles[6] = {1, 1, 5};
  expect_refused(repeated, "degenerate triangle", "triangle 6");
  TriSurface collinear = cube();
  collinear.points.push_back(Vec3(0.5, 0, 0));  // midpoint of edge 0-1
  collinear.triangles.push_back({0, 8, 1});
  expect_refused(collinear, "degenerate triangle", "triangle 12");

  TriSurface duplicate = cube();
  duplicate.triangles.push_back({duplicate.triangles[7][1], duplicate.triangles[7][2], duplicate.triangles[7][0]});
  expect_refused(duplicate, "duplicate triangles", "triangle 7");

  TriSurface open = cube();
  open.triangles.erase(open.triangles.begin() + 5);
  expect_refused(open, "open surface", "1 hole (loops of open boundary edges, 3 edges in all)");

  // Two tetrahedra sharing only the edge 0-1: that edge has four triangles.
  TriSurface edge_pair;
  edge_pair.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(0, 0, -1)};
  add_tet(edge_pair, {0, 1, 2, 3});
  add_tet(edge_pair, {0, 1, 4, 5});
  expect_refused(edge_pair, "non-manifold edge", "vertex 0 (0, 0, 0), vertex 1 (1, 0, 0)");

  // Two tetrahedra sharing only vertex 0 (a bow tie): every edge is fine, the vertex is not.
  TriSurface bow_tie;
  bow_tie.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(-1, 0, 0), Vec3(0, -1, 0),
                    Vec3(0, 0, -1)};
  add_tet(bow_tie, {0, 1, 2, 3});
  add_tet(bow_tie, {0, 4, 5, 6});
  expect_refused(bow_tie, "non-manifold vertex", "vertex 0 (0, 0, 0)");

  TriSurface one_flipped = cube();
  flip(one_flipped, 9, 1);
  expect_refused(one_flipped, "inconsistent orientation", "triangles ");

  // A doubly covered square with different diagonals: closed, manifold, consistent, flat;
  // each of its outer edges is a fold (the self-intersections come after).
  TriSurface flat;
  flat.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 0, 3}, {1, 3, 2}};
  expect_refused(flat, "folded edge", "4 edges where the surface folds back onto itself, first triangle 0");
  dthex::VerifyOptions no_intersections;
  no_intersections.check_self_intersections = false;
  expect_refused(flat, "zero volume", "component 0", no_intersections);
}

TEST(VerifySurface, RulesAreCheckedInOrder) {
  // Open and non-finite at once: the non-finite coordinate is reported first.
  TriSurface s = cube();
  s.triangles.pop_back();
  s.points[0].x() = std::nan("");
  expect_refused(s, "non-finite coordinates", "vertex 0");
}

TEST(VerifySurface, InwardCubeIsFlippedAndAccepted) {
  TriSurface s = cube(3.0);
  flip(s);
  const SurfaceStats stats = verify_surface(s, "inward");
  EXPECT_EQ(stats.flipped_components, 1u);
  EXPECT_NEAR(stats.volume, 27.0, 1e-12);
  // The repaired surface is outward: verifying again changes nothing.
  const SurfaceStats again = verify_surface(s, "again");
  EXPECT_EQ(again.flipped_components, 0u);
  EXPECT_NEAR(again.volume, 27.0, 1e-12);
}

TEST(VerifySurface, DisjointCubesAreTwoComponents) {
  TriSurface s;
  add_cube(s, Vec3(0, 0, 0), 1.0);
  add_cube(s, Vec3(3, 0, 0), 2.0);
  flip(s, 12, 12);  // the second one inward: repaired independently
  const SurfaceStats stats = verify_surface(s, "two");
  EXPECT_EQ(stats.components, 2u);
  EXPECT_EQ(stats.cavities, 0u);
  EXPECT_EQ(stats.flipped_components, 1u);
  EXPECT_EQ(stats.component_genus, (std::vector<int>{0, 0}));
  EXPECT_NEAR(stats.volume, 9.0, 1e-12);
}

TEST(VerifySurface, CubeWithCavity) {
  TriSurface s;
  add_cube(s, Vec3(0, 0, 0), 4.0);
  add_cube(s, Vec3(1, 1, 1), 2.0);  // given outward: must be turned to face into the cavity
  const SurfaceStats stats = verify_surface(s, "hollow");
  EXPECT_EQ(stats.components, 2u);
  EXPECT_EQ(stats.cavities, 1u);
  EXPECT_EQ(stats.flipped_components, 1u);
  EXPECT_NEAR(stats.volume, 64.0 - 8.0, 1e-12);
  // The inner cube's triangles now face inward toward the cavity centre (2, 2, 2).
  const auto& t = s.triangles[12];
  const Vec3 n = (s.points[size_t(t[1])] - s.points[size_t(t[0])]).cross(s.points[size_t(t[2])] - s.points[size_t(t[0])]);
  const Vec3 c = (s.points[size_t(t[0])] + s.points[size_t(t[1])] + s.points[size_t(t[2])]) / 3.0;
  EXPECT_GT(n.dot(Vec3(2, 2, 2) - c), 0.0);

  // An island inside the cavity (depth 2) is a body again: positive.
  add_cube(s, Vec3(1.5, 1.5, 1.5), 1.0);
  const SurfaceStats island = verify_surface(s, "island");
  EXPECT_EQ(island.components, 3u);
  EXPECT_EQ(island.cavities, 1u);
  EXPECT_NEAR(island.volume, 64.0 - 8.0 + 1.0, 1e-12);
}

TEST(VerifySurface, HandsOverItsSearchTreeOnlyWhileItFits) {
  std::unique_ptr<TriangleBvh> tree;
  VerifyOptions options;
  options.search_tree = &tree;
  // Verified as given: the tree is over exactly the verified points and triangles.
  TriSurface outward = cube(3.0);
  verify_surface(outward, "outward", options);
  ASSERT_TRUE(tree);
  EXPECT_EQ(tree->triangles(), outward.triangles);
  EXPECT_EQ(tree->points(), outward.points);
  EXPECT_NEAR(tree->closest_point(Vec3(1, 1, -2)).distance_sq, 4.0, 1e-12);
  // Flipped after the check: the tree's triangles face the other way, so none is given.
  TriSurface inward = cube(3.0);
  flip(inward);
  tree.reset();
  verify_surface(inward, "inward", options);
  EXPECT_FALSE(tree);
  // A vertex removed after the check renumbers the others: none either.
  TriSurface spare = cube(3.0);
  spare.points.insert(spare.points.begin(), Vec3(9, 9, 9));
  for (auto& t : spare.triangles)
    for (int& v : t) ++v;
  verify_surface(spare, "spare", options);
  EXPECT_EQ(spare.points.size(), 8u);
  EXPECT_FALSE(tree);
  // No check, no tree.
  options.check_self_intersections = false;
  TriSurface unchecked = cube(3.0);
  verify_surface(unchecked, "unchecked", options);
  EXPECT_FALSE(tree);
}

TEST(VerifySurface, TorusHasGenusOne) {
  TriSurface s = torus(24, 12, 2.0, 0.5);
  const SurfaceStats stats = verify_surface(s, "torus");
  EXPECT_EQ(stats.genus, 1);
  EXPECT_EQ(stats.component_genus, std::vector<int>{1});
  EXPECT_NEAR(stats.volume, 2 * M_PI * M_PI * 2.0 * 0.25, 0.1 * 2 * M_PI * M_PI * 2.0 * 0.25);
}

TEST(VerifySurface, UnreferencedVerticesAreDropped) {
  TriSurface s;
  s.points.push_back(Vec3(9, 9, 9));  // unused, before the cube
  add_cube(s, Vec3::Zero(), 1.0);
  s.points.push_back(Vec3(-9, 0, 0));  // unused, after
  const SurfaceStats stats = verify_surface(s, "spare");
  EXPECT_EQ(stats.unreferenced_vertices, 2u);
  EXPECT_EQ(s.points.size(), 8u);
  EXPECT_EQ(stats.vertices, 8u);
  EXPECT_NEAR(stats.volume, 1.0, 1e-12);
  EXPECT_TRUE(stats.bounds.isApprox(Eigen::AlignedBox3d(Vec3::Zero(), Vec3::Ones())));
}

TEST(VerifySurface, SelfIntersections) {
  TriSurface cubes;
  add_cube(cubes, Vec3(0, 0, 0), 1.0);
  add_cube(cubes, Vec3(0.5, 0.4, 0.3), 1.0);
  expect_refused(cubes, "self-intersection", "intersecting triangle pair");

  // A sphere whose north pole is pushed out through the south side.
  TriSurface sphere = uv_sphere(12, 16);
  ASSERT_NO_THROW({
    TriSurface copy = sphere;
    verify_surface(copy, "sphere");
  });
  sphere.points[0] = Vec3(0.05, 0.02, -1.4);
  expect_refused(sphere, "self-intersection", "triangle 0 ");

  const Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  const TriSurface base = tet_at(o, x, y, z);
  // An edge of the second tetrahedron pierces a face of the first.
  expect_refused(join(base, tet_at(Vec3(0.2, 0.2, -0.5), Vec3(0.25, 0.2, 0.5), Vec3(0.2, 0.3, -0.5), Vec3(0.3, 0.3, -0.6))),
                 "self-intersection", "triangle 0");
  // A vertex touching the inside of a face exactly (touching counts).
  expect_refused(join(base, tet_at(Vec3(0.25, 0.25, 0), Vec3(0, 0, -1), Vec3(1, 0, -1), Vec3(0, 1, -1))),
                 "self-intersection", "triangle");
  // Coplanar faces overlapping in the plane z = 0 (the tetrahedra lie on opposite sides).
  expect_refused(join(base, tet_at(Vec3(0.3, 0.3, 0), Vec3(1.3, 0.3, 0), Vec3(0.3, 1.3, 0), Vec3(0.3, 0.3, -1))),
                 "self-intersection", "triangle");
  // Triangles sharing exactly one vertex and crossing beyond it: in a triangular bipyramid
  // every pair of triangles shares a vertex, so only the shared-vertex test can see this.
  TriSurface bipyramid;
  bipyramid.points = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1)};
  bipyramid.triangles = {{3, 0, 1}, {3, 1, 2}, {3, 2, 0}, {4, 1, 0}, {4, 2, 1}, {4, 0, 2}};
  TriSurface valid = bipyramid;
  EXPECT_NO_THROW(verify_surface(valid, "bipyramid"));
  bipyramid.points[4] = Vec3(1.5, -1, 1.4);  // edge 4-2 now pierces triangle {3, 0, 1} (shared vertex 1)
  expect_refused(bipyramid, "self-intersection", "triangle 0 [3 (0.5, 0.5, 1), 0 (0, 0, 0), 1 (2, 0, 0)]");

  // The same shapes separated by a gap are fine: the test does not over-report.
  TriSurface apart = join(base, tet_at(Vec3(0.3, 0.3, -0.001), Vec3(1.3, 0.3, -0.001), Vec3(0.3, 1.3, -0.001),
                                       Vec3(0.3, 0.3, -1)));
  const SurfaceStats stats = verify_surface(apart, "apart");
  EXPECT_EQ(stats.components, 2u);
}

// On a big surface the pairs are searched on all cores, in parts: the count and the first
// pair named must be those of the search on one core. A small sphere with its pole pushed
// through (384 triangles, searched on one core) is copied 60 times side by side (23,040
// triangles): 60 times the pairs, the same first pair.
TEST(VerifySurface, SelfIntersectionsAreCountedAlikeOnAllCores) {
  auto refusal = [](TriSurface s) {
    try {
      verify_surface(s, "case.off");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  TriSurface small = uv_sphere(12, 16);
  small.points[0] = Vec3(0.05, 0.02, -1.4);
  TriSurface many = small;
  for (int copy = 1; copy < 60; ++copy) {
    TriSurface moved = small;
    for (Vec3& p : moved.points) p += Vec3(4.0 * (copy % 8), 4.0 * (copy / 8), 0);
    many = join(many, moved);
  }
  ASSERT_GT(many.triangles.size(), 20000u);
  const std::string alone = refusal(small);
  const std::string prefix = "case.off: self-intersection: ";
  ASSERT_EQ(alone.rfind(prefix, 0), 0u) << alone;
  const size_t pairs = std::stoul(alone.substr(prefix.size()));
  const std::string rest = alone.substr(alone.find(" intersecting triangle pairs, first triangle 0 "));
  ASSERT_GT(pairs, 1u);
  EXPECT_EQ(refusal(many), prefix + std::to_string(60 * pairs) + rest);
}

TEST(VerifySurface, AnOpenSurfaceNamesItsHolesAndTheToolsThatCloseThem) {
  // A sphere with one triangle removed near the north pole and one near the south pole.
  TriSurface s = uv_sphere(12, 16);
  const size_t north = 20, south = s.triangles.size() - 40;
  const Vec3 hole_vertex = s.points[size_t(std::min({s.triangles[south][0], s.triangles[south][1], s.triangles[south][2]}))];
  double south_length = 0;
  for (int k = 0; k < 3; ++k)
    south_length += (s.points[size_t(s.triangles[south][size_t(k)])] - s.points[size_t(s.triangles[south][size_t((k + 1) % 3)])]).norm();
  s.triangles.erase(s.triangles.begin() + long(south));
  s.triangles.erase(s.triangles.begin() + long(north));
  try {
    verify_surface(s, "case.off");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("case.off: open surface: 2 holes (loops of open boundary edges, 6 edges in all): ", 0), 0u)
        << message;
    EXPECT_NE(message.find("hole 1 of 3 edges, length "), std::string::npos) << message;
    EXPECT_NE(message.find("hole 2 of 3 edges, length "), std::string::npos) << message;
    EXPECT_EQ(message.find("hole 3"), std::string::npos) << message;
    // The second hole (in edge order, the south one's vertices have higher ids) is named by
    // its length and a vertex on it.
    std::ostringstream length;
    length.precision(6);
    length << south_length;
    EXPECT_NE(message.find("hole 2 of 3 edges, length " + length.str() + ", at vertex "), std::string::npos) << message;
    std::ostringstream place;
    place.precision(10);
    place << "(" << hole_vertex.x() << ", " << hole_vertex.y() << ", " << hole_vertex.z() << ")";
    EXPECT_NE(message.find(place.str()), std::string::npos) << message;
    EXPECT_NE(message.find("belongs only to triangle"), std::string::npos) << message;
    EXPECT_NE(message.find("MeshLab (Close Holes), PyMeshFix or Blender (Fill Holes)"), std::string::npos) << message;
  }
}

TEST(VerifySurface, ASelfIntersectionNamesTheFirstPairsWithAPointOfEach) {
  // Two unit cubes, the second shifted by (0.5, 0.4, 0.3): they cross along a closed curve.
  TriSurface cubes;
  add_cube(cubes, Vec3(0, 0, 0), 1.0);
  add_cube(cubes, Vec3(0.5, 0.4, 0.3), 1.0);
  std::string message;
  try {
    verify_surface(cubes, "case.off");
  } catch (const InputError& e) {
    message = e.what();
  }
  ASSERT_FALSE(message.empty());
  const size_t listed = message.find("the first 5 pairs: ");
  ASSERT_NE(listed, std::string::npos) << message;
  // Each pair named is of a triangle of each cube (0-11, 12-23), at a point on both.
  const std::regex pair("(\\d+) and (\\d+) at \\(([-0-9.e]+), ([-0-9.e]+), ([-0-9.e]+)\\)");
  const std::string list = message.substr(listed);
  int named = 0;
  for (auto it = std::sregex_iterator(list.begin(), list.end(), pair); it != std::sregex_iterator(); ++it) {
    const int a = std::stoi((*it)[1]), b = std::stoi((*it)[2]);
    const Vec3 p(std::stod((*it)[3]), std::stod((*it)[4]), std::stod((*it)[5]));
    EXPECT_LT(a, 12);
    EXPECT_GE(b, 12);
    // On the boundary of both cubes: of the first, each coordinate in [0, 1] and one at 0 or 1.
    const Vec3 q = p - Vec3(0.5, 0.4, 0.3);
    auto on_cube = [](const Vec3& x) {
      const double inside = std::max({-x.minCoeff(), x.maxCoeff() - 1});
      const double face = std::min({x.cwiseAbs().minCoeff(), (x - Vec3::Ones()).cwiseAbs().minCoeff()});
      return inside <= 1e-9 && face <= 1e-9;
    };
    EXPECT_TRUE(on_cube(p) && on_cube(q)) << (*it)[0];
    ++named;
  }
  EXPECT_EQ(named, 5) << message;
  EXPECT_NE(message.find("MeshLab (Select Self Intersecting Faces"), std::string::npos) << message;
  EXPECT_NE(message.find("PyMeshFix"), std::string::npos) << message;
}

TEST(VerifySurface, BodiesCloserThanTheTetMesherCanTellApartAreRefusedNamingBoth) {
  // Two unit cubes side by side, 1e-9 apart: not intersecting, and far below 1e-6 of the
  // diagonal (about 2.4).
  TriSurface near;
  add_cube(near, Vec3(0, 0, 0), 1.0);
  add_cube(near, Vec3(1 + 1e-9, 0, 0), 1.0);
  std::string message;
  try {
    TriSurface copy = near;
    verify_surface(copy, "case.off");
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_EQ(message.rfind("case.off: bodies too close: component 0 (12 triangles, here triangle ", 0), 0u) << message;
  EXPECT_NE(message.find(") and component 1 (12 triangles, here triangle "), std::string::npos) << message;
  EXPECT_NE(message.find(" are 1e-09 apart at (1, "), std::string::npos) << message;
  EXPECT_NE(message.find("move one away from the other, or merge them"), std::string::npos) << message;
  EXPECT_NE(message.find("boolean union"), std::string::npos) << message;
  // The named triangles reach the facing sides (x = 1 of the first, x = 1 + 1e-9 of the second).
  const std::regex ids("here triangle (\\d+)\\) and component 1 \\(12 triangles, here triangle (\\d+)\\)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(message, m, ids)) << message;
  for (int k : {1, 2}) {
    const auto& t = near.triangles[size_t(std::stoi(m[size_t(k)]))];
    double nearest = 1;
    for (int v : t) nearest = std::min(nearest, std::abs(near.points[size_t(v)].x() - 1.0));
    EXPECT_LT(nearest, 1e-8) << message;
  }
  // 1e-3 apart they are two bodies; with the check off, 1e-9 too.
  TriSurface apart;
  add_cube(apart, Vec3(0, 0, 0), 1.0);
  add_cube(apart, Vec3(1 + 1e-3, 0, 0), 1.0);
  EXPECT_EQ(verify_surface(apart, "apart").components, 2u);
  VerifyOptions unchecked;
  unchecked.near_contact_tolerance = 0;
  EXPECT_EQ(verify_surface(near, "near", unchecked).components, 2u);
}

TEST(VerifySurface, ACavityNearlyTouchingItsBodyIsTooClose) {
  TriSurface s;
  add_cube(s, Vec3(0, 0, 0), 3.0);
  add_cube(s, Vec3(1, 1, 1e-8), 1.0);  // a cavity whose bottom is 1e-8 above the body's
  flip(s, 12, 12);
  expect_refused(s, "bodies too close", "component 0 (12 triangles");
}

TEST(VerifySurface, FoldedAdjacentTrianglesAreRefusedAsAFold) {
  // A square pyramid; then its apex is moved into the base plane, inside the base, so each
  // side triangle folds flat onto the base triangle it shares an edge with.
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0), Vec3(1, 1, -1)};
  s.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  TriSurface ok = s;
  EXPECT_NO_THROW(verify_surface(ok, "pyramid"));
  s.points[4] = Vec3(1, 0.5, 0);
  // The lowest pair: base triangle 0 and side 2 on edge 0-1, exactly on each other.
  expect_refused(s, "folded edge", "4 edges where the surface folds back onto itself, first triangle 0 ");
  expect_refused(s, "folded edge", "triangle 2 [0 (0, 0, 0), 1 (2, 0, 0), 4 (1, 0.5, 0)] on their shared edge");
  expect_refused(s, "folded edge", "their sides 0 degrees apart");
}

TEST(VerifySurface, TheFoldsOfALargeSurfaceAreCountedAndTheLowestNamedOnBothCores) {
  // An icosphere of 20,480 triangles (the pass runs on both cores from 20,000) with a fold
  // made at two places far apart: across edge k of triangle t, the other triangle's third
  // vertex is moved onto t's centroid, so that triangle lies flat on t. The lowest pair
  // (triangle 0's, across its edge 1-2) lies late in the edges' order, the other (triangle
  // 20000's, across its edge 0-1) early: each core's share finds one.
  TriSurface s = dthex::from_openmesh(dthex_test::openmesh_icosphere<dthex::SurfaceMesh>(5));
  ASSERT_EQ(s.triangles.size(), 20480u);
  for (const auto& [t, k] : {std::pair{20000, 0}, std::pair{0, 1}}) {
    const auto tri = s.triangles[size_t(t)];
    const int u = tri[size_t(k)], w = tri[size_t((k + 1) % 3)], third = tri[size_t((k + 2) % 3)];
    for (const auto& other : s.triangles) {
      const bool across = std::count(other.begin(), other.end(), u) && std::count(other.begin(), other.end(), w) &&
                          !std::count(other.begin(), other.end(), third);
      if (!across) continue;
      for (int v : other)
        if (v != u && v != w)
          s.points[size_t(v)] = (s.points[size_t(tri[0])] + s.points[size_t(tri[1])] + s.points[size_t(tri[2])]) / 3;
      break;
    }
  }
  // What one core finds, edge by edge: the count and the lowest pair.
  size_t folded = 0;
  std::array<int, 2> lowest{-1, -1};
  const auto half_edges = dthex::sorted_half_edges(s.triangles);
  auto corners = [&](int t) {
    const auto& tri = s.triangles[size_t(t)];
    return std::array<Vec3, 3>{s.points[size_t(tri[0])], s.points[size_t(tri[1])], s.points[size_t(tri[2])]};
  };
  for (size_t k = 0; k < half_edges.size(); k += 2) {
    const int a = half_edges[k].triangle, b = half_edges[k + 1].triangle;
    if (!dthex::triangles_fold_onto_each_other(corners(a), corners(b))) continue;
    ++folded;
    const std::array<int, 2> pair{std::min(a, b), std::max(a, b)};
    if (lowest[0] < 0 || pair < lowest) lowest = pair;
  }
  ASSERT_GE(folded, 2u);
  expect_refused(s, "folded edge", std::to_string(folded) + " edges where the surface folds back onto itself, first triangle " +
                                       std::to_string(lowest[0]) + " [");
  expect_refused(s, "folded edge", " and triangle " + std::to_string(lowest[1]) + " [");
}

TEST(VerifySurface, ANearlyFoldedFinIsRefusedAsTheCoarseningWouldRefuseIt) {
  // The pyramid flattened until its sides are within 2e-7 radians of its base: not a
  // self-intersection (no two triangles overlap), but a fin the coarsening's check refuses
  // at every eps; the input's own check must say so, not let the run fail after minutes.
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0), Vec3(1, 0.5, -1e-7)};
  s.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  // The coarsening's own test flags its folds.
  EXPECT_FALSE(self_intersections(s).empty());
  expect_refused(s, "folded edge", "edges where the surface folds back onto itself, first triangle 0 ");
  // The lowest pair, triangles 0 and 2 on edge 0-1: their sides 1e-7 / 0.5 radians apart.
  expect_refused(s, "folded edge", "and triangle 2 [0 (0, 0, 0), 1 (2, 0, 0), 4 (1, 0.5, -1e-07)]");
  expect_refused(s, "folded edge", "their sides 1.1e-05 degrees apart");
  // With the apex 1e-3 below, the sides are at least 0.038 degrees apart: a thin wedge, but
  // not a fold, and neither check refuses it.
  s.points[4].z() = -1e-3;
  EXPECT_TRUE(self_intersections(s).empty());
  EXPECT_NO_THROW(verify_surface(s, "wedge"));
}

namespace {

struct SourceRow {
  size_t triangles = 0, vertices = 0, components = 0;
  int genus = -1;
};

//! Rows of the SOURCES.md table: file, triangles, vertices, components and "genus N" in the notes.
std::map<std::string, SourceRow> read_sources(const std::string& path) {
  std::map<std::string, SourceRow> rows;
  std::ifstream in(path);
  std::string line;
  const std::regex genus_re("genus (\\d+)");
  while (std::getline(in, line)) {
    if (line.rfind("| ", 0) != 0 || line.find(".off") == std::string::npos) continue;
    std::vector<std::string> cells;
    std::stringstream cells_in(line.substr(1));
    std::string cell;
    while (std::getline(cells_in, cell, '|')) cells.push_back(cell);
    if (cells.size() < 10) continue;
    auto trim = [](std::string s) {
      s.erase(0, s.find_first_not_of(' '));
      s.erase(s.find_last_not_of(' ') + 1);
      return s;
    };
    SourceRow row;
    row.triangles = std::stoul(trim(cells[2]));
    row.vertices = std::stoul(trim(cells[3]));
    row.components = std::stoul(trim(cells[5]));
    std::smatch match;
    if (std::regex_search(cells[9], match, genus_re)) row.genus = std::stoi(match[1]);
    rows[trim(cells[0])] = row;
  }
  return rows;
}

//! Verifies every .off in folder and compares with the expected rows (file -> row).
void verify_folder(const std::string& folder, const std::map<std::string, SourceRow>& rows) {
  size_t checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".off") continue;
    const std::string file = entry.path().filename().string();
    SCOPED_TRACE(file);
    TriSurface s = dthex::read_surface(entry.path().string());
    SurfaceStats stats;
    ASSERT_NO_THROW(stats = verify_surface(s, file));
    EXPECT_GT(stats.volume, 0.0);
    EXPECT_EQ(stats.cavities, 0u);
    const auto row = rows.find(file);
    if (row != rows.end()) {
      if (row->second.triangles) EXPECT_EQ(stats.triangles, row->second.triangles);
      if (row->second.vertices) EXPECT_EQ(stats.vertices, row->second.vertices);
      EXPECT_EQ(stats.components, row->second.components);
      ASSERT_GE(row->second.genus, 0) << "SOURCES.md states no genus";
      EXPECT_EQ(stats.genus, row->second.genus);
      ++checked;
    } else {
      EXPECT_EQ(stats.genus, 0);  // calibration shapes (sphere, icosahedron)
      EXPECT_EQ(stats.components, 1u);
    }
    if (file == "heart.off") EXPECT_EQ(stats.flipped_components, 1u);  // inward in the source
    else EXPECT_EQ(stats.flipped_components, 0u);
  }
  EXPECT_GE(checked, 5u);
}

}  // namespace

TEST(VerifySurface, BundledMeshesVerifyWithTheirDocumentedTopology) {
  // The bundled SOURCES.md lists no topology; these rows are transcribed from the shared
  // collection's SOURCES.md (the same files, copied unchanged).
  std::map<std::string, SourceRow> rows = {
      {"femur_proximal_ct.off", {72868, 36436, 1, 0}}, {"vertebra_L1.off", {8052, 4026, 1, 1}},
      {"heart.off", {15552, 7778, 1, 0}},             {"liver.off", {2336, 1170, 1, 0}},
      {"spot.off", {5856, 2930, 1, 0}},               {"sphere728.off", {728, 366, 1, 0}},
      {"icosahedron.off", {20, 12, 1, 0}}};
  if (std::filesystem::exists(DTHEX_SHARED_DIR "/meshes/SOURCES.md"))
    for (const auto& [file, row] : read_sources(DTHEX_SHARED_DIR "/meshes/SOURCES.md")) rows[file] = row;
  verify_folder(DTHEX_SOURCE_DIR "/meshes", rows);
}

TEST(VerifySurface, SharedMeshesVerifyWithTheirDocumentedTopology) {
  if (!std::filesystem::exists(DTHEX_SHARED_DIR "/meshes/SOURCES.md")) GTEST_SKIP() << "no shared meshes";
  const auto rows = read_sources(DTHEX_SHARED_DIR "/meshes/SOURCES.md");
  EXPECT_GE(rows.size(), 11u);
  verify_folder(DTHEX_SHARED_DIR "/meshes", rows);
}
