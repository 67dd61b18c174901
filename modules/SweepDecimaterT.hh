// SPDX-License-Identifier: MIT
// A decimater that collapses in sweeps over the edges, shortest first, instead of keeping a
// priority queue: for taking a very fine mesh most of the way down before a greedy decimater
// (RevalidatingDecimaterT) does the rest. On a million-vertex mesh the queue's upkeep (every
// collapse re-queues a dozen neighbours, and the heap grows with stale entries) is a large
// share of the time; a sweep only sorts the edges once.
#pragma once

#include "CollapseLegality.hh"

#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace dthex {

//! Same modules as OpenMesh's DecimaterT. Each sweep orders the live edges by a cheap
//! estimate of their collapse priority (set_priority_estimate: for an edge, the smaller over
//! its two halfedges; edges with none >= 0 are left out), then visits them in that order
//! and collapses each one that is still legal at that moment (collapse_is_legal() and
//! collapse_priority() >= 0 on the mesh as it is then; of its two halfedges, the one of
//! lower estimate first). The order is the greedy one only at the start of a sweep, so the
//! result is rougher than a greedy decimater's, which is why it is meant as a first pass.
//! Sweeps stop when one collapses fewer than min_share of the live vertices.
//! The app must request vertex, edge and face status on the mesh first.
template <class MeshT>
class SweepDecimaterT : public OpenMesh::Decimater::BaseDecimaterT<MeshT> {
 public:
  using Base = OpenMesh::Decimater::BaseDecimaterT<MeshT>;
  using Mesh = MeshT;
  using CollapseInfo = typename Base::CollapseInfo;
  using HalfedgeHandle = typename Mesh::HalfedgeHandle;

  explicit SweepDecimaterT(Mesh& mesh) : Base(mesh), mesh_(mesh) {}

  //! Required: a cheap lower bound of collapse_priority(), < 0 only when the collapse is
  //! certainly illegal (as RevalidatingDecimaterT::set_priority_estimate).
  void set_priority_estimate(std::function<float(const CollapseInfo&)> estimate) { estimate_ = std::move(estimate); }

  //! Sweeps (at most max_sweeps) until one collapses fewer than min_share of the live
  //! vertices. Returns the number of collapses; 0 if initialize() fails or no estimate is set.
  size_t decimate(size_t max_sweeps = 16, double min_share = 0.02) {
    if (!estimate_ || (!this->is_initialized() && !this->initialize())) return 0;
    size_t done = 0, live = 0;
    for (auto v : mesh_.vertices()) live += !mesh_.status(v).deleted();
    std::vector<std::pair<float, int>> order;  // (estimate, halfedge to try first)
    for (size_t sweep = 0; sweep < max_sweeps; ++sweep) {
      order.clear();
      for (auto e : mesh_.edges()) {
        if (mesh_.status(e).deleted()) continue;
        const HalfedgeHandle h0 = mesh_.halfedge_handle(e, 0), h1 = mesh_.halfedge_handle(e, 1);
        const float e0 = estimate_of(h0), e1 = estimate_of(h1);
        if (e0 < 0 && e1 < 0) continue;
        if (e1 < 0 || (e0 >= 0 && e0 <= e1)) order.emplace_back(e0, h0.idx());
        else order.emplace_back(e1, h1.idx());
      }
      std::sort(order.begin(), order.end());
      size_t collapsed = 0;
      for (const auto& [estimate, first] : order) {
        const HalfedgeHandle h(first);
        if (mesh_.status(mesh_.edge_handle(h)).deleted()) continue;
        if (try_collapse(h) || try_collapse(mesh_.opposite_halfedge_handle(h))) ++collapsed;
      }
      done += collapsed;
      live -= collapsed;
      if (collapsed == 0 || double(collapsed) < min_share * double(live)) break;
    }
    return done;
  }

 private:
  float estimate_of(HalfedgeHandle h) const {
    const auto v0 = mesh_.from_vertex_handle(h);
    if (mesh_.status(v0).locked()) return -1.f;
    return estimate_(CollapseInfo(mesh_, h));
  }

  bool try_collapse(HalfedgeHandle h) {
    if (mesh_.status(mesh_.from_vertex_handle(h)).deleted() || estimate_of(h) < 0) return false;
    CollapseInfo ci(mesh_, h);
    // The modules' test first: on a fine mesh it refuses about half of what it is asked, the
    // topological test (OpenMesh's, the dearer) hardly any. Both only read the mesh.
    if (this->collapse_priority(ci) < 0 || !collapse_is_legal(mesh_, ci)) return false;
    this->preprocess_collapse(ci);
    mesh_.collapse(h);
    if (mesh_.has_face_normals())
      for (auto f : mesh_.vf_range(ci.v1)) mesh_.set_normal(f, mesh_.calc_face_normal(f));
    this->postprocess_collapse(ci);
    return true;
  }

  Mesh& mesh_;
  std::function<float(const CollapseInfo&)> estimate_;
};

}  // namespace dthex
