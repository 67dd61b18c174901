// SPDX-License-Identifier: MIT
// A greedy decimater that stays correct when post-collapse modules flip edges and move
// vertices (OpenMesh's DecimaterT only re-checks topology when it pops a stored collapse).
#pragma once

#include "DThexTouched.hh"

#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>

#include <algorithm>
#include <queue>
#include <vector>

namespace dthex {

//! Same modules and observer as OpenMesh's DecimaterT, different queue:
//! - a lazy min-heap of (priority, vertex, stamp); re-queuing a vertex bumps its stamp so
//!   older entries are skipped;
//! - on pop, the stored halfedge must still start at the popped vertex, and both
//!   is_collapse_legal() (topology, locks, features) and collapse_priority() (every binary
//!   module, then the priority module) are evaluated again on the mesh as it is now; a
//!   failing or worsened entry is re-queued with its current best collapse instead;
//! - after postprocess_collapse, re-queues the old one-ring of v0, the ring of v1, and every
//!   vertex listed in "m:dthex_touched" with its ring.
//! The app must request vertex, edge and face status on the mesh before constructing any
//! decimater (BaseDecimaterT releases the status it requested itself when destroyed).
template <class MeshT>
class RevalidatingDecimaterT : public OpenMesh::Decimater::BaseDecimaterT<MeshT> {
 public:
  using Base = OpenMesh::Decimater::BaseDecimaterT<MeshT>;
  using Mesh = MeshT;
  using CollapseInfo = typename Base::CollapseInfo;
  using VertexHandle = typename Mesh::VertexHandle;
  using HalfedgeHandle = typename Mesh::HalfedgeHandle;

  explicit RevalidatingDecimaterT(Mesh& mesh) : Base(mesh), mesh_(mesh) { touched_ = touched_property(mesh); }

  //! Collapses until no legal collapse is left or n_collapses (0 = no limit) are done.
  //! Returns the number of collapses; 0 if initialize() fails.
  size_t decimate(size_t n_collapses = 0) {
    if (!this->is_initialized() && !this->initialize()) return 0;
    stamp_.assign(mesh_.n_vertices(), 0);
    queue_ = Queue();
    for (auto v : mesh_.vertices())
      if (!mesh_.status(v).deleted()) heap_vertex(v);
    size_t done = 0;
    std::vector<VertexHandle> support, requeue;
    while (!queue_.empty() && (n_collapses == 0 || done < n_collapses)) {
      const Entry top = queue_.top();
      queue_.pop();
      const VertexHandle v0(top.vertex);
      if (top.stamp != stamp_[size_t(top.vertex)] || mesh_.status(v0).deleted()) continue;
      const HalfedgeHandle h(top.halfedge);
      if (mesh_.status(mesh_.edge_handle(h)).deleted() || mesh_.from_vertex_handle(h) != v0) {
        heap_vertex(v0);
        continue;
      }
      CollapseInfo ci(mesh_, h);
      const float priority = this->is_collapse_legal(ci) ? this->collapse_priority(ci) : -1.f;
      if (priority < 0 || priority > top.priority) {  // stale: re-evaluate from scratch
        heap_vertex(v0);
        continue;
      }
      support.clear();
      for (auto v : mesh_.vv_range(v0)) support.push_back(v);
      this->preprocess_collapse(ci);
      mesh_.collapse(h);
      if (mesh_.has_face_normals())
        for (auto f : mesh_.vf_range(ci.v1)) mesh_.set_normal(f, mesh_.calc_face_normal(f));
      this->postprocess_collapse(ci);
      ++done;
      ++stamp_[size_t(v0.idx())];  // v0 is deleted: drop its entries

      requeue = support;
      for (auto v : mesh_.vv_range(ci.v1)) requeue.push_back(v);
      auto& touched = mesh_.property(touched_);
      for (auto t : touched) {
        requeue.push_back(t);
        for (auto v : mesh_.vv_range(t)) requeue.push_back(v);
      }
      touched.clear();
      std::sort(requeue.begin(), requeue.end());
      requeue.erase(std::unique(requeue.begin(), requeue.end()), requeue.end());
      for (auto v : requeue)
        if (!mesh_.status(v).deleted()) heap_vertex(v);
      if (!this->notify_observer(done)) break;
    }
    return done;
  }

  //! Collapses until at most n_vertices live vertices remain (or nothing is legal).
  size_t decimate_to(size_t n_vertices) {
    size_t live = 0;
    for (auto v : mesh_.vertices()) live += !mesh_.status(v).deleted();
    return live > n_vertices ? decimate(live - n_vertices) : 0;
  }

 private:
  struct Entry {
    float priority;
    int vertex, halfedge;
    unsigned stamp;
    bool operator>(const Entry& o) const { return priority > o.priority; }
  };
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;

  //! Queues v with its best (lowest-priority) legal outgoing collapse, if any.
  void heap_vertex(VertexHandle v) {
    const unsigned stamp = ++stamp_[size_t(v.idx())];
    if (mesh_.status(v).locked()) return;
    float best = -1.f;
    HalfedgeHandle best_h;
    for (auto h : mesh_.voh_range(v)) {
      CollapseInfo ci(mesh_, h);
      const float priority = this->collapse_priority(ci);  // geometry first: cheaper to reject
      if (priority < 0 || (best >= 0 && priority >= best)) continue;
      if (!this->is_collapse_legal(ci)) continue;
      best = priority;
      best_h = h;
    }
    if (best >= 0) queue_.push(Entry{best, v.idx(), best_h.idx(), stamp});
  }

  Mesh& mesh_;
  OpenMesh::MPropHandleT<std::vector<VertexHandle>> touched_;
  std::vector<unsigned> stamp_;
  Queue queue_;
};

}  // namespace dthex
