// SPDX-License-Identifier: MIT
// Small procedural meshes for the projection and untangling tests: a structured hex block,
// a subdivided box surface, a banded sphere, the tets of a star-shaped surface around its centre
// (the paper's sphere case), labelling of boundary nodes with their coarse facet, and the
// smallest scaled Jacobian of a hex mesh.
#pragma once

#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <string>

namespace dthex::testing {

inline TriSurface read_off(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  size_t nv = 0, nf = 0, ne = 0;
  in >> magic >> nv >> nf >> ne;
  TriSurface s;
  s.points.resize(nv);
  for (auto& p : s.points) in >> p.x() >> p.y() >> p.z();
  for (size_t f = 0; f < nf; ++f) {
    int k = 0;
    std::array<int, 3> t{};
    in >> k >> t[0] >> t[1] >> t[2];
    s.triangles.push_back(t);
  }
  return s;
}

//! Axis-aligned box [lo, hi] whose faces are grids of cells[axis] quads along each axis, two
//! triangles per quad, outward (uneven counts make the needle strips of a CAD export).
inline TriSurface box_surface(const Vec3& lo, const Vec3& hi, const std::array<int, 3>& cells) {
  TriSurface s;
  std::map<std::array<long, 3>, int> index;
  auto vertex = [&](const Vec3& p) {
    const std::array<long, 3> key = {std::lround(p.x() * 1e9), std::lround(p.y() * 1e9), std::lround(p.z() * 1e9)};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    s.points.push_back(p);
    return index[key] = int(s.points.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      auto at = [&](int i, int j) {
        Vec3 p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[u] = lo[u] + (hi[u] - lo[u]) * i / cells[size_t(u)];
        p[v] = lo[v] + (hi[v] - lo[v]) * j / cells[size_t(v)];
        return vertex(p);
      };
      for (int i = 0; i < cells[size_t(u)]; ++i)
        for (int j = 0; j < cells[size_t(v)]; ++j) {
          const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (side) s.triangles.push_back({a, b, c}), s.triangles.push_back({a, c, d});
          else s.triangles.push_back({a, c, b}), s.triangles.push_back({a, d, c});
        }
    }
  return s;
}

//! Axis-aligned box [lo, hi] with each face split into n x n quads, two triangles each, outward.
inline TriSurface box_surface(const Vec3& lo, const Vec3& hi, int n) { return box_surface(lo, hi, {n, n, n}); }

//! Structured block of nx x ny x nz hexes filling [lo, hi], VTK order, no labels.
inline HexMesh hex_block(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz) {
  HexMesh m;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.nodes.push_back(Vec3(lo.x() + (hi.x() - lo.x()) * i / nx, lo.y() + (hi.y() - lo.y()) * j / ny,
                               lo.z() + (hi.z() - lo.z()) * k / nz));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return m;
}

//! Nodes of faces used by one hex get the index of the nearest `coarse` triangle, others -1.
inline void label_boundary(HexMesh& m, const TriSurface& coarse) {
  constexpr int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  std::map<std::array<int, 4>, int> count;
  for (const auto& h : m.hexes)
    for (const auto& f : faces) {
      std::array<int, 4> key = {h[size_t(f[0])], h[size_t(f[1])], h[size_t(f[2])], h[size_t(f[3])]};
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  m.boundary_facet.assign(m.nodes.size(), -1);
  for (const auto& [key, c] : count) {
    if (c != 1) continue;
    for (int v : key) {
      double best = 1e300;
      for (size_t t = 0; t < coarse.triangles.size(); ++t) {
        const auto& tri = coarse.triangles[t];
        const double d = (closest_point_on_triangle(m.nodes[size_t(v)], coarse.points[size_t(tri[0])],
                                                    coarse.points[size_t(tri[1])], coarse.points[size_t(tri[2])]) -
                          m.nodes[size_t(v)])
                             .squaredNorm();
        if (d < best) best = d, m.boundary_facet[size_t(v)] = int(t);
      }
    }
  }
}

//! A unit sphere of `around` x `rings` bands (a pole at each end, alternate rings turned by half a
//! step so the triangles are even), outward.
inline TriSurface staggered_sphere(int around, int rings) {
  TriSurface s;
  s.points.push_back(Vec3(0, 0, 1));
  for (int j = 1; j < rings; ++j)
    for (int i = 0; i < around; ++i) {
      const double theta = M_PI * j / rings, phi = 2 * M_PI * (i + 0.5 * (j % 2)) / around;
      s.points.push_back(Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  s.points.push_back(Vec3(0, 0, -1));
  const int south = int(s.points.size()) - 1;
  auto id = [&](int j, int i) { return 1 + (j - 1) * around + i % around; };
  for (int i = 0; i < around; ++i) s.triangles.push_back({0, id(1, i), id(1, i + 1)});
  for (int j = 1; j < rings - 1; ++j)
    for (int i = 0; i < around; ++i) {
      if (j % 2) {
        s.triangles.push_back({id(j, i), id(j + 1, i), id(j + 1, i + 1)});
        s.triangles.push_back({id(j, i), id(j + 1, i + 1), id(j, i + 1)});
      } else {
        s.triangles.push_back({id(j, i), id(j + 1, i), id(j, i + 1)});
        s.triangles.push_back({id(j, i + 1), id(j + 1, i), id(j + 1, i + 1)});
      }
    }
  for (int i = 0; i < around; ++i) s.triangles.push_back({south, id(rings - 1, i + 1), id(rings - 1, i)});
  for (auto& t : s.triangles) {
    const Vec3 &a = s.points[size_t(t[0])], &b = s.points[size_t(t[1])], &c = s.points[size_t(t[2])];
    if ((b - a).cross(c - a).dot(a + b + c) < 0) std::swap(t[1], t[2]);
  }
  return s;
}

//! The tets of a star-shaped closed surface around `centre` (one per triangle), positively
//! oriented, with the surface triangles as boundary faces: what TetGen would give for the
//! icosahedron of the paper's sphere case.
inline TetMesh star_tets(const TriSurface& s, const Vec3& centre) {
  TetMesh tm;
  tm.points = s.points;
  tm.points.push_back(centre);
  const int c = int(tm.points.size()) - 1;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const auto& f = s.triangles[t];
    tm.tets.push_back({f[1], f[0], f[2], c});  // outward triangle, centre inside: positive
    tm.boundary_faces.push_back(f);
    tm.boundary_face_source.push_back(int(t));
  }
  return tm;
}

// An n^3 block of the unit box with every interior node pushed by a deterministic
// pseudo-random offset of up to `cells` cell: valid, but far from cubes.
inline HexMesh perturbed_block(const TriSurface& box, int n, double cells) {
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), n, n, n);
  label_boundary(mesh, box);
  unsigned state = 12345;
  auto next = [&] {
    state = state * 1103515245u + 12345u;
    return double((state >> 8) & 0xffff) / 65535.0 - 0.5;
  };
  for (size_t v = 0; v < mesh.nodes.size(); ++v)
    if (!mesh.is_boundary_node(int(v))) mesh.nodes[v] += Vec3(next(), next(), next()) * (2 * cells / n);
  return mesh;
}

//! The smallest scaled Jacobian over the hexes of `m` (1 for no hex).
inline double min_scaled_jacobian(const HexMesh& m) {
  double s = 1;
  for (size_t h = 0; h < m.hexes.size(); ++h) s = std::min(s, hex_scaled_jacobian(hex_corners(m, h)));
  return s;
}

}  // namespace dthex::testing
