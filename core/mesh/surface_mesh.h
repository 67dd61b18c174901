// SPDX-License-Identifier: MIT
// The OpenMesh triangle mesh type the coarsening modules run on, and conversions
// to and from the plain TriSurface the rest of the pipeline uses.
#pragma once

#include <dthex/mesh/types.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace dthex {

struct SurfaceTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};

//! Status (needed by the Decimater) and normals are requested for the mesh's lifetime.
using SurfaceMesh = OpenMesh::TriMesh_ArrayKernelT<SurfaceTraits>;

//! Builds an OpenMesh mesh from a verified (closed, manifold) surface. Its normals are not
//! computed (om_dthex computes the normals it needs from the points; on millions of triangles
//! they were a fifth of the time): call update_normals() where the stored ones are read.
//! Throws InputError if OpenMesh refuses a face (it should not on a verified surface).
SurfaceMesh to_openmesh(const TriSurface& surface);
//! As to_openmesh(), into an empty `mesh`: OpenMesh 9's meshes have no move assignment, so
//! `existing = to_openmesh(s)` copies the whole mesh once more.
void fill_openmesh(SurfaceMesh& mesh, const TriSurface& surface);
//! fill_openmesh's way to the mesh OpenMesh's add_face makes, a triangle at a time, without
//! add_face's search around each vertex for an edge (half of the time of reading a surface of
//! millions of triangles): the edges are numbered first, in the order add_face creates them,
//! the arrays sized once, and add_face (PolyConnectivity.cc, OpenMesh 9) is then replayed on
//! them step by step: its checks, its re-linking of patches, its next-halfedge updates and its
//! choice of each vertex's outgoing halfedge, so that every handle and link, and with them the
//! order in which circulators visit a vertex's neighbours, end as add_face sets them. Into an
//! empty `mesh`; false, with `mesh` partly built, at the first triangle add_face would refuse
//! (fill_openmesh then names it) or one that repeats a vertex or names one out of range.
bool replay_add_faces(SurfaceMesh& mesh, const TriSurface& surface);
//! Copies the live (non-deleted) vertices and faces, compacting indices.
TriSurface from_openmesh(const SurfaceMesh& mesh);

inline Vec3 to_eigen(const OpenMesh::Vec3d& p) { return Vec3(p[0], p[1], p[2]); }
inline OpenMesh::Vec3d to_openmesh(const Vec3& p) { return OpenMesh::Vec3d(p.x(), p.y(), p.z()); }

}  // namespace dthex
