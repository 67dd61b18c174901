// SPDX-License-Identifier: MIT
// collapse_is_legal: the same answer as OpenMesh's BaseDecimaterT::is_collapse_legal for every
// halfedge of a mesh with locked and feature vertices, feature edges, a boundary, valence-3
// vertices and deleted items; and it writes nothing.
#include <dthex/modules/CollapseLegality.hh>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>
#include "icosphere.h"

#include <gtest/gtest.h>

namespace {

struct LegalityTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using LegalityMesh = OpenMesh::TriMesh_ArrayKernelT<LegalityTraits>;
using CollapseInfo = OpenMesh::Decimater::CollapseInfoT<LegalityMesh>;

//! The library's test, which BaseDecimaterT keeps protected.
struct LibraryLegality : OpenMesh::Decimater::BaseDecimaterT<LegalityMesh> {
  explicit LibraryLegality(LegalityMesh& mesh) : BaseDecimaterT(mesh) {}
  bool legal(const CollapseInfo& ci) { return is_collapse_legal(ci); }
};

//! Every halfedge's answer from both tests; the number of legal collapses.
size_t expect_same_answers(LegalityMesh& mesh) {
  LibraryLegality library(mesh);
  size_t legal = 0;
  for (auto h : mesh.halfedges()) {
    const CollapseInfo ci(mesh, h);
    const bool ours = dthex::collapse_is_legal(mesh, ci);
    EXPECT_EQ(ours, library.legal(ci)) << "halfedge " << h.idx();
    legal += ours;
  }
  return legal;
}

LegalityMesh marked_icosphere() {
  LegalityMesh mesh = dthex_test::openmesh_icosphere<LegalityMesh>(2);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  for (auto v : mesh.vertices()) {
    if (v.idx() % 7 == 0) mesh.status(v).set_locked(true);
    if (v.idx() % 5 == 0) mesh.status(v).set_feature(true);
  }
  for (auto e : mesh.edges())
    if (e.idx() % 4 == 0) mesh.status(e).set_feature(true);
  return mesh;
}

}  // namespace

TEST(CollapseLegality, SameAnswersAsOpenMeshOnAClosedSurface) {
  LegalityMesh mesh = marked_icosphere();
  const size_t legal = expect_same_answers(mesh);
  EXPECT_GT(legal, 0u);
  EXPECT_LT(legal, mesh.n_halfedges());
}

TEST(CollapseLegality, SameAnswersWithABoundaryDeletedItemsAndValenceThreeVertices) {
  LegalityMesh mesh = marked_icosphere();
  // A hole of two triangles (a boundary with ears), then collapses that delete items and
  // leave vertices of valence 3 behind.
  mesh.delete_face(LegalityMesh::FaceHandle(0), false);
  mesh.delete_face(LegalityMesh::FaceHandle(1), false);
  size_t collapsed = 0;
  for (auto h : mesh.halfedges()) {
    if (collapsed == 40) break;
    const CollapseInfo ci(mesh, h);
    if (!dthex::collapse_is_legal(mesh, ci)) continue;
    mesh.collapse(h);
    ++collapsed;
  }
  EXPECT_EQ(collapsed, 40u);
  bool valence_three = false;
  for (auto v : mesh.vertices())
    if (!mesh.status(v).deleted() && mesh.valence(v) == 3) valence_three = true;
  EXPECT_TRUE(valence_three);
  expect_same_answers(mesh);
}

TEST(CollapseLegality, WritesNothing) {
  LegalityMesh mesh = marked_icosphere();
  for (auto v : mesh.vertices()) mesh.status(v).set_tagged(v.idx() % 2 == 0);
  for (auto h : mesh.halfedges()) dthex::collapse_is_legal(mesh, CollapseInfo(mesh, h));
  for (auto v : mesh.vertices()) EXPECT_EQ(mesh.status(v).tagged(), v.idx() % 2 == 0);
}
