// SPDX-License-Identifier: MIT
#include "core/features.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Geometry>

namespace dthex {
namespace {

void finish(Features& features, size_t n_vertices) {
  std::sort(features.edges.begin(), features.edges.end());
  features.feature_valence.assign(n_vertices, 0);
  for (const auto& e : features.edges) {
    ++features.feature_valence[size_t(e[0])];
    ++features.feature_valence[size_t(e[1])];
  }
  for (size_t v = 0; v < n_vertices; ++v)
    if (features.feature_valence[v] == 1 || features.feature_valence[v] > 2) features.corners.push_back(int(v));
}

}  // namespace

Features detect_features(const TriSurface& surface, double angle_deg) {
  const double cos_limit = std::cos(angle_deg * M_PI / 180.0);
  std::vector<Vec3> normals;
  normals.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) {
    const Vec3 n = (surface.points[size_t(t[1])] - surface.points[size_t(t[0])])
                       .cross(surface.points[size_t(t[2])] - surface.points[size_t(t[0])]);
    const double len = n.norm();
    normals.push_back(len > 0 ? Vec3(n / len) : Vec3::Zero());
  }
  // Edge key (a < b) -> up to two incident triangles and a use count.
  struct EdgeUse {
    int first = -1, second = -1, count = 0;
  };
  std::unordered_map<uint64_t, EdgeUse> uses;
  uses.reserve(surface.triangles.size() * 2);
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const int a = std::min(t[size_t(k)], t[size_t((k + 1) % 3)]);
      const int b = std::max(t[size_t(k)], t[size_t((k + 1) % 3)]);
      EdgeUse& use = uses[(uint64_t(uint32_t(a)) << 32) | uint32_t(b)];
      (use.count == 0 ? use.first : use.second) = int(f);
      ++use.count;
    }
  }
  Features features;
  for (const auto& [key, use] : uses) {
    const bool sharp = use.count != 2 || normals[size_t(use.first)].dot(normals[size_t(use.second)]) < cos_limit;
    if (sharp) features.edges.push_back({int(key >> 32), int(key & 0xffffffffu)});
  }
  finish(features, surface.points.size());
  return features;
}

std::vector<std::array<int, 2>> feature_edges(const TriSurface& surface, double angle_deg) {
  return detect_features(surface, angle_deg).edges;
}

Features mark_features(SurfaceMesh& mesh, double angle_deg) {
  const double cos_limit = std::cos(angle_deg * M_PI / 180.0);
  Features features;
  for (auto e : mesh.edges()) {
    if (mesh.status(e).deleted()) continue;
    bool sharp = mesh.is_boundary(e);
    if (!sharp) {
      const auto n0 = mesh.calc_face_normal(mesh.face_handle(mesh.halfedge_handle(e, 0)));
      const auto n1 = mesh.calc_face_normal(mesh.face_handle(mesh.halfedge_handle(e, 1)));
      sharp = (n0 | n1) < cos_limit;
    }
    mesh.status(e).set_feature(sharp);
    if (sharp) {
      const int a = mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx();
      const int b = mesh.to_vertex_handle(mesh.halfedge_handle(e, 1)).idx();
      features.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  finish(features, mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const int valence = features.feature_valence[size_t(v.idx())];
    mesh.status(v).set_feature(valence > 0);
    mesh.status(v).set_locked(valence == 1 || valence > 2);
  }
  return features;
}

std::vector<char> nodes_on_feature_edges(const HexMesh& mesh, const TriSurface& coarse, double angle_deg) {
  std::vector<char> on_feature(mesh.nodes.size(), 0);
  if (mesh.boundary_facet.size() != mesh.nodes.size()) return on_feature;
  const std::vector<std::array<int, 2>> edges = feature_edges(coarse, angle_deg);  // sorted
  auto is_feature = [&](int a, int b) {
    return std::binary_search(edges.begin(), edges.end(), std::array<int, 2>{std::min(a, b), std::max(a, b)});
  };
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    const int facet = mesh.boundary_facet[v];
    if (facet < 0 || size_t(facet) >= coarse.triangles.size()) continue;
    const auto& t = coarse.triangles[size_t(facet)];
    for (int k = 0; k < 3 && !on_feature[v]; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      if (!is_feature(a, b)) continue;
      // Dicing places the nodes of a coarse edge on it up to rounding.
      const Vec3 pa = coarse.points[size_t(a)], d = coarse.points[size_t(b)] - pa;
      const double length_sq = d.squaredNorm();
      if (!(length_sq > 0)) continue;
      const double s = std::clamp((mesh.nodes[v] - pa).dot(d) / length_sq, 0.0, 1.0);
      on_feature[v] = (pa + s * d - mesh.nodes[v]).squaredNorm() <= 1e-16 * length_sq;
    }
  }
  return on_feature;
}

std::vector<Vec3> unit_triangle_normals(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles) {
  std::vector<Vec3> normals(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const auto& f = triangles[t];
    const Vec3 c = (points[size_t(f[1])] - points[size_t(f[0])]).cross(points[size_t(f[2])] - points[size_t(f[0])]);
    normals[t] = c.norm() > 0 ? Vec3(c.normalized()) : Vec3::Zero();
  }
  return normals;
}

bool on_surface_crease(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                       double radius, double min_cos, bool convex_only) {
  const Eigen::AlignedBox3d box(x - Vec3::Constant(radius), x + Vec3::Constant(radius));
  bool crease = false;
  const auto& p = surface.points();
  surface.for_each_in_box(box, [&](int t) {
    if (crease || normals[size_t(t)].dot(normal) >= min_cos) return;
    const auto& f = surface.triangles()[size_t(t)];
    if (convex_only && ((p[size_t(f[0])] + p[size_t(f[1])] + p[size_t(f[2])]) / 3 - x).dot(normal) > 0) return;
    const Vec3 c = closest_point_on_triangle(x, p[size_t(f[0])], p[size_t(f[1])], p[size_t(f[2])]);
    if ((c - x).squaredNorm() <= radius * radius) crease = true;
  });
  return crease;
}

CreaseKind crease_at(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                     double radius, double min_cos, Vec3& direction) {
  const Eigen::AlignedBox3d box(x - Vec3::Constant(radius), x + Vec3::Constant(radius));
  std::vector<Vec3> faces;
  bool concave = false;
  const auto& p = surface.points();
  surface.for_each_in_box(box, [&](int t) {
    const Vec3& n = normals[size_t(t)];
    if (n.squaredNorm() == 0) return;
    const auto& f = surface.triangles()[size_t(t)];
    const Vec3 c = closest_point_on_triangle(x, p[size_t(f[0])], p[size_t(f[1])], p[size_t(f[2])]);
    if ((c - x).squaredNorm() > radius * radius) return;
    for (const Vec3& m : faces)
      if (m.dot(n) >= min_cos) return;
    faces.push_back(n);
    if (n.dot(normal) < min_cos && ((p[size_t(f[0])] + p[size_t(f[1])] + p[size_t(f[2])]) / 3 - x).dot(normal) > 0)
      concave = true;
  });
  if (faces.size() <= 1) return CreaseKind::none;
  if (faces.size() > 2) return CreaseKind::corner;
  const Vec3 line = faces[0].cross(faces[1]);
  if (!(line.norm() > 0)) return CreaseKind::corner;
  direction = line.normalized();
  return concave ? CreaseKind::concave_line : CreaseKind::convex_line;
}

}  // namespace dthex
