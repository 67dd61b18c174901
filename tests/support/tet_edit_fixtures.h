// SPDX-License-Identifier: MIT
// Checks and a small mesh shared by the tests of the tet-mesh edits done before THex
// (remove_boundary_edges, flip_three_tet_edges, split_surface_tets).
#pragma once

#include <dthex/io/read_surface.h>
#include <dthex/mesh/types.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tetrahedralize.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

namespace dthex::tet_fixtures {

inline double signed_volume(const TetMesh& m, const std::array<int, 4>& t) {
  const Vec3& a = m.points[size_t(t[0])];
  return (m.points[size_t(t[1])] - a).dot((m.points[size_t(t[2])] - a).cross(m.points[size_t(t[3])] - a)) / 6.0;
}

inline std::array<int, 3> sorted_face(const std::array<int, 4>& t, int skip) {
  std::array<int, 3> key{};
  for (int i = 0, k = 0; i < 4; ++i)
    if (i != skip) key[size_t(k++)] = t[size_t(i)];
  std::sort(key.begin(), key.end());
  return key;
}

// Every interior triangle is shared by exactly two tets, every boundary face by one: the tet
// mesh is conforming and its boundary is the given faces.
inline void expect_conforming(const TetMesh& m) {
  std::map<std::array<int, 3>, int> uses;
  for (const auto& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) ++uses[sorted_face(t, skip)];
  size_t boundary = 0;
  for (const auto& [key, n] : uses) {
    ASSERT_LE(n, 2);
    if (n == 1) ++boundary;
  }
  EXPECT_EQ(boundary, m.boundary_faces.size());
  for (const auto& f : m.boundary_faces) {
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    EXPECT_EQ(uses[key], 1);
  }
}

// Conforming, every tet positive and the volume what it was: the mesh is a valid
// triangulation of the same domain with the same boundary.
inline void expect_valid(const TetMesh& m, double volume) {
  double total = 0;
  for (const auto& t : m.tets) {
    EXPECT_GT(signed_volume(m, t), 0);
    total += signed_volume(m, t);
  }
  EXPECT_NEAR(total, volume, 1e-9 * volume);
  expect_conforming(m);
}

// The bundled vertebra coarsened and tet-meshed at the defaults, its interior edges between
// boundary vertices already gone (coned, then flipped or split), as the pipeline hands it on.
inline TetMesh coarse_vertebra_without_boundary_edges() {
  TriSurface coarse = coarsen(read_surface(DTHEX_SOURCE_DIR "/meshes/vertebra_L1.off")).surface;
  verify_surface(coarse, "coarse vertebra");
  TetMesh tets = tetrahedralize(coarse);
  cone_edge_clusters(tets);
  remove_boundary_edges(tets);
  return tets;
}

// The same vertebra one step on, as THex would get it before the worst-tet edits: three-tet
// edges flipped, interior points merged, surface tets split.
inline TetMesh coarse_vertebra_before_worst_tet_edits() {
  TetMesh tets = coarse_vertebra_without_boundary_edges();
  flip_three_tet_edges(tets);
  collapse_interior_vertices(tets);
  split_surface_tets(tets);
  return tets;
}

inline double total_volume(const TetMesh& m) {
  double v = 0;
  for (const auto& t : m.tets) v += signed_volume(m, t);
  return v;
}

// Interior edges and interior faces whose vertices are all boundary vertices.
struct BadEntities {
  size_t edges = 0, faces = 0;
};
inline BadEntities bad_entities(const TetMesh& m) {
  std::vector<char> on_boundary(m.points.size(), 0);
  std::set<std::pair<int, int>> boundary_edges;
  std::set<std::array<int, 3>> boundary_faces;
  for (const auto& f : m.boundary_faces) {
    for (int i = 0; i < 3; ++i) {
      on_boundary[size_t(f[size_t(i)])] = 1;
      boundary_edges.insert(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
    }
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    boundary_faces.insert(key);
  }
  std::set<std::pair<int, int>> edges;
  std::set<std::array<int, 3>> faces;
  for (const auto& t : m.tets) {
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const std::pair<int, int> e = std::minmax(t[size_t(i)], t[size_t(j)]);
        if (on_boundary[size_t(e.first)] && on_boundary[size_t(e.second)] && !boundary_edges.count(e)) edges.insert(e);
      }
    for (int skip = 0; skip < 4; ++skip) {
      const auto key = sorted_face(t, skip);
      if (on_boundary[size_t(key[0])] && on_boundary[size_t(key[1])] && on_boundary[size_t(key[2])] &&
          !boundary_faces.count(key))
        faces.insert(key);
    }
  }
  return {edges.size(), faces.size()};
}

// Adds tet (a, b, c, d), swapping c and d if that is needed to make it positive.
inline void add_positive(TetMesh& m, int a, int b, int c, int d) {
  std::array<int, 4> t{a, b, c, d};
  if (signed_volume(m, t) < 0) std::swap(t[2], t[3]);
  m.tets.push_back(t);
}

// Three tets around the edge p-q from the bottom apex p to the top apex q, with ring r0 r1
// r2; r0 is an interior vertex: four more tets join the faces at r0 to a vertex s beyond it.
// The boundary is the hull of p, q, r1, r2 and s, and p-q runs through the interior.
enum { P = 0, Q, R0, R1, R2, S };
inline TetMesh edge_with_an_interior_ring_vertex(bool r0_interior = true) {
  TetMesh m;
  m.points = {{0, 0, -1}, {0, 0, 1}, {0.6, 0, 0}, {-0.5, 0.87, 0}, {-0.5, -0.87, 0}, {2, 0, 0}};
  add_positive(m, P, Q, R0, R1);
  add_positive(m, P, Q, R1, R2);
  add_positive(m, P, Q, R2, R0);
  if (r0_interior) {
    add_positive(m, S, P, R0, R1);
    add_positive(m, S, Q, R0, R1);
    add_positive(m, S, P, R2, R0);
    add_positive(m, S, Q, R2, R0);
    m.boundary_faces = {{P, R2, R1}, {Q, R1, R2}, {S, R1, P}, {S, Q, R1}, {S, R2, Q}, {S, P, R2}};
  } else {
    m.points.pop_back();
    m.boundary_faces = {{P, R2, R1}, {Q, R1, R2}, {P, R1, R0}, {Q, R0, R1}, {P, R0, R2}, {Q, R2, R0}};
  }
  m.boundary_face_source.resize(m.boundary_faces.size(), 0);
  return m;
}

}  // namespace dthex::tet_fixtures
