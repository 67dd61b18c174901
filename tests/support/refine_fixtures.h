// SPDX-License-Identifier: MIT
// Small procedural meshes shared by the THex, dicing and conformity tests.
#pragma once

#include <dthex/io/read_surface.h>
#include <dthex/mesh/types.h>

#include <array>
#include <cmath>
#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

namespace dthex::fixtures {

inline TriSurface read_off(const std::string& path) { return read_surface(path); }

//! The 20 tets joining a closed convex surface's triangles to one centre node
//! (the paper's icosahedron sphere), with the triangles as boundary faces.
inline TetMesh cone_to_centre(const TriSurface& s) {
  TetMesh m;
  m.points = s.points;
  Vec3 centre = Vec3::Zero();
  for (const auto& p : s.points) centre += p;
  centre /= double(s.points.size());
  m.points.push_back(centre);
  const int c = int(s.points.size());
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    auto t = s.triangles[i];
    const double vol = (m.points[size_t(t[1])] - m.points[size_t(t[0])])
                           .cross(m.points[size_t(t[2])] - m.points[size_t(t[0])])
                           .dot(centre - m.points[size_t(t[0])]);
    // The centre is inside: an outward triangle (a,b,c) makes (a,c,b,centre) positive.
    if (vol < 0) m.tets.push_back({t[0], t[2], t[1], c}); else m.tets.push_back({t[0], t[1], t[2], c});
    std::array<int, 3> f = vol < 0 ? t : std::array<int, 3>{t[0], t[2], t[1]};
    m.boundary_faces.push_back(f);
    m.boundary_face_source.push_back(int(i));
  }
  return m;
}

//! A regular tet, positively oriented.
inline TetMesh regular_tet() {
  TetMesh m;
  m.points = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
  m.tets = {{0, 1, 2, 3}};
  if ((m.points[1] - m.points[0]).cross(m.points[2] - m.points[0]).dot(m.points[3] - m.points[0]) < 0)
    m.tets = {{0, 2, 1, 3}};
  return m;
}

//! An nx x ny x nz block of unit cubes, each cut into 6 tets (Kuhn), boundary faces
//! outward with their own index as source.
inline TetMesh kuhn_block(int nx, int ny, int nz) {
  TetMesh m;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points.push_back(Vec3(i, j, k));
  // The 6 monotone paths from (0,0,0) to (1,1,1) through the cube.
  const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& path : paths) {
          int p[3] = {i, j, k};
          std::array<int, 4> t;
          t[0] = id(p[0], p[1], p[2]);
          for (int s = 0; s < 3; ++s) {
            ++p[path[s]];
            t[size_t(s) + 1] = id(p[0], p[1], p[2]);
          }
          const Vec3 &a = m.points[size_t(t[0])], &b = m.points[size_t(t[1])], &c = m.points[size_t(t[2])],
                     &d = m.points[size_t(t[3])];
          if ((b - a).cross(c - a).dot(d - a) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
  // Boundary faces: faces used by exactly one tet, oriented away from the tet's 4th vertex.
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;
  for (const auto& t : m.tets)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> tri = {t[size_t((f + 1) % 4)], t[size_t((f + 2) % 4)], t[size_t((f + 3) % 4)]};
      const Vec3 &a = m.points[size_t(tri[0])], &b = m.points[size_t(tri[1])], &c = m.points[size_t(tri[2])];
      if ((b - a).cross(c - a).dot(m.points[size_t(t[size_t(f)])] - a) > 0) std::swap(tri[1], tri[2]);
      auto key = tri;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      ++entry.first;
      entry.second = tri;
    }
  for (const auto& [key, entry] : faces)
    if (entry.first == 1) {
      m.boundary_face_source.push_back(int(m.boundary_faces.size()));
      m.boundary_faces.push_back(entry.second);
    }
  return m;
}

//! An nx x ny x nz block of unit cube hexes in VTK order.
inline HexMesh hex_block(int nx, int ny, int nz) {
  HexMesh m;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.nodes.push_back(Vec3(i, j, k));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return m;
}

//! Counts of unique edges and faces of a tet mesh (set based, independent of thex()).
inline std::pair<size_t, size_t> tet_edges_faces(const TetMesh& m) {
  std::set<std::array<int, 2>> edges;
  std::set<std::array<int, 3>> faces;
  for (const auto& t : m.tets) {
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.insert({std::min(t[size_t(i)], t[size_t(j)]), std::max(t[size_t(i)], t[size_t(j)])});
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> tri = {t[size_t((f + 1) % 4)], t[size_t((f + 2) % 4)], t[size_t((f + 3) % 4)]};
      std::sort(tri.begin(), tri.end());
      faces.insert(tri);
    }
  }
  return {edges.size(), faces.size()};
}

//! Counts of unique edges and faces of a hex mesh (set based, independent of dice()).
inline std::pair<size_t, size_t> hex_edges_faces(const HexMesh& m) {
  static const int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  static const int kFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::set<std::array<int, 2>> edges;
  std::set<std::array<int, 4>> faces;
  for (const auto& h : m.hexes) {
    for (const auto& e : kEdges)
      edges.insert({std::min(h[size_t(e[0])], h[size_t(e[1])]), std::max(h[size_t(e[0])], h[size_t(e[1])])});
    for (const auto& f : kFaces) {
      std::array<int, 4> q = {h[size_t(f[0])], h[size_t(f[1])], h[size_t(f[2])], h[size_t(f[3])]};
      std::sort(q.begin(), q.end());
      faces.insert(q);
    }
  }
  return {edges.size(), faces.size()};
}

//! Number of nodes that coincide (to 1e-9) with an earlier node.
inline size_t duplicate_coordinates(const HexMesh& m) {
  std::set<std::array<long long, 3>> seen;
  size_t dup = 0;
  for (const auto& p : m.nodes)
    if (!seen.insert({std::llround(p.x() * 1e9), std::llround(p.y() * 1e9), std::llround(p.z() * 1e9)}).second) ++dup;
  return dup;
}

}  // namespace dthex::fixtures
