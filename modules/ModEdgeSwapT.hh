// SPDX-License-Identifier: MIT
// Post-collapse edge swaps around the kept vertex (docs/METHOD.md section 3, Coarsening: After
// each collapse), as a Decimater module.
#pragma once

#include "DTHexTouched.hh"

#include <OpenMesh/Tools/Decimater/ModBaseT.hh>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dthex {

struct EdgeSwapOptions {
  //! The two triangles of a swapped edge must be this close to coplanar (angle between
  //! their normals, degrees): a swap across a crease would change the shape of the surface.
  double max_dihedral_deg = 10.0;
  //! The new edge must stay below this normalized length (when a size field exists).
  double max_normalized_length = std::sqrt(2.0);
  //! Passes around the vertex (a swap changes its ring, so later edges may become swappable).
  int passes = 2;
};

//! Flips edges incident to v when that raises the worse of the two triangles' shapes, the
//! triangles are nearly coplanar, the edge is no feature, mesh.is_flip_ok() holds and the
//! new triangles keep the orientation. Face normals of flipped faces are updated when the
//! mesh has them. Returns the number of flips; appends p, c, d of each flipped edge v-p
//! (new edge c-d) to touched when given. size: the sizing property, or an invalid handle.
template <class Mesh>
size_t swap_edges_around(Mesh& mesh, typename Mesh::VertexHandle v, const EdgeSwapOptions& options,
                         OpenMesh::VPropHandleT<double> size,
                         std::vector<typename Mesh::VertexHandle>* touched = nullptr) {
  using Point = typename Mesh::Point;
  const double cos_dihedral = std::cos(deg_to_rad(options.max_dihedral_deg));
  size_t flips = 0;
  // Reused per thread: this runs after every collapse, and a new list grew through several
  // allocations each time.
  thread_local std::vector<typename Mesh::EdgeHandle> edges;
  for (int pass = 0; pass < options.passes; ++pass) {
    edges.clear();
    for (auto h : mesh.voh_range(v)) edges.push_back(mesh.edge_handle(h));
    size_t flips_this_pass = 0;
    for (auto e : edges) {
      if (mesh.status(e).deleted() || mesh.is_boundary(e) || mesh.status(e).feature()) continue;
      auto h = mesh.halfedge_handle(e, 0);
      if (mesh.from_vertex_handle(h) != v) h = mesh.opposite_halfedge_handle(h);
      if (mesh.from_vertex_handle(h) != v) continue;
      const auto o = mesh.opposite_halfedge_handle(h);
      const auto vp = mesh.to_vertex_handle(h);
      const auto vc = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
      const auto vd = mesh.to_vertex_handle(mesh.next_halfedge_handle(o));
      const Point pv = mesh.point(v), pp = mesh.point(vp), pc = mesh.point(vc), pd = mesh.point(vd);
      // Old triangles (v, p, c), (p, v, d); new ones (v, d, c), (d, p, c).
      const Point n1 = triangle_normal(pv, pp, pc), n2 = triangle_normal(pp, pv, pd);
      const double l1 = n1.norm(), l2 = n2.norm();
      if (!(l1 > 0) || !(l2 > 0) || double(n1 | n2) < cos_dihedral * l1 * l2) continue;
      const double old_shape = std::min(triangle_shape(pv, pp, pc), triangle_shape(pp, pv, pd));
      const double new_shape = std::min(triangle_shape(pv, pd, pc), triangle_shape(pd, pp, pc));
      if (!(new_shape > old_shape + 1e-6)) continue;
      const Point reference = n1 / l1 + n2 / l2;
      const Point m1 = triangle_normal(pv, pd, pc), m2 = triangle_normal(pd, pp, pc);
      const double rl = reference.norm();
      if (double(m1 | reference) < cos_dihedral * m1.norm() * rl ||
          double(m2 | reference) < cos_dihedral * m2.norm() * rl)
        continue;
      if (size.is_valid() &&
          !(normalized_length((pc - pd).norm(), mesh.property(size, vc), mesh.property(size, vd)) <
            options.max_normalized_length))
        continue;
      if (!mesh.is_flip_ok(e)) continue;
      mesh.flip(e);
      ++flips;
      ++flips_this_pass;
      if (mesh.has_face_normals()) {
        for (int i = 0; i < 2; ++i) {
          const auto f = mesh.face_handle(mesh.halfedge_handle(e, i));
          mesh.set_normal(f, mesh.calc_face_normal(f));
        }
      }
      if (touched) {
        touched->push_back(vp);
        touched->push_back(vc);
        touched->push_back(vd);
      }
    }
    if (flips_this_pass == 0) break;
  }
  return flips;
}

//! Binary, always-legal module: after each collapse, swaps edges around the kept vertex
//! (swap_edges_around) and lists the vertices it changed in "m:dthex_touched".
template <class MeshT>
class ModEdgeSwapT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModEdgeSwapT, MeshT, EdgeSwap);

  explicit ModEdgeSwapT(MeshT& mesh) : Base(mesh, true) { touched_ = touched_property(mesh); }

  void set_options(const EdgeSwapOptions& options) { options_ = options; }
  const EdgeSwapOptions& options() const { return options_; }
  size_t n_swaps() const { return swaps_; }

  void initialize() override {
    if (!Base::mesh().get_property_handle(size_, size_property_name())) size_.reset();
    swaps_ = 0;
  }
  float collapse_priority(const CollapseInfo&) override { return float(Base::LEGAL_COLLAPSE); }
  void preprocess_collapse(const CollapseInfo&) override { Base::mesh().property(touched_).clear(); }
  void postprocess_collapse(const CollapseInfo& ci) override {
    auto& mesh = Base::mesh();
    swaps_ += swap_edges_around(mesh, ci.v1, options_, size_, &mesh.property(touched_));
  }

 private:
  OpenMesh::MPropHandleT<std::vector<typename MeshT::VertexHandle>> touched_;
  OpenMesh::VPropHandleT<double> size_;
  EdgeSwapOptions options_;
  size_t swaps_ = 0;
};

}  // namespace dthex
