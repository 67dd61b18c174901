// SPDX-License-Identifier: MIT
// SweepDecimaterT: every collapse it makes is legal when it is made, it leaves no legal
// collapse behind when it sweeps to the end, and (without smoothing) it moves no vertex.
#include <dthex/modules/ModEdgeSwapT.hh>
#include <dthex/modules/ModNormalizedLengthT.hh>
#include <dthex/modules/RevalidatingDecimaterT.hh>
#include <dthex/modules/SweepDecimaterT.hh>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include "collapse_check_module.h"
#include "icosphere.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace {

struct SweepTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  FaceAttributes(OpenMesh::Attributes::Normal);
};
using SweepMesh = OpenMesh::TriMesh_ArrayKernelT<SweepTraits>;

//! The unit icosphere (split `levels` times) with the status and normals the decimater needs.
SweepMesh sweep_icosphere(int levels) {
  SweepMesh mesh = dthex_test::openmesh_icosphere<SweepMesh>(levels);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mesh.update_face_normals();
  return mesh;
}

//! Decimates `mesh` (sizes h everywhere) with the length and swap modules; returns the
//! collapses made and those the check found illegal when they were made.
template <class Decimater>
std::pair<size_t, size_t> decimate_with(SweepMesh& mesh, bool sweep_to_the_end) {
  const OpenMesh::VPropHandleT<double> size = dthex::size_property(mesh);
  Decimater decimater(mesh);
  typename dthex::ModNormalizedLengthT<SweepMesh>::Handle length;
  typename dthex::ModEdgeSwapT<SweepMesh>::Handle swap;
  typename dthex_test::ModCollapseCheckT<SweepMesh>::Handle check;
  decimater.add(length);
  decimater.add(swap);
  decimater.add(check);
  decimater.set_priority_estimate([&mesh, size](const typename Decimater::CollapseInfo& ci) {
    return dthex::ModNormalizedLengthT<SweepMesh>::priority_estimate(mesh, size, ci);
  });
  EXPECT_TRUE(decimater.initialize());
  size_t collapses = 0;
  if constexpr (std::is_same_v<Decimater, dthex::SweepDecimaterT<SweepMesh>>)
    collapses = sweep_to_the_end ? decimater.decimate(1000, 0.0) : decimater.decimate();
  else
    collapses = decimater.decimate();
  EXPECT_EQ(decimater.module(check).executed, collapses);
  return {collapses, decimater.module(check).rejected};
}

}  // namespace

TEST(SweepDecimater, CollapsesOnlyLegallyMovesNothingAndLeavesNothingLegal) {
  SweepMesh mesh = sweep_icosphere(4);  // 2562 vertices, edges ~0.06
  const size_t before = mesh.n_vertices();
  const auto size = dthex::size_property(mesh);
  for (auto v : mesh.vertices()) mesh.property(size, v) = 0.3;
  const auto locked = mesh.vertex_handle(7);
  mesh.status(locked).set_locked(true);
  std::set<std::array<double, 3>> original;
  for (auto v : mesh.vertices()) original.insert({mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]});

  const auto [collapses, illegal] = decimate_with<dthex::SweepDecimaterT<SweepMesh>>(mesh, true);
  EXPECT_EQ(illegal, 0u);
  EXPECT_GT(collapses, before * 9 / 10);  // h = 0.3 is ~5 input edges: most vertices go
  // Nothing legal is left: the greedy decimater with the same modules finds no collapse.
  EXPECT_EQ(decimate_with<dthex::RevalidatingDecimaterT<SweepMesh>>(mesh, false).first, 0u);
  EXPECT_FALSE(mesh.status(locked).deleted());
  mesh.garbage_collection();
  EXPECT_EQ(mesh.n_vertices(), before - collapses);
  EXPECT_EQ(int(mesh.n_vertices()) - int(mesh.n_edges()) + int(mesh.n_faces()), 2);
  for (auto e : mesh.edges()) EXPECT_FALSE(mesh.is_boundary(e));
  for (auto v : mesh.vertices())
    EXPECT_TRUE(original.count({mesh.point(v)[0], mesh.point(v)[1], mesh.point(v)[2]})) << "vertex " << v.idx() << " moved";
}

TEST(SweepDecimater, StopsWhenASweepCollapsesTooFew) {
  // With the default share (2 %) it stops earlier than sweeping to the end, never later.
  SweepMesh to_the_end = sweep_icosphere(4), by_share = sweep_icosphere(4);
  for (SweepMesh* mesh : {&to_the_end, &by_share}) {
    const auto size = dthex::size_property(*mesh);
    for (auto v : mesh->vertices()) mesh->property(size, v) = 0.3;
  }
  const size_t all = decimate_with<dthex::SweepDecimaterT<SweepMesh>>(to_the_end, true).first;
  const size_t some = decimate_with<dthex::SweepDecimaterT<SweepMesh>>(by_share, false).first;
  EXPECT_LE(some, all);
  EXPECT_GT(some, all * 8 / 10);
}
