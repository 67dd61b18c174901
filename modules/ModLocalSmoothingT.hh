// SPDX-License-Identifier: MIT
// Post-collapse local smoothing of the kept vertex and the swapped neighbours (docs/METHOD.md
// section 3, Coarsening: After each collapse), pulled back onto the input surface through a
// callback the app provides.
#pragma once

#include "DTHexTouched.hh"

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace dthex {

template <class Point>
struct LocalSmoothingOptions {
  //! Blend of the two weights: x = sum_i C_i (c1 A_i / A + c2 (1/S_i) / S), c2 = 1 - c1.
  //! C_i, A_i: centroid and area of triangle i around the vertex; S_i its mean size.
  double c1 = 0.5;
  //! A move may turn no incident triangle's normal by more than this (degrees).
  double max_normal_deviation_deg = 45.0;
  //! After a move every incident edge must be below this normalized length (so a too long
  //! input edge pins its vertices: smoothing never makes a new edge that is too long).
  double max_normalized_length = std::sqrt(2.0);
  //! Pull-back onto the surface the mesh approximates: returns the point to use for p and
  //! may overwrite size with the sizing field there. Unset = no pull-back, size unchanged.
  std::function<Point(const Point& p, double& size)> projection;
};

//! The local smoothing target of a vertex at p (size hp) whose triangles are (p, a_i, b_i)
//! with sizes ha_i, hb_i: sum_i C_i (c1 A_i / A + c2 (1/S_i) / S), before any pull-back.
//! ring holds (a_i, b_i) and sizes (ha_i, hb_i); with_sizes false measures S_i by the
//! triangle's mean edge length instead. Returns false when the ring has no area.
template <class Point>
bool smoothing_target(const Point& p, double hp, const std::vector<std::pair<Point, Point>>& ring,
                      const std::vector<std::pair<double, double>>& sizes, bool with_sizes, double c1_in,
                      Point& target) {
  const double c1 = std::clamp(c1_in, 0.0, 1.0), c2 = 1.0 - c1;
  Point sum_area(0, 0, 0), sum_size(0, 0, 0);
  double area = 0, inv_size = 0;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Point& a = ring[i].first;
    const Point& b = ring[i].second;
    const Point centroid = (p + a + b) / 3.0;
    const double ai = 0.5 * triangle_normal(p, a, b).norm();
    double si = with_sizes ? (hp + sizes[i].first + sizes[i].second) / 3.0
                           : ((a - p).norm() + (b - a).norm() + (p - b).norm()) / 3.0;
    if (!(si > 0)) si = 1e-300;
    sum_area += centroid * ai;
    area += ai;
    sum_size += centroid / si;
    inv_size += 1.0 / si;
  }
  if (!(area > 0) || !(inv_size > 0)) return false;
  target = sum_area * (c1 / area) + sum_size * (c2 / inv_size);
  return true;
}

//! Smooths one vertex (no-op on locked, feature and boundary vertices). The move is rejected
//! when it flips or over-turns a normal, lowers the worst incident triangle shape, or leaves
//! an incident edge at or above the normalized-length bound. Returns true when the vertex moved; updates incident face normals when
//! the mesh has them and the size property (if valid) from the projection.
template <class Mesh>
bool smooth_vertex(Mesh& mesh, typename Mesh::VertexHandle v, const LocalSmoothingOptions<typename Mesh::Point>& options,
                   OpenMesh::VPropHandleT<double> size) {
  using Point = typename Mesh::Point;
  if (mesh.status(v).deleted() || mesh.status(v).locked() || mesh.status(v).feature() || mesh.is_boundary(v))
    return false;
  const Point p = mesh.point(v);
  std::vector<std::pair<Point, Point>> ring;
  std::vector<std::pair<double, double>> sizes;
  double worst_shape = 1.0;
  for (auto h : mesh.voh_range(v)) {
    if (!mesh.face_handle(h).is_valid()) return false;
    const auto va = mesh.to_vertex_handle(h), vb = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    ring.emplace_back(mesh.point(va), mesh.point(vb));
    sizes.emplace_back(size.is_valid() ? mesh.property(size, va) : 0.0, size.is_valid() ? mesh.property(size, vb) : 0.0);
    worst_shape = std::min(worst_shape, triangle_shape(p, ring.back().first, ring.back().second));
  }
  Point target;
  if (!smoothing_target(p, size.is_valid() ? mesh.property(size, v) : 0.0, ring, sizes, size.is_valid(), options.c1,
                        target))
    return false;
  double h_new = size.is_valid() ? mesh.property(size, v) : 0.0;
  if (options.projection) target = options.projection(target, h_new);

  const double cos_bound = std::cos(deg_to_rad(options.max_normal_deviation_deg));
  double new_worst = 1.0;
  for (auto h : mesh.voh_range(v)) {
    const auto va = mesh.to_vertex_handle(h), vb = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
    const Point a = mesh.point(va), b = mesh.point(vb);
    const Point n_old = triangle_normal(p, a, b), n_new = triangle_normal(target, a, b);
    const double lo = n_old.norm(), ln = n_new.norm();
    if (!(ln > 0) || double(n_old | n_new) < cos_bound * lo * ln) return false;
    new_worst = std::min(new_worst, triangle_shape(target, a, b));
    if (size.is_valid()) {
      const double ha = mesh.property(size, va);
      if (!(normalized_length((a - target).norm(), h_new, ha) < options.max_normalized_length)) return false;
    }
  }
  if (new_worst < worst_shape) return false;
  mesh.set_point(v, target);
  if (size.is_valid()) mesh.property(size, v) = h_new;
  if (mesh.has_face_normals())
    for (auto f : mesh.vf_range(v)) mesh.set_normal(f, mesh.calc_face_normal(f));
  return true;
}

//! Where the kept vertex A (= ci.v1) lands if B (= ci.v0) collapses into it and A is then
//! smoothed: the smoothing target of A's ring after the collapse (B's triangles with B
//! replaced by A), pulled back by options.projection, which also gives the size there.
//! For ModNormalizedLengthT::set_placement: the bounds of a collapse are then judged on the
//! mesh the collapse and its smoothing leave, not on the intermediate one. False (keep A)
//! for a vertex smoothing would not move (locked, feature, boundary).
template <class Mesh, class CollapseInfo>
bool smoothed_collapse_target(const Mesh& mesh, const CollapseInfo& ci,
                              const LocalSmoothingOptions<typename Mesh::Point>& options,
                              OpenMesh::VPropHandleT<double> size, typename Mesh::Point& position, double& h) {
  using Point = typename Mesh::Point;
  const auto A = ci.v1;
  if (mesh.status(A).locked() || mesh.status(A).feature() || mesh.is_boundary(A) || mesh.is_boundary(ci.v0))
    return false;
  std::vector<std::pair<Point, Point>> ring;
  std::vector<std::pair<double, double>> sizes;
  for (auto center : {ci.v1, ci.v0})
    for (auto he : mesh.voh_range(center)) {
      const auto f = mesh.face_handle(he);
      if (!f.is_valid() || f == ci.fl || f == ci.fr) continue;
      const auto va = mesh.to_vertex_handle(he), vb = mesh.to_vertex_handle(mesh.next_halfedge_handle(he));
      ring.emplace_back(mesh.point(va), mesh.point(vb));
      sizes.emplace_back(size.is_valid() ? mesh.property(size, va) : 0.0,
                         size.is_valid() ? mesh.property(size, vb) : 0.0);
    }
  h = size.is_valid() ? mesh.property(size, A) : 0.0;
  if (!smoothing_target(ci.p1, h, ring, sizes, size.is_valid(), options.c1, position)) return false;
  if (options.projection) position = options.projection(position, h);
  return true;
}

//! Binary, always-legal module: after each collapse, smooths the kept vertex and the
//! vertices listed in "m:dthex_touched" (by ModEdgeSwapT, which must be added before this
//! module), and appends the vertices it moved to that list.
template <class MeshT>
class ModLocalSmoothingT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModLocalSmoothingT, MeshT, LocalSmoothing);
  using Options = LocalSmoothingOptions<typename MeshT::Point>;

  explicit ModLocalSmoothingT(MeshT& mesh) : Base(mesh, true) { touched_ = touched_property(mesh); }

  void set_options(const Options& options) { options_ = options; }
  const Options& options() const { return options_; }
  size_t n_moves() const { return moves_; }

  void initialize() override {
    if (!Base::mesh().get_property_handle(size_, size_property_name())) size_.reset();
    moves_ = 0;
  }
  float collapse_priority(const CollapseInfo&) override { return float(Base::LEGAL_COLLAPSE); }
  void preprocess_collapse(const CollapseInfo&) override { Base::mesh().property(touched_).clear(); }
  void postprocess_collapse(const CollapseInfo& ci) override {
    auto& mesh = Base::mesh();
    auto& touched = mesh.property(touched_);
    candidates_.assign(1, ci.v1);
    candidates_.insert(candidates_.end(), touched.begin(), touched.end());
    std::sort(candidates_.begin() + 1, candidates_.end());
    candidates_.erase(std::unique(candidates_.begin() + 1, candidates_.end()), candidates_.end());
    for (size_t i = 0; i < candidates_.size(); ++i) {
      const auto v = candidates_[i];
      if (i > 0 && v == ci.v1) continue;
      if (smooth_vertex(mesh, v, options_, size_)) {
        ++moves_;
        touched.push_back(v);
      }
    }
  }

 private:
  OpenMesh::MPropHandleT<std::vector<typename MeshT::VertexHandle>> touched_;
  OpenMesh::VPropHandleT<double> size_;
  Options options_;
  std::vector<typename MeshT::VertexHandle> candidates_;
  size_t moves_ = 0;
};

}  // namespace dthex
