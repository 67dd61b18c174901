// SPDX-License-Identifier: MIT
// The DTHex priority module (DESIGN.md step 4): shortest normalized edge first, collapse
// B (= ci.v0, removed) into A (= ci.v1, kept) only while the edge is shorter than its size.
#pragma once

#include "DThexGeometry.hh"

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

  void set_limits(const NormalizedLengthLimits& limits) {
    limits_ = limits;
    cos_bound_ = std::cos(deg_to_rad(limits.max_normal_deviation_deg));
  }
  const NormalizedLengthLimits& limits() const { return limits_; }

  void initialize() override {
    if (!Base::mesh().get_property_handle(size_, size_property_name()))
      throw std::logic_error("ModNormalizedLengthT: vertex property v:dthex_size is missing "
                             "(add ModCurvatureSizingT before this module)");
  }

  float collapse_priority(const CollapseInfo& ci) override {
    const MeshT& m = Base::mesh();
    const double hA = m.property(size_, ci.v1), hB = m.property(size_, ci.v0);
    const double l = normalized_length((ci.p1 - ci.p0).norm(), hA, hB);
    if (!(l < 1.0)) return float(Base::ILLEGAL_COLLAPSE);
    if (!collapse_keeps_shape(m, ci, size_, limits_, cos_bound_)) return float(Base::ILLEGAL_COLLAPSE);
    return float(l);
  }

  //! Lower bound of collapse_priority() for RevalidatingDecimaterT::set_priority_estimate:
  //! the normalized length alone (-1 when it is not below 1).
  static float priority_estimate(const MeshT& m, OpenMesh::VPropHandleT<double> size, const CollapseInfo& ci) {
    const double l = normalized_length((ci.p1 - ci.p0).norm(), m.property(size, ci.v1), m.property(size, ci.v0));
    return l < 1.0 ? float(l) : float(Base::ILLEGAL_COLLAPSE);
  }

  //! The geometric part of the legality test (new edges, normals, shapes, feature wings)
  //! as a plain function, for decimaters and checks outside this module.
  static bool collapse_keeps_shape(const MeshT& m, const CollapseInfo& ci,
                                   OpenMesh::VPropHandleT<double> size, const NormalizedLengthLimits& limits) {
    return collapse_keeps_shape(m, ci, size, limits, std::cos(deg_to_rad(limits.max_normal_deviation_deg)));
  }

 private:
  static bool collapse_keeps_shape(const MeshT& m, const CollapseInfo& ci, OpenMesh::VPropHandleT<double> size,
                                   const NormalizedLengthLimits& limits, double cos_bound) {
    // Feature edges of the two vanishing triangles would be merged with non-feature ones.
    if (m.has_edge_status()) {
      const typename MeshT::HalfedgeHandle wings[4] = {ci.vlv1, ci.v0vl, ci.vrv0, ci.v1vr};
      for (auto h : wings)
        if (h.is_valid() && m.status(m.edge_handle(h)).feature()) return false;
    }
    const double hA = m.property(size, ci.v1);
    // New edges A-P_i (P_i in ring(B) but not already adjacent to A: vl, vr).
    for (auto q : m.vv_range(ci.v0)) {
      if (q == ci.v1 || q == ci.vl || q == ci.vr) continue;
      const double d = (m.point(q) - ci.p1).norm(), hP = m.property(size, q);
      if (d < limits.max_normalized_length * std::min(hA, hP)) continue;  // l <= d / min(h)
      if (!(normalized_length(d, hA, hP) < limits.max_normalized_length)) return false;
    }
    // Triangles around B that survive with B replaced by A.
    for (auto h : m.voh_range(ci.v0)) {
      const auto f = m.face_handle(h);
      if (!f.is_valid() || f == ci.fl || f == ci.fr) continue;
      const Point a = m.point(m.to_vertex_handle(h));
      const Point b = m.point(m.to_vertex_handle(m.next_halfedge_handle(h)));
      const Point n_old = triangle_normal(ci.p0, a, b), n_new = triangle_normal(ci.p1, a, b);
      const double lo = n_old.norm(), ln = n_new.norm();
      if (!(ln > 0) || !(lo > 0)) return false;
      if (double(n_old | n_new) < cos_bound * lo * ln) return false;
      const double shape_new = triangle_shape(ci.p1, a, b);
      if (shape_new < limits.min_shape && shape_new < triangle_shape(ci.p0, a, b)) return false;
    }
    return true;
  }

  OpenMesh::VPropHandleT<double> size_;
  NormalizedLengthLimits limits_;
  double cos_bound_ = std::cos(deg_to_rad(NormalizedLengthLimits().max_normal_deviation_deg));
};

}  // namespace dthex
