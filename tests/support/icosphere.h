// SPDX-License-Identifier: MIT
// The icosphere the module tests decimate: an icosahedron whose faces are split in four
// `levels` times, its vertices put on the unit sphere. One generator for every OpenMesh mesh type
// an app might declare (the tests declare their own traits, as an app does).
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace dthex_test {

//! The unit icosphere as a `Mesh` (any OpenMesh triangle mesh with double or float points):
//! 12 + 10 (4^levels - 1) vertices, 20 4^levels faces. Requests nothing on the mesh.
template <class Mesh>
Mesh openmesh_icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<OpenMesh::Vec3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (mid.count(key)) return mid[key];
      p.push_back((p[size_t(a)] + p[size_t(b)]) / 2);
      return mid[key] = int(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.insert(g.end(), {{tri[0], a, c}, {tri[1], b, a}, {tri[2], c, b}, {a, b, c}});
    }
    f = g;
  }
  Mesh mesh;
  std::vector<typename Mesh::VertexHandle> vh;
  for (auto& q : p) vh.push_back(mesh.add_vertex(q.normalized()));
  for (const auto& tri : f) mesh.add_face(vh[size_t(tri[0])], vh[size_t(tri[1])], vh[size_t(tri[2])]);
  return mesh;
}

}  // namespace dthex_test
