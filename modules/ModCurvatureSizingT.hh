// SPDX-License-Identifier: MIT
// Curvature sizing field for DTHex coarsening (docs/METHOD.md section 3, Coarsening: Sizing
// field) and the Decimater module
// that stores it in the vertex property "v:dthex_size" (see size_property_name()).
//
// h(P) = clamp(alpha * rho_P, h_min, h_max), alpha = 2 sqrt(eps (2 - eps)), rho_P the smallest
// osculating radius over P's edges, then limited so |h(A) - h(B)| <= beta |AB| along edges.
#pragma once

#include "DTHexGeometry.hh"

#include <OpenMesh/Core/Utils/Property.hh>

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <vector>

namespace dthex {

struct CurvatureSizingOptions {
  //! Coarsening factor: the allowed sagitta of an edge relative to the local radius.
  double eps = 0.1;
  //! Smallest size. 0 = automatic: the mean input edge length. Scan noise gives tiny radii;
  //! this floor keeps them from pinning the input resolution below its own average, while an
  //! input that is already coarse (every edge near the mean) is not coarsened by the floor alone.
  double h_min = 0;
  //! Largest size. 0 = automatic: half the bounding-box diagonal (a flat region is bounded
  //! by its own outline long before that; the cap only stops rho = infinity on planes).
  double h_max = 0;
  //! Gradation beta: h may change by at most beta per unit length along an edge. 0.5 keeps
  //! neighbouring coarse edges within a factor of ~1.5 of each other (well-shaped triangles)
  //! while letting a small curved detail be surrounded by large flat triangles within a
  //! few edges. <= 0 disables the limit.
  double gradation = 0.5;
};

//! Vertex normal with Max's weights (N. Max, "Weights for computing vertex normals from
//! facet normals", 1999): sum of (a x b) / (|a|^2 |b|^2) over the triangles (a, b edges from
//! P). It is exact for vertices on a sphere whatever the triangulation, which is what the
//! osculating radius needs (angle or area weights tilt the normal next to irregular
//! vertices, and rho is very sensitive to tilt). Unit length; zero for an isolated vertex.
template <class Mesh>
typename Mesh::Point vertex_normal(const Mesh& mesh, typename Mesh::VertexHandle v) {
  using Point = typename Mesh::Point;
  Point n(0, 0, 0);
  const Point p = mesh.point(v);
  for (auto h : mesh.voh_range(v)) {
    if (!mesh.face_handle(h).is_valid()) continue;
    const Point a = mesh.point(mesh.to_vertex_handle(h)) - p;
    const Point b = mesh.point(mesh.to_vertex_handle(mesh.next_halfedge_handle(h))) - p;
    const double w = double(a.sqrnorm() * b.sqrnorm());
    if (w > 0) n += (a % b) / w;
  }
  const double len = n.norm();
  return len > 0 ? Point(n / len) : n;
}

//! rho_P on a feature line (a vertex with exactly two feature edges): the radius of the
//! line itself (circle through P and its two feature neighbours), and on each side of the
//! crease the osculating radius measured with that side's normal. The averaged vertex
//! normal would see the crease as a tight curve and pin the whole line at h_min.
template <class Mesh>
double feature_line_radius(const Mesh& mesh, typename Mesh::VertexHandle v) {
  using Point = typename Mesh::Point;
  const Point p = mesh.point(v);
  std::vector<Point> along;
  double r = std::numeric_limits<double>::infinity();
  for (auto h : mesh.voh_range(v)) {
    const Point q = mesh.point(mesh.to_vertex_handle(h));
    if (mesh.status(mesh.edge_handle(h)).feature()) {
      along.push_back(q);
      continue;
    }
    Point n(0, 0, 0);
    for (auto fh : {mesh.face_handle(h), mesh.opposite_face_handle(h)})
      if (fh.is_valid()) n += mesh.calc_face_normal(fh);
    if (n.norm() > 0) r = std::min(r, osculating_radius(p, Point(n / n.norm()), q));
  }
  if (along.size() == 2) {
    const Point a = along[0] - p, b = along[1] - p;
    const double cross = (a % b).norm();
    if (cross > 1e-12 * a.norm() * b.norm())
      r = std::min(r, (a.norm() * b.norm() * (a - b).norm()) / (2.0 * cross));  // circumradius
  }
  return r;
}

//! rho_P for every vertex (indexed by vertex idx): the smallest osculating radius over
//! P's edges, infinity where every edge is tangent (planes). Deleted vertices get infinity.
//! Where edges carry feature status, vertices on a feature line use feature_line_radius.
//! Each vertex is independent of the others: with OpenMP, they are shared among the cores.
template <class Mesh>
std::vector<double> osculating_radii(const Mesh& mesh) {
  std::vector<double> rho(mesh.n_vertices(), std::numeric_limits<double>::infinity());
  const int count = int(mesh.n_vertices());
#pragma omp parallel for schedule(static, 4096) if (count >= 65536)
  for (int i = 0; i < count; ++i) {
    const auto v = mesh.vertex_handle(unsigned(i));
    if (mesh.has_vertex_status() && mesh.status(v).deleted()) continue;
    if (mesh.has_edge_status()) {
      int feature_edges = 0;
      for (auto e : mesh.ve_range(v)) feature_edges += mesh.status(e).feature() ? 1 : 0;
      if (feature_edges == 2) {
        rho[size_t(v.idx())] = feature_line_radius(mesh, v);
        continue;
      }
    }
    const auto n = vertex_normal(mesh, v);
    double r = std::numeric_limits<double>::infinity();
    for (auto q : mesh.vv_range(v)) r = std::min(r, osculating_radius(mesh.point(v), n, mesh.point(q)));
    rho[size_t(v.idx())] = r;
  }
  return rho;
}

//! Lowers h until |h(A) - h(B)| <= beta |AB| on every edge (Dijkstra from the smallest
//! sizes outward: each h ends as min over vertices Q of h(Q) + beta * path length, the sum
//! taken in floating point from Q outward). The sizes it ends at are the largest that fit
//! under the given ones and meet the limit, so they do not depend on the order in which equal
//! sizes are taken from the queue, nor on the kind of queue.
//! On a fine input nearly every size falls, and the search is bound by memory, not by
//! arithmetic: the one-rings are first copied into flat arrays with their edges' beta |AB|
//! (one pass in vertex order, instead of a walk around each vertex's halfedges at its turn),
//! and the queue is a radix heap (sizes taken out only grow, so a vertex goes in a bucket by
//! the highest bit in which its size differs from the last one taken out, and entries hold
//! only the vertex): on 2.3 million vertices half the time of an indexed 4-ary heap walking
//! the halfedges. A vertex whose size falls is queued again; its older entry is passed over.
template <class Mesh>
void limit_gradation(const Mesh& mesh, std::vector<double>& h, double beta) {
  if (!(beta > 0)) return;
  const size_t n = mesh.n_vertices();
  std::vector<size_t> ring_start(n + 1, 0);
  std::vector<int> ring;
  std::vector<double> step;  // beta |AB| beside each ring entry
  ring.reserve(mesh.n_halfedges());
  step.reserve(mesh.n_halfedges());
  for (size_t i = 0; i < n; ++i) {
    ring_start[i] = ring.size();
    const auto v = mesh.vertex_handle(unsigned(i));
    if (mesh.has_vertex_status() && mesh.status(v).deleted()) continue;
    for (auto q : mesh.vv_range(v)) {
      ring.push_back(q.idx());
      step.push_back(beta * (mesh.point(q) - mesh.point(v)).norm());
    }
  }
  ring_start[n] = ring.size();
  // The size's bits as an unsigned number of the same order (negative sizes too).
  const auto key = [&h](int v) {
    uint64_t bits;
    std::memcpy(&bits, &h[size_t(v)], sizeof bits);
    return bits >> 63 ? ~bits : bits | (uint64_t(1) << 63);
  };
  std::vector<int> bucket[65];
  uint64_t last = 0;  // the key of the size last taken out
  size_t queued = 0;
  const auto bucket_of = [&last](uint64_t k) { return k == last ? 0 : 64 - __builtin_clzll(k ^ last); };
  const auto enqueue = [&](int v) {
    bucket[bucket_of(key(v))].push_back(v);
    ++queued;
  };
  for (size_t i = 0; i < n; ++i)
    if (ring_start[i + 1] > ring_start[i]) enqueue(int(i));
  std::vector<char> taken(n, 0);
  std::vector<int> spread;  // the bucket being spread (its storage kept for the next)
  while (queued > 0) {
    if (bucket[0].empty()) {
      // Spread the first non-empty bucket out from its smallest size, which becomes `last`.
      int b = 1;
      while (bucket[b].empty()) ++b;
      bool any = false;
      for (int v : bucket[b]) {
        if (taken[size_t(v)]) continue;
        last = any ? std::min(last, key(v)) : key(v);
        any = true;
      }
      spread.swap(bucket[b]);
      for (int v : spread) {
        if (taken[size_t(v)]) --queued;
        else bucket[bucket_of(key(v))].push_back(v);
      }
      spread.clear();
      continue;
    }
    const int v = bucket[0].back();
    bucket[0].pop_back();
    --queued;
    if (taken[size_t(v)]) continue;
    taken[size_t(v)] = 1;
    const double hv = h[size_t(v)];
    for (size_t k = ring_start[size_t(v)]; k < ring_start[size_t(v) + 1]; ++k) {
      const int q = ring[k];
      const double candidate = hv + step[k];
      if (!(candidate < h[size_t(q)])) continue;
      h[size_t(q)] = candidate;
      enqueue(q);
    }
  }
}

//! What the automatic (0) size bounds of CurvatureSizingOptions are made from: the mesh's
//! mean edge length (h_min) and half its bounding-box diagonal (h_max).
struct AutomaticSizeBounds {
  double mean_edge = 0, half_diagonal = 0;
};

template <class Mesh>
AutomaticSizeBounds automatic_size_bounds(const Mesh& mesh) {
  AutomaticSizeBounds out;
  double sum = 0;
  size_t count = 0;
  for (auto e : mesh.edges()) {
    if (mesh.has_edge_status() && mesh.status(e).deleted()) continue;
    sum += mesh.calc_edge_length(e);
    ++count;
  }
  out.mean_edge = count ? sum / double(count) : 0.0;
  typename Mesh::Point lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (auto v : mesh.vertices()) {
    lo.minimize(mesh.point(v));
    hi.maximize(mesh.point(v));
  }
  out.half_diagonal = mesh.n_vertices() ? 0.5 * (hi - lo).norm() : 0.0;
  return out;
}

//! h_min/h_max of options, its automatic (0) defaults taken from `automatic`.
inline std::pair<double, double> sizing_bounds(const AutomaticSizeBounds& automatic,
                                               const CurvatureSizingOptions& options) {
  const double h_min = options.h_min > 0 ? options.h_min : automatic.mean_edge;
  const double h_max = options.h_max > 0 ? options.h_max : automatic.half_diagonal;
  return {h_min, std::max(h_min, h_max)};
}

//! h_min/h_max after resolving the automatic (0) defaults of options on this mesh.
template <class Mesh>
std::pair<double, double> sizing_bounds(const Mesh& mesh, const CurvatureSizingOptions& options) {
  return sizing_bounds(automatic_size_bounds(mesh), options);
}

//! The sizing field from osculating radii already measured on `mesh` (osculating_radii) and
//! the bounds (sizing_bounds): what curvature_sizing computes after measuring them.
template <class Mesh>
std::vector<double> sizing_from_radii(const Mesh& mesh, std::vector<double> rho, std::pair<double, double> bounds,
                                      const CurvatureSizingOptions& options) {
  const double alpha = sizing_alpha(options.eps);
  for (double& x : rho) x = std::clamp(alpha * x, bounds.first, bounds.second);  // clamp maps inf to h_max
  limit_gradation(mesh, rho, options.gradation);
  return rho;
}

//! The sizing field (indexed by vertex idx) of docs/METHOD.md section 3 (Coarsening) on the
//! mesh as it is.
template <class Mesh>
std::vector<double> curvature_sizing(const Mesh& mesh, const CurvatureSizingOptions& options) {
  return sizing_from_radii(mesh, osculating_radii(mesh), sizing_bounds(mesh, options), options);
}

//! The "v:dthex_size" property, added if the mesh does not have it yet.
template <class Mesh>
OpenMesh::VPropHandleT<double> size_property(Mesh& mesh) {
  OpenMesh::VPropHandleT<double> prop;
  if (!mesh.get_property_handle(prop, size_property_name())) mesh.add_property(prop, size_property_name());
  return prop;
}

//! Binary, always-legal module whose job is initialize(): it computes the sizing field on
//! the mesh as it is (the input) into "v:dthex_size". Configure with set_options() before
//! the decimater's initialize(); set_compute_on_initialize(false) keeps a field the app
//! wrote itself.
template <class MeshT>
class ModCurvatureSizingT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModCurvatureSizingT, MeshT, CurvatureSizing);

  explicit ModCurvatureSizingT(MeshT& mesh) : Base(mesh, true) { size_ = size_property(mesh); }

  void set_options(const CurvatureSizingOptions& options) { options_ = options; }
  const CurvatureSizingOptions& options() const { return options_; }
  void set_compute_on_initialize(bool compute) { compute_ = compute; }

  void initialize() override {
    if (!compute_) return;
    auto& mesh = Base::mesh();
    const std::vector<double> h = curvature_sizing(mesh, options_);
    for (auto v : mesh.vertices()) mesh.property(size_, v) = h[size_t(v.idx())];
  }

  float collapse_priority(const CollapseInfo&) override { return float(Base::LEGAL_COLLAPSE); }

 private:
  OpenMesh::VPropHandleT<double> size_;
  CurvatureSizingOptions options_;
  bool compute_ = true;
};

}  // namespace dthex
