// SPDX-License-Identifier: MIT
// The DTHex priority module (docs/METHOD.md section 3, Coarsening: Normalized length and the
// collapse test): shortest normalized edge first, collapse
// B (= ci.v0, removed) into A (= ci.v1, kept) only while the edge is shorter than its size.
#pragma once

#include "DTHexGeometry.hh"

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace dthex {

struct NormalizedLengthLimits {
  //! Upper bound on the normalized length of every new edge A-P_i. sqrt(2): after the
  //! collapse an edge may be at most ~1.4 sizes long, so a coarse edge never needs a split.
  double max_normalized_length = std::sqrt(2.0);
  //! Largest rotation of a triangle's normal caused by a collapse (degrees).
  double max_normal_deviation_deg = 45.0;
  //! Shape floor for new triangles (Verdict shape). A new triangle below it is allowed only
  //! if it is no worse than the triangle it replaces (input slivers must not block).
  double min_shape = 0.2;
};

//! Non-binary priority module. Reads the sizing field "v:dthex_size" (written by
//! ModCurvatureSizingT, or by the app) and vertex/edge feature status bits:
//! - feature corners must be locked (status locked) - the decimater never removes them;
//! - a feature vertex (status feature) only collapses along a feature edge (decimater rule);
//! - no collapse may merge a feature edge of fl/fr with another edge (checked here).
//! Priority = l(AB); illegal when l >= 1 or a limit of NormalizedLengthLimits fails.
template <class MeshT>
class ModNormalizedLengthT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModNormalizedLengthT, MeshT, NormalizedLength);
  using Point = typename MeshT::Point;

  explicit ModNormalizedLengthT(MeshT& mesh) : Base(mesh, false) {}

  //! An edge is short (may collapse) below this normalized length: 1 up to rounding, so an
  //! input whose edges all equal their size (e.g. a uniform mesh at h_min) stays as it is.
  static constexpr double kShorterThanSize = 1.0 - 1e-9;

  void set_limits(const NormalizedLengthLimits& limits) {
    limits_ = limits;
    cos_bound_ = std::cos(deg_to_rad(limits.max_normal_deviation_deg));
  }
  const NormalizedLengthLimits& limits() const { return limits_; }

  //! Where A goes when B collapses into it, and its size there; false keeps A in place.
  using Placement = std::function<bool(const MeshT&, const CollapseInfo&, Point& position, double& size)>;
  //! Optional. A collapse that fails the limits with A in place is tried again with A at the
  //! placement (e.g. smoothed_collapse_target: where the post-collapse smoothing would put
  //! it), and if that passes, preprocess_collapse() moves A there. A halfedge collapse
  //! followed by smoothing otherwise has its bounds judged on the intermediate mesh, whose
  //! new edges span two rings: on a near-regular mesh they are ~1.7 edges long, so no
  //! collapse below the sqrt(2) bound exists long before the sizes are reached.
  void set_placement(Placement placement) { placement_ = std::move(placement); }

  //! The unit normal of the input surface where it is closest to a point; false if unknown.
  using SurfaceNormal = std::function<bool(const Point& p, Point& normal)>;
  //! Optional. A collapse is also illegal when a triangle it changes would face more than
  //! `max_deg` away from the input surface at the triangle's centroid, and further than it
  //! did before. The per-collapse normal bound compares a triangle with its previous self
  //! only, so turns can add up over many collapses; judged after smoothing, a coarse surface
  //! can end with a triangle facing away from the input where the shape narrows, and the
  //! hexes there stay inverted after projection.
  void set_surface_normal(SurfaceNormal surface_normal, double max_deg) {
    surface_normal_ = std::move(surface_normal);
    cos_surface_bound_ = std::cos(deg_to_rad(max_deg));
  }

  void initialize() override {
    if (!Base::mesh().get_property_handle(size_, size_property_name()))
      throw std::logic_error("ModNormalizedLengthT: vertex property v:dthex_size is missing "
                             "(add ModCurvatureSizingT before this module)");
  }

  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& m = Base::mesh();
    const double hA = m.property(size_, ci.v1), hB = m.property(size_, ci.v0);
    const double l = normalized_length((ci.p1 - ci.p0).norm(), hA, hB);
    if (!(l < kShorterThanSize)) return float(Base::ILLEGAL_COLLAPSE);
    if (keeps_shape(m, ci, ci.p1, hA)) return float(l);
    Point position;
    double h = hA;
    if (placement_ && placement_(m, ci, position, h) && keeps_shape(m, ci, position, h)) return float(l);
    return float(Base::ILLEGAL_COLLAPSE);
  }

  //! Moves A to the placement when the collapse is legal only there (see set_placement).
  void preprocess_collapse(const CollapseInfo& ci) override {
    if (!placement_) return;
    MeshT& m = Base::mesh();
    const double hA = m.property(size_, ci.v1);
    if (keeps_shape(m, ci, ci.p1, hA)) return;
    Point position;
    double h = hA;
    if (placement_(m, ci, position, h) && keeps_shape(m, ci, position, h)) {
      m.set_point(ci.v1, position);
      m.property(size_, ci.v1) = h;
    }
  }

  //! Lower bound of collapse_priority() for RevalidatingDecimaterT::set_priority_estimate:
  //! the normalized length alone (-1 when it is not below 1).
  static float priority_estimate(const MeshT& m, OpenMesh::VPropHandleT<double> size, const CollapseInfo& ci) {
    const double l = normalized_length((ci.p1 - ci.p0).norm(), m.property(size, ci.v1), m.property(size, ci.v0));
    return l < kShorterThanSize ? float(l) : float(Base::ILLEGAL_COLLAPSE);
  }

  //! The geometric part of the legality test (new edges, normals, shapes, feature wings)
  //! as a plain function, for decimaters and checks outside this module.
  static bool collapse_keeps_shape(const MeshT& m, const CollapseInfo& ci,
                                   OpenMesh::VPropHandleT<double> size, const NormalizedLengthLimits& limits) {
    return collapse_keeps_shape(m, ci, size, limits, std::cos(deg_to_rad(limits.max_normal_deviation_deg)), ci.p1,
                                m.property(size, ci.v1));
  }

 private:
  bool keeps_shape(const MeshT& m, const CollapseInfo& ci, const Point& pA, double hA) const {
    return collapse_keeps_shape(m, ci, size_, limits_, cos_bound_, pA, hA, surface_normal_ ? &surface_normal_ : nullptr,
                                cos_surface_bound_);
  }

  //! The limits with A at pA (size hA) after the collapse: every new edge A-P_i below the
  //! bound; when A moved, its kept edges too (as local smoothing requires); no triangle around
  //! A or B turned too far or newly below the shape floor.
  static bool collapse_keeps_shape(const MeshT& m, const CollapseInfo& ci, OpenMesh::VPropHandleT<double> size,
                                   const NormalizedLengthLimits& limits, double cos_bound, const Point& pA,
                                   double hA, const SurfaceNormal* surface_normal = nullptr,
                                   double cos_surface_bound = -1) {
    // Feature edges of the two vanishing triangles would be merged with non-feature ones.
    if (m.has_edge_status()) {
      const typename MeshT::HalfedgeHandle wings[4] = {ci.vlv1, ci.v0vl, ci.vrv0, ci.v1vr};
      for (auto h : wings)
        if (h.is_valid() && m.status(m.edge_handle(h)).feature()) return false;
    }
    const bool moved = !(pA == ci.p1);
    auto edge_ok = [&](const Point& q, double hP) {
      const double d = (q - pA).norm();
      if (d < limits.max_normalized_length * std::min(hA, hP)) return true;  // l <= d / min(h)
      return normalized_length(d, hA, hP) < limits.max_normalized_length;
    };
    // New edges A-P_i (P_i in ring(B) but not already adjacent to A: vl, vr).
    for (auto q : m.vv_range(ci.v0)) {
      if (q == ci.v1 || q == ci.vl || q == ci.vr) continue;
      if (!edge_ok(m.point(q), m.property(size, q))) return false;
    }
    if (moved)
      for (auto q : m.vv_range(ci.v1)) {
        if (q == ci.v0) continue;
        const Point pq = m.point(q);
        if (!edge_ok(pq, m.property(size, q))) return false;
      }
    // Triangles around B that survive with B replaced by A, and (if A moved) around A.
    // The surface-normal test needs a closest-point query per triangle, the costliest part
    // of coarsening, so it runs only once every cheap test of both rings has passed.
    struct Changed {
      Point centroid, n_new, n_old;
      double ln, lo;
    };
    thread_local std::vector<Changed> changed;
    changed.clear();
    auto triangles_ok = [&](typename MeshT::VertexHandle center, const Point& p_old) {
      for (auto h : m.voh_range(center)) {
        const auto f = m.face_handle(h);
        if (!f.is_valid() || f == ci.fl || f == ci.fr) continue;
        const Point a = m.point(m.to_vertex_handle(h));
        const Point b = m.point(m.to_vertex_handle(m.next_halfedge_handle(h)));
        const Point n_old = triangle_normal(p_old, a, b), n_new = triangle_normal(pA, a, b);
        const double lo = n_old.norm(), ln = n_new.norm();
        if (!(ln > 0) || !(lo > 0)) return false;
        if (double(n_old | n_new) < cos_bound * lo * ln) return false;
        const double shape_new = triangle_shape(pA, a, b);
        if (shape_new < limits.min_shape && shape_new < triangle_shape(p_old, a, b)) return false;
        if (surface_normal) changed.push_back({(pA + a + b) / 3, n_new, n_old, ln, lo});
      }
      return true;
    };
    if (!triangles_ok(ci.v0, ci.p0) || (moved && !triangles_ok(ci.v1, ci.p1))) return false;
    for (const Changed& t : changed) {
      Point reference;
      if ((*surface_normal)(t.centroid, reference)) {
        const double cos_new = double(t.n_new | reference) / t.ln, cos_old = double(t.n_old | reference) / t.lo;
        if (cos_new < cos_surface_bound && cos_new < cos_old) return false;
      }
    }
    return true;
  }

  OpenMesh::VPropHandleT<double> size_;
  NormalizedLengthLimits limits_;
  Placement placement_;
  SurfaceNormal surface_normal_;
  double cos_surface_bound_ = -1;
  double cos_bound_ = std::cos(deg_to_rad(NormalizedLengthLimits().max_normal_deviation_deg));
};

}  // namespace dthex
