// SPDX-License-Identifier: MIT
#include <dthex/mesh/surface_mesh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "bundled_meshes.h"

namespace dthex {
namespace {

using dthex_test::read_bundled_mesh;

// The mesh OpenMesh's own add_face makes, a triangle at a time: what the replay must equal.
SurfaceMesh built_by_add_face(const TriSurface& surface) {
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::VertexHandle> handles;
  for (const Vec3& p : surface.points) handles.push_back(mesh.add_vertex(to_openmesh(p)));
  for (const auto& t : surface.triangles)
    EXPECT_TRUE(mesh.add_face(handles[size_t(t[0])], handles[size_t(t[1])], handles[size_t(t[2])]).is_valid());
  return mesh;
}

// Every handle and link of the two meshes equal: the vertices' outgoing halfedges, the
// halfedges' next, previous, target and face, the faces' halfedges. The order in which the
// modules circulate around a vertex, and so every output, hangs on these.
void expect_same_connectivity(const SurfaceMesh& a, const SurfaceMesh& b) {
  ASSERT_EQ(a.n_vertices(), b.n_vertices());
  ASSERT_EQ(a.n_edges(), b.n_edges());
  ASSERT_EQ(a.n_faces(), b.n_faces());
  for (size_t i = 0; i < a.n_vertices(); ++i) {
    const SurfaceMesh::VertexHandle v{int(i)};
    ASSERT_EQ(a.halfedge_handle(v), b.halfedge_handle(v)) << "vertex " << i;
    ASSERT_EQ(a.point(v), b.point(v)) << "vertex " << i;
  }
  for (size_t i = 0; i < a.n_halfedges(); ++i) {
    const SurfaceMesh::HalfedgeHandle h{int(i)};
    ASSERT_EQ(a.next_halfedge_handle(h), b.next_halfedge_handle(h)) << "halfedge " << i;
    ASSERT_EQ(a.prev_halfedge_handle(h), b.prev_halfedge_handle(h)) << "halfedge " << i;
    ASSERT_EQ(a.to_vertex_handle(h), b.to_vertex_handle(h)) << "halfedge " << i;
    ASSERT_EQ(a.face_handle(h), b.face_handle(h)) << "halfedge " << i;
  }
  for (size_t i = 0; i < a.n_faces(); ++i) {
    const SurfaceMesh::FaceHandle f{int(i)};
    ASSERT_EQ(a.halfedge_handle(f), b.halfedge_handle(f)) << "face " << i;
  }
}

TEST(ReplayAddFaces, MakesTheMeshAddFaceMakesInFileOrder) {
  for (const std::string name : {"spot.off", "liver.off", "icosahedron.off"}) {
    SCOPED_TRACE(name);
    const TriSurface surface = read_bundled_mesh(name);
    SurfaceMesh fast;
    ASSERT_TRUE(replay_add_faces(fast, surface));
    expect_same_connectivity(fast, built_by_add_face(surface));
  }
}

// Triangles in random order meet as separate patches around a vertex, which add_face links up
// as it goes (its re-linking and its adjustment of outgoing halfedges); an open surface keeps
// boundary halfedges to the end.
TEST(ReplayAddFaces, MakesTheMeshAddFaceMakesInAnyOrderAndOnOpenSurfaces) {
  TriSurface surface = read_bundled_mesh("spot.off");
  std::mt19937 random(7);
  for (int round = 0; round < 3; ++round) {
    std::shuffle(surface.triangles.begin(), surface.triangles.end(), random);
    SurfaceMesh fast;
    ASSERT_TRUE(replay_add_faces(fast, surface));
    expect_same_connectivity(fast, built_by_add_face(surface));
  }
  // Open: every seventh triangle left out, and in the shuffled order.
  TriSurface open = surface;
  open.triangles.clear();
  for (size_t t = 0; t < surface.triangles.size(); ++t)
    if (t % 7 != 3) open.triangles.push_back(surface.triangles[t]);
  SurfaceMesh fast;
  ASSERT_TRUE(replay_add_faces(fast, open));
  const SurfaceMesh reference = built_by_add_face(open);
  expect_same_connectivity(fast, reference);
  size_t boundary = 0;
  for (auto h : fast.halfedges()) boundary += fast.is_boundary(h) ? 1 : 0;
  EXPECT_GT(boundary, 0u);
}

// A triangle OpenMesh cannot add (a third one on an edge, at a vertex already closed all
// around) is named as add_face finds it.
TEST(FillOpenMesh, RefusesAndNamesTheFirstTriangleAddFaceRefuses) {
  TriSurface surface = read_bundled_mesh("icosahedron.off");
  const auto t0 = surface.triangles[0];
  surface.points.push_back(Vec3(5, 5, 5));
  surface.triangles.push_back({t0[0], t0[1], int(surface.points.size() - 1)});  // a third face on edge t0[0]-t0[1]
  SurfaceMesh replayed;
  EXPECT_FALSE(replay_add_faces(replayed, surface));
  SurfaceMesh mesh;
  try {
    fill_openmesh(mesh, surface);
    FAIL() << "a non-manifold edge was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "triangle " + std::to_string(surface.triangles.size() - 1) + " cannot be added to a manifold mesh");
  }
}

}  // namespace
}  // namespace dthex
