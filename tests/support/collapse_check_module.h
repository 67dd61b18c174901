// SPDX-License-Identifier: MIT
// A Decimater module for the module tests: it judges every collapse the decimater executes,
// at the moment it is executed, by the normalized-length module's own test and the topology
// test, so a decimater that executes a collapse its modules would now reject is caught.
#pragma once

#include <dthex/modules/ModNormalizedLengthT.hh>

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <cstddef>

namespace dthex_test {

//! Binary, always legal: just before each executed collapse (preprocess), asks whether it is
//! allowed on the mesh as it is then (normalized length below 1, OpenMesh's is_collapse_ok, the
//! kept vertex not locked, the shape bound of dthex::NormalizedLengthLimits' defaults), and
//! counts the executed collapses and the ones that are not allowed. Reads the sizes the
//! sizing module (or the test) stored in dthex::size_property_name().
template <class MeshT>
class ModCollapseCheckT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModCollapseCheckT, MeshT, CollapseCheck);
  explicit ModCollapseCheckT(MeshT& mesh) : Base(mesh, true) {}
  void initialize() override { Base::mesh().get_property_handle(size_, dthex::size_property_name()); }
  float collapse_priority(const CollapseInfo&) override { return float(Base::LEGAL_COLLAPSE); }
  void preprocess_collapse(const CollapseInfo& ci) override {
    auto& m = Base::mesh();
    ++executed;
    const double l = dthex::normalized_length((ci.p1 - ci.p0).norm(), m.property(size_, ci.v1), m.property(size_, ci.v0));
    const bool ok = l < 1.0 && m.is_collapse_ok(ci.v0v1) && !m.status(ci.v0).locked() &&
                    dthex::ModNormalizedLengthT<MeshT>::collapse_keeps_shape(m, ci, size_, dthex::NormalizedLengthLimits{});
    if (!ok) ++rejected;
  }
  size_t executed = 0, rejected = 0;

 private:
  OpenMesh::VPropHandleT<double> size_;
};

}  // namespace dthex_test
