// SPDX-License-Identifier: MIT
#include <dthex/surface/features.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Geometry>

namespace dthex {
namespace {

//! Per-triangle loops over more triangles than this (a scan, not a coarse surface) are split
//! over the cores; each triangle writes only its own entry, so the result is the same.
constexpr size_t kParallelFrom = 100000;

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

Vec3 unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0 ? Vec3(n / length) : Vec3::Zero();
}

//! Per edge (a < b): the triangles that use it (the first two) and how many do.
struct EdgeUse {
  int first = -1, second = -1, count = 0;
};
std::unordered_map<uint64_t, EdgeUse> edge_uses(const std::vector<std::array<int, 3>>& triangles) {
  std::unordered_map<uint64_t, EdgeUse> uses;
  uses.reserve(triangles.size() * 2);
  for (size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    for (int k = 0; k < 3; ++k) {
      const int a = std::min(t[size_t(k)], t[size_t((k + 1) % 3)]);
      const int b = std::max(t[size_t(k)], t[size_t((k + 1) % 3)]);
      EdgeUse& use = uses[(uint64_t(uint32_t(a)) << 32) | uint32_t(b)];
      (use.count == 0 ? use.first : use.second) = int(f);
      ++use.count;
    }
  }
  return uses;
}

//! Per triangle, the triangle across each of its edges (edge k joins corners k and k + 1); -1
//! on a border or a non-manifold edge. Through each vertex's triangles: no hash map, which
//! is slow on large inputs.
std::vector<std::array<int, 3>> triangle_neighbours(const std::vector<std::array<int, 3>>& triangles) {
  int n_points = 0;
  for (const auto& t : triangles) n_points = std::max({n_points, t[0] + 1, t[1] + 1, t[2] + 1});
  std::vector<int> start(size_t(n_points) + 1, 0), incident(3 * triangles.size());
  for (const auto& t : triangles)
    for (int v : t) ++start[size_t(v) + 1];
  for (size_t v = 0; v < size_t(n_points); ++v) start[v + 1] += start[v];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int v : triangles[f]) incident[size_t(fill[size_t(v)]++)] = int(f);
  std::vector<std::array<int, 3>> neighbours(triangles.size(), {-1, -1, -1});
  // Each triangle's search reads the lists and writes its own entry: split over the cores.
#pragma omp parallel for schedule(static) if (triangles.size() > kParallelFrom)
  for (size_t f = 0; f < triangles.size(); ++f)
    for (size_t k = 0; k < 3; ++k) {
      const int a = triangles[f][k], b = triangles[f][(k + 1) % 3];
      int found = -1, count = 0;
      for (int i = start[size_t(a)]; i < start[size_t(a) + 1]; ++i) {
        const int g = incident[size_t(i)];
        const auto& u = triangles[size_t(g)];
        if (g != int(f) && (u[0] == b || u[1] == b || u[2] == b)) found = g, ++count;
      }
      neighbours[f][k] = count == 1 ? found : -1;
    }
  return neighbours;
}

bool is_needle(const Vec3& a, const Vec3& b, const Vec3& c) {
  static const double needle_cos = std::cos(kFinNeedleAngleDeg * M_PI / 180.0);
  const std::array<Vec3, 3> corners = {a, b, c};
  for (size_t k = 0; k < 3; ++k) {
    const Vec3 u = corners[(k + 1) % 3] - corners[k], w = corners[(k + 2) % 3] - corners[k];
    const double lu = u.norm(), lw = w.norm();
    if (lu > 0 && lw > 0 && u.dot(w) > needle_cos * lu * lw) return true;
  }
  return false;
}

//! The fins among the triangles, given their unit normals; the neighbours are looked up only
//! when there is a needle at all.
std::vector<char> fins_from(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                            const std::vector<Vec3>& normals, double angle_deg) {
  std::vector<char> fins(triangles.size(), 0);
  std::vector<char> needle(triangles.size(), 0);
#pragma omp parallel for schedule(static) if (triangles.size() > kParallelFrom)
  for (size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    needle[f] = is_needle(points[size_t(t[0])], points[size_t(t[1])], points[size_t(t[2])]);
  }
  std::vector<size_t> needles;
  for (size_t f = 0; f < triangles.size(); ++f)
    if (needle[f]) needles.push_back(f);
  if (needles.empty()) return fins;
  const std::vector<std::array<int, 3>> neighbours = triangle_neighbours(triangles);
  for (size_t f : needles) {
    const auto& t = triangles[f];
    std::array<Vec3, 3> corners, around;
    for (size_t k = 0; k < 3; ++k) {
      corners[k] = points[size_t(t[k])];
      const int other = neighbours[f][k];
      around[k] = other < 0 ? Vec3(-normals[f]) : normals[size_t(other)];
    }
    fins[f] = is_fin(corners, normals[f], around, angle_deg);
  }
  return fins;
}

}  // namespace

bool is_fin(const std::array<Vec3, 3>& corners, const Vec3& unit_normal, const std::array<Vec3, 3>& neighbour_normals,
            double angle_deg) {
  if (unit_normal.squaredNorm() == 0 || !is_needle(corners[0], corners[1], corners[2])) return false;
  const double cos_limit = std::cos(angle_deg * M_PI / 180.0);
  for (const Vec3& n : neighbour_normals)
    if (n.squaredNorm() > 0 && unit_normal.dot(n) >= cos_limit) return false;
  return true;
}

std::vector<char> fin_triangles(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                double angle_deg) {
  std::vector<Vec3> normals(triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    normals[f] = unit_normal(points[size_t(t[0])], points[size_t(t[1])], points[size_t(t[2])]);
  }
  return fins_from(points, triangles, normals, angle_deg);
}

CreaseTest::CreaseTest(const TriSurface& surface, double angle_deg)
    : normals_(surface.triangles.size()), cos_limit_(std::cos(angle_deg * M_PI / 180.0)) {
  const auto& points = surface.points;
#pragma omp parallel for schedule(static) if (surface.triangles.size() > kParallelFrom)
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    normals_[f] = unit_normal(points[size_t(t[0])], points[size_t(t[1])], points[size_t(t[2])]);
  }
  fins_ = fins_from(points, surface.triangles, normals_, angle_deg);
}

Features detect_features(const TriSurface& surface, double angle_deg) {
  const std::unordered_map<uint64_t, EdgeUse> uses = edge_uses(surface.triangles);
  const CreaseTest crease(surface, angle_deg);
  Features features;
  for (const auto& [key, use] : uses) {
    const bool sharp = use.count != 2 || crease(use.first, use.second);
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
  // Each triangle's normal once (the fin test and the edge test ask for it about seven times).
  std::vector<SurfaceMesh::Normal> normals(mesh.n_faces());
  for (auto f : mesh.faces())
    if (!mesh.status(f).deleted()) normals[size_t(f.idx())] = mesh.calc_face_normal(f);
  auto normal = [&](OpenMesh::FaceHandle f) { return to_eigen(normals[size_t(f.idx())]); };
  std::vector<char> fins(mesh.n_faces(), 0);
  for (auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    std::array<Vec3, 3> corners, neighbours;
    size_t k = 0;
    for (auto h : mesh.fh_range(f)) {
      corners[k] = to_eigen(mesh.point(mesh.from_vertex_handle(h)));
      const auto other = mesh.opposite_face_handle(h);
      neighbours[k++] = other.is_valid() ? normal(other) : Vec3(-normal(f));
    }
    fins[size_t(f.idx())] = is_fin(corners, normal(f), neighbours, angle_deg);
  }
  Features features;
  for (auto e : mesh.edges()) {
    if (mesh.status(e).deleted()) continue;
    bool sharp = mesh.is_boundary(e);
    if (!sharp) {
      const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0)), f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
      sharp = !fins[size_t(f0.idx())] && !fins[size_t(f1.idx())] &&
              (normals[size_t(f0.idx())] | normals[size_t(f1.idx())]) < cos_limit;
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
#pragma omp parallel for schedule(static) if (triangles.size() > kParallelFrom)
  for (size_t t = 0; t < triangles.size(); ++t) {
    const auto& f = triangles[t];
    normals[t] = unit_normal(points[size_t(f[0])], points[size_t(f[1])], points[size_t(f[2])]);
  }
  const std::vector<char> fins = fins_from(points, triangles, normals, kDefaultFeatureAngleDeg);
  for (size_t t = 0; t < triangles.size(); ++t)
    if (fins[t]) normals[t] = Vec3::Zero();
  return normals;
}

namespace {

// Whether a triangle of `surface` with a non-zero normal that `counts` (given the triangle)
// lies within `radius` of x.
template <class Counts>
bool any_triangle_within(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, double radius,
                         const Counts& counts) {
  const Eigen::AlignedBox3d box(x - Vec3::Constant(radius), x + Vec3::Constant(radius));
  bool found = false;
  const auto& p = surface.points();
  surface.for_each_in_box(box, [&](int t) {
    if (found || normals[size_t(t)].squaredNorm() == 0 || !counts(t)) return;
    const auto& f = surface.triangles()[size_t(t)];
    const Vec3 c = closest_point_on_triangle(x, p[size_t(f[0])], p[size_t(f[1])], p[size_t(f[2])]);
    if ((c - x).squaredNorm() <= radius * radius) found = true;
  });
  return found;
}

}  // namespace

bool on_surface_crease(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                       double radius, double min_cos, bool convex_only) {
  const auto& p = surface.points();
  return any_triangle_within(surface, normals, x, radius, [&](int t) {
    if (normals[size_t(t)].dot(normal) >= min_cos) return false;
    const auto& f = surface.triangles()[size_t(t)];
    return !(convex_only && ((p[size_t(f[0])] + p[size_t(f[1])] + p[size_t(f[2])]) / 3 - x).dot(normal) > 0);
  });
}

bool surface_curves_near(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                         double radius, double flat_cos, double face_cos) {
  return any_triangle_within(surface, normals, x, radius, [&](int t) {
    const double turn = normals[size_t(t)].dot(normal);
    return turn < flat_cos && turn >= face_cos;
  });
}

bool has_knife_edge(const std::vector<std::array<int, 3>>& triangles, const std::vector<Vec3>& normals,
                    double knife_angle_deg) {
  const double knife_cos = -std::cos(knife_angle_deg * M_PI / 180.0);
  const std::vector<std::array<int, 3>> neighbours = triangle_neighbours(triangles);
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int g : neighbours[f])
      if (g > int(f) && normals[f].dot(normals[size_t(g)]) < knife_cos) return true;
  return false;
}

bool near_knife_edge(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, double radius,
                     double knife_angle_deg) {
  const double knife_cos = -std::cos(knife_angle_deg * M_PI / 180.0);
  const Eigen::AlignedBox3d box(x - Vec3::Constant(radius), x + Vec3::Constant(radius));
  std::vector<int> near;
  bool knife = false;
  const auto& p = surface.points();
  const auto& triangles = surface.triangles();
  surface.for_each_in_box(box, [&](int t) {
    const Vec3& n = normals[size_t(t)];
    if (knife || n.squaredNorm() == 0) return;
    const auto& f = triangles[size_t(t)];
    if ((closest_point_on_triangle(x, p[size_t(f[0])], p[size_t(f[1])], p[size_t(f[2])]) - x).squaredNorm() >
        radius * radius)
      return;
    for (int u : near) {
      if (normals[size_t(u)].dot(n) >= knife_cos) continue;
      // The edge the two share, if they are neighbours: x must be within radius of it.
      std::array<int, 2> shared{};
      int count = 0;
      for (int a : triangles[size_t(u)])
        if (a == f[0] || a == f[1] || a == f[2]) shared[size_t(std::min(count++, 1))] = a;
      if (count != 2) continue;
      const Vec3 a = p[size_t(shared[0])], d = p[size_t(shared[1])] - a;
      const double s = std::clamp((x - a).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
      if ((a + s * d - x).squaredNorm() <= radius * radius) knife = true;
    }
    near.push_back(t);
  });
  return knife;
}

CreaseKind crease_at(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                     double radius, double min_cos, Vec3& direction, double* faces_cos) {
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
  if (faces_cos) *faces_cos = faces[0].dot(faces[1]);
  return concave ? CreaseKind::concave_line : CreaseKind::convex_line;
}

}  // namespace dthex
