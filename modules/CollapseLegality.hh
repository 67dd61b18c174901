// SPDX-License-Identifier: MIT
// The topological test of a halfedge collapse that OpenMesh's decimaters make before every
// collapse: BaseDecimaterT::is_collapse_legal (locks, features, boundary cases, two valence-3
// vertices) with TriConnectivity::is_collapse_ok (deleted items, boundary ears, one-ring
// intersection) inside it. Same answers, read straight from the mesh's arrays: the library's
// versions reach every handle through out-of-line calls (and, where OpenMesh is built with
// assertions, check the status property's type by name at every access), which made the test
// a tenth of the coarsening of a million-triangle input. Unlike the library's, it writes
// nothing (is_collapse_ok sets the tagged bit of the vertices around the edge).
#pragma once

#include <OpenMesh/Tools/Decimater/CollapseInfoT.hh>

namespace dthex {

//! Calls visit(w) for each vertex w joined to v by an edge (v must have an outgoing halfedge);
//! stops early, returning true, when visit returns true.
template <class Mesh, class Visit>
bool any_neighbour(const Mesh& mesh, typename Mesh::VertexHandle v, Visit&& visit) {
  const typename Mesh::HalfedgeHandle start = mesh.halfedge_handle(v);
  typename Mesh::HalfedgeHandle h = start;
  do {
    if (visit(mesh.to_vertex_handle(h))) return true;
    h = mesh.cw_rotated_halfedge_handle(h);
  } while (h != start);
  return false;
}

//! TriConnectivity::is_collapse_ok(v0v1): false if the edge or either vertex is deleted, if
//! a triangle beside the edge has its two other edges on the boundary, if vl and vr (the
//! vertices opposite the edge) are equal or both missing, if v0 and v1 share a neighbour other
//! than vl and vr, or if both are boundary vertices joined by an inner edge. Needs the status
//! attributes of vertices and edges.
template <class Mesh>
bool collapse_is_ok(const Mesh& mesh, typename Mesh::HalfedgeHandle v0v1) {
  using VertexHandle = typename Mesh::VertexHandle;
  using HalfedgeHandle = typename Mesh::HalfedgeHandle;
  if (mesh.status(mesh.edge_handle(v0v1)).deleted()) return false;
  const HalfedgeHandle v1v0 = mesh.opposite_halfedge_handle(v0v1);
  const VertexHandle v0 = mesh.to_vertex_handle(v1v0), v1 = mesh.to_vertex_handle(v0v1);
  if (mesh.status(v0).deleted() || mesh.status(v1).deleted()) return false;
  // The vertex opposite the edge in the triangle of `h`; false if that triangle's two other
  // edges are both on the boundary.
  auto opposite = [&mesh](HalfedgeHandle h, VertexHandle& apex) {
    const HalfedgeHandle h1 = mesh.next_halfedge_handle(h), h2 = mesh.next_halfedge_handle(h1);
    apex = mesh.to_vertex_handle(h1);
    return !(mesh.is_boundary(mesh.opposite_halfedge_handle(h1)) && mesh.is_boundary(mesh.opposite_halfedge_handle(h2)));
  };
  VertexHandle vl, vr;
  if (!mesh.is_boundary(v0v1) && !opposite(v0v1, vl)) return false;
  if (!mesh.is_boundary(v1v0) && !opposite(v1v0, vr)) return false;
  if (vl == vr) return false;
  // The one-rings of v0 and v1 may meet only at vl and vr.
  const bool ring_meets = any_neighbour(mesh, v0, [&](VertexHandle w) {
    if (w == vl || w == vr) return false;
    return any_neighbour(mesh, v1, [w](VertexHandle u) { return u == w; });
  });
  if (ring_meets) return false;
  return !(mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(v0v1) && !mesh.is_boundary(v1v0));
}

//! BaseDecimaterT::is_collapse_legal(ci): v0 not locked, collapse_is_ok, not both vl and vr of
//! valence 3 and joined by an edge, a feature vertex only along a feature edge, a boundary
//! vertex only onto a boundary vertex and only beside one triangle, and at least two
//! triangles at v0. Needs the status attributes of vertices and edges.
template <class Mesh>
bool collapse_is_legal(const Mesh& mesh, const OpenMesh::Decimater::CollapseInfoT<Mesh>& ci) {
  using VertexHandle = typename Mesh::VertexHandle;
  if (mesh.status(ci.v0).locked()) return false;
  if (!collapse_is_ok(mesh, ci.v0v1)) return false;
  if (ci.vl.is_valid() && ci.vr.is_valid()) {
    const VertexHandle vr = ci.vr;
    const bool joined = any_neighbour(mesh, ci.vl, [vr](VertexHandle w) { return w == vr; });
    auto valence = [&mesh](VertexHandle v) {
      int count = 0;
      any_neighbour(mesh, v, [&count](VertexHandle) { return ++count > 3; });
      return count;
    };
    if (joined && valence(ci.vl) == 3 && valence(ci.vr) == 3) return false;
  }
  if (mesh.status(ci.v0).feature() && !mesh.status(mesh.edge_handle(ci.v0v1)).feature()) return false;
  if (mesh.is_boundary(ci.v0) && (!mesh.is_boundary(ci.v1) || (ci.vl.is_valid() && ci.vr.is_valid()))) return false;
  return mesh.cw_rotated_halfedge_handle(mesh.cw_rotated_halfedge_handle(ci.v0v1)) != ci.v0v1;
}

}  // namespace dthex
