// SPDX-License-Identifier: MIT
#include <dthex/tets/tet_regions.h>

#include <dthex/numerics/signed_volume.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>

namespace dthex {
namespace {

std::array<int, 3> sorted(std::array<int, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}


// Exact coordinates as a key: the interface points are copies of one point, never recomputed.
using PointKey = std::array<uint64_t, 3>;
PointKey key_of(const Vec3& p) {
  PointKey k;
  for (int i = 0; i < 3; ++i) std::memcpy(&k[size_t(i)], &p[i], sizeof(double));
  return k;
}

}  // namespace

std::vector<TetMesh> split_tet_regions(const TetMesh& mesh) {
  int n_regions = 1;
  for (int r : mesh.tet_region) n_regions = std::max(n_regions, r + 1);
  // Each face of a tet, sorted, with the tet and the corner opposite it.
  struct Face {
    std::array<int, 3> key;
    int tet, opposite;
    bool operator<(const Face& o) const { return key < o.key; }
  };
  std::vector<Face> faces;
  faces.reserve(4 * mesh.tets.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const auto& tet = mesh.tets[t];
      faces.push_back({sorted({tet[size_t((f + 1) % 4)], tet[size_t((f + 2) % 4)], tet[size_t((f + 3) % 4)]}), int(t),
                       tet[size_t(f)]});
    }
  std::sort(faces.begin(), faces.end());
  auto region_of = [&](int t) { return mesh.tet_region.empty() ? 0 : mesh.tet_region[size_t(t)]; };

  std::vector<TetMesh> out(static_cast<size_t>(n_regions));
  std::vector<std::vector<int>> local(static_cast<size_t>(n_regions), std::vector<int>(mesh.points.size(), -1));
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) local[size_t(region_of(int(t)))][size_t(v)] = 0;
  for (size_t r = 0; r < out.size(); ++r)
    for (size_t v = 0; v < mesh.points.size(); ++v)
      if (local[r][v] == 0) {
        local[r][v] = int(out[r].points.size());
        out[r].points.push_back(mesh.points[v]);
      }
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const size_t r = size_t(region_of(int(t)));
    std::array<int, 4> tet = mesh.tets[t];
    for (int& v : tet) v = local[r][size_t(v)];
    out[r].tets.push_back(tet);
  }
  for (size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
    const std::array<int, 3> key = sorted(mesh.boundary_faces[i]);
    const int source = mesh.boundary_face_source.empty() ? int(i) : mesh.boundary_face_source[i];
    for (auto it = std::lower_bound(faces.begin(), faces.end(), Face{key, -1, -1}); it != faces.end() && it->key == key;
         ++it) {
      const size_t r = size_t(region_of(it->tet));
      std::array<int, 3> f = mesh.boundary_faces[i];
      if (signed_volume6(mesh.points[size_t(f[0])], mesh.points[size_t(f[1])], mesh.points[size_t(f[2])],
                         mesh.points[size_t(it->opposite)]) > 0) std::swap(f[1], f[2]);
      for (int& v : f) v = local[r][size_t(v)];
      out[r].boundary_faces.push_back(f);
      out[r].boundary_face_source.push_back(source);
    }
  }
  return out;
}

TetMesh merge_tet_regions(const std::vector<TetMesh>& regions) {
  TetMesh out;
  if (regions.size() == 1) return regions.front();
  std::map<PointKey, int> boundary_point;  // a boundary vertex's index in `out`
  std::map<std::array<int, 3>, size_t> face_slot;
  for (size_t r = 0; r < regions.size(); ++r) {
    const TetMesh& region = regions[r];
    std::vector<char> on_boundary(region.points.size(), 0);
    for (const auto& f : region.boundary_faces)
      for (int v : f) on_boundary[size_t(v)] = 1;
    std::vector<int> global(region.points.size());
    for (size_t v = 0; v < region.points.size(); ++v) {
      if (on_boundary[v]) {
        const auto [it, added] = boundary_point.try_emplace(key_of(region.points[v]), int(out.points.size()));
        global[v] = it->second;
        if (!added) continue;
      } else {
        global[v] = int(out.points.size());
      }
      out.points.push_back(region.points[v]);
    }
    for (std::array<int, 4> tet : region.tets) {
      for (int& v : tet) v = global[size_t(v)];
      out.tets.push_back(tet);
      out.tet_region.push_back(int(r));
    }
    for (size_t i = 0; i < region.boundary_faces.size(); ++i) {
      std::array<int, 3> f = region.boundary_faces[i];
      for (int& v : f) v = global[size_t(v)];
      // An interface face keeps the orientation of the region met first (the lower one).
      if (!face_slot.try_emplace(sorted(f), out.boundary_faces.size()).second) continue;
      out.boundary_faces.push_back(f);
      out.boundary_face_source.push_back(region.boundary_face_source.empty() ? int(i) : region.boundary_face_source[i]);
    }
  }
  return out;
}

}  // namespace dthex
