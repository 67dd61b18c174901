// SPDX-License-Identifier: MIT
// A greedy decimater that stays correct when post-collapse modules flip edges and move
// vertices (OpenMesh's DecimaterT only re-checks topology when it pops a stored collapse).
#pragma once

#include "CollapseLegality.hh"
#include "DTHexTouched.hh"

#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>

#include <algorithm>
#include <functional>
#include <queue>
#include <vector>

namespace dthex {

//! Same modules and observer as OpenMesh's DecimaterT, different queue:
//! - a lazy min-heap of (priority, vertex, stamp); re-queuing a vertex bumps its stamp so
//!   older entries are skipped;
//! - on pop, the stored halfedge must still start at the popped vertex, and both
//!   collapse_is_legal() (OpenMesh's is_collapse_legal(): topology, locks, features) and
//!   collapse_priority() (every binary module, then the priority module) are evaluated
//!   again on the mesh as it is now; a failing or worsened entry is re-queued with its
//!   current best collapse instead;
//! - after postprocess_collapse, re-queues the old one-ring of v0, the ring of v1, and every
//!   vertex listed in "m:dthex_touched" (a moved vertex changes its neighbours' collapses
//!   too, but their stale entries are caught on pop, so their rings are not re-queued);
//! - when the queue runs empty, re-queues every live vertex once more, and stops only when
//!   that finds nothing (collapses that became legal far from where the mesh changed).
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

  //! Optional cheap lower bound of collapse_priority(): for any collapse it must return a
  //! value <= collapse_priority() whenever that is legal, and may return < 0 only when the
  //! collapse is certainly illegal. With it, re-queued vertices are keyed by the estimate and
  //! fully evaluated only when they reach the top (lazy evaluation; same greedy order).
  void set_priority_estimate(std::function<float(const CollapseInfo&)> estimate) { estimate_ = std::move(estimate); }

  //! Number of popped collapses found illegal or worse than queued (then re-queued).
  size_t n_revalidation_failures() const { return failures_; }

  //! Collapses until no legal collapse is left or n_collapses (0 = no limit) are done.
  //! Returns the number of collapses; 0 if initialize() fails.
  size_t decimate(size_t n_collapses = 0) {
    if (!this->is_initialized() && !this->initialize()) return 0;
    stamp_.assign(mesh_.n_vertices(), 0);
    queue_ = Queue();
    for (auto v : mesh_.vertices())
      if (!mesh_.status(v).deleted()) heap_vertex(v);
    size_t done = 0, done_at_sweep = 0;
    std::vector<VertexHandle> support, requeue;
    while (n_collapses == 0 || done < n_collapses) {
      if (queue_.empty()) {
        if (done == done_at_sweep) break;  // a full sweep found nothing new
        done_at_sweep = done;
        for (auto v : mesh_.vertices())
          if (!mesh_.status(v).deleted()) heap_vertex(v);
        if (queue_.empty()) break;
      }
      const Entry top = queue_.top();
      queue_.pop();
      const VertexHandle v0(top.vertex);
      if (top.stamp != stamp_[size_t(top.vertex)] || mesh_.status(v0).deleted()) continue;
      HalfedgeHandle h(top.halfedge);
      float priority = -1.f;
      if (top.estimated) {
        // Full evaluation now; execute at once if nothing queued can come before it.
        h = best_collapse(v0, priority);
        if (!h.is_valid()) {
          ++stamp_[size_t(v0.idx())];
          continue;
        }
        if (!queue_.empty() && queue_.top().priority < priority) {
          queue_.push(Entry{priority, v0.idx(), h.idx(), ++stamp_[size_t(v0.idx())], false});
          continue;
        }
      } else {
        if (mesh_.status(mesh_.edge_handle(h)).deleted() || mesh_.from_vertex_handle(h) != v0) {
          heap_vertex(v0);
          continue;
        }
        CollapseInfo check(mesh_, h);
        priority = collapse_is_legal(mesh_, check) ? this->collapse_priority(check) : -1.f;
        if (priority < 0 || priority > top.priority) {  // stale: re-evaluate from scratch
          ++failures_;
          heap_vertex(v0);
          continue;
        }
      }
      CollapseInfo ci(mesh_, h);
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
      requeue.insert(requeue.end(), touched.begin(), touched.end());
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
    bool estimated;  //!< priority is a lower bound, halfedge not chosen yet
    bool operator>(const Entry& o) const { return priority > o.priority; }
  };
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;

  //! Queues v: keyed by the estimate of its best outgoing collapse when an estimate is set,
  //! otherwise with its best fully evaluated legal collapse.
  void heap_vertex(VertexHandle v) {
    const unsigned stamp = ++stamp_[size_t(v.idx())];
    if (mesh_.status(v).locked()) return;
    if (estimate_) {
      float best = -1.f;
      for (auto h : mesh_.voh_range(v)) {
        const float e = estimate_(CollapseInfo(mesh_, h));
        if (e >= 0 && (best < 0 || e < best)) best = e;
      }
      if (best >= 0) queue_.push(Entry{best, v.idx(), -1, stamp, true});
      return;
    }
    float priority = -1.f;
    const HalfedgeHandle h = best_collapse(v, priority);
    if (h.is_valid()) queue_.push(Entry{priority, v.idx(), h.idx(), stamp, false});
  }

  //! v's legal outgoing collapse of lowest priority (invalid handle if none). Priorities
  //! (geometry) are cheap next to the topology test, so that runs in priority order only
  //! until one candidate passes. With an estimate, candidates are ordered by it and fully
  //! evaluated in that order: a legal collapse's priority equals its estimate's rank
  //! (the estimate is a lower bound), so the first legal one is the best and the rest are
  //! never evaluated; the full evaluation (closest-point queries on the input) dominated
  //! coarsening when every outgoing collapse was evaluated.
  HalfedgeHandle best_collapse(VertexHandle v, float& priority) {
    candidates_.clear();
    if (mesh_.status(v).locked()) return HalfedgeHandle();
    if (estimate_) {
      for (auto h : mesh_.voh_range(v)) {
        const float e = estimate_(CollapseInfo(mesh_, h));
        if (e >= 0) candidates_.push_back({e, h.idx()});
      }
      std::sort(candidates_.begin(), candidates_.end());
      float found = -1.f;
      HalfedgeHandle best;
      for (const auto& [e, h] : candidates_) {
        if (best.is_valid() && e > found) break;  // no later candidate can beat it
        const CollapseInfo ci(mesh_, HalfedgeHandle(h));
        const float p = this->collapse_priority(ci);
        if (p < 0 || (best.is_valid() && !(p < found))) continue;
        if (!collapse_is_legal(mesh_, ci)) continue;
        found = p;
        best = HalfedgeHandle(h);
      }
      priority = found;
      return best;
    }
    for (auto h : mesh_.voh_range(v)) {
      const float p = this->collapse_priority(CollapseInfo(mesh_, h));
      if (p >= 0) candidates_.push_back({p, h.idx()});
    }
    std::sort(candidates_.begin(), candidates_.end());
    for (const auto& [p, h] : candidates_)
      if (collapse_is_legal(mesh_, CollapseInfo(mesh_, HalfedgeHandle(h)))) {
        priority = p;
        return HalfedgeHandle(h);
      }
    return HalfedgeHandle();
  }

  Mesh& mesh_;
  OpenMesh::MPropHandleT<std::vector<VertexHandle>> touched_;
  std::vector<unsigned> stamp_;
  std::vector<std::pair<float, int>> candidates_;
  std::function<float(const CollapseInfo&)> estimate_;
  size_t failures_ = 0;
  Queue queue_;
};

}  // namespace dthex
