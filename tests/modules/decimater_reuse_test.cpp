// SPDX-License-Identifier: MIT
// The reuse case: an OpenMesh application that includes only the public module headers
// (no core/), with OpenMesh's stock DecimaterT; and a count of collapses executed against
// the modules' own verdict, stock DecimaterT vs RevalidatingDecimaterT.
#include <dthex/modules/ModCurvatureSizingT.hh>
#include <dthex/modules/ModEdgeSwapT.hh>
#include <dthex/modules/ModLocalSmoothingT.hh>
#include <dthex/modules/ModNormalizedLengthT.hh>
#include <dthex/modules/RevalidatingDecimaterT.hh>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include "collapse_check_module.h"
#include "icosphere.h"

#include <gtest/gtest.h>

#include <map>
#include <type_traits>

namespace {

struct AppTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  FaceAttributes(OpenMesh::Attributes::Normal);
};
using AppMesh = OpenMesh::TriMesh_ArrayKernelT<AppTraits>;

AppMesh app_icosphere(int levels) { return dthex_test::openmesh_icosphere<AppMesh>(levels); }

template <class Decimater>
std::pair<size_t, size_t> run_with_check(AppMesh& mesh, bool callbacks, double eps, bool estimate = false) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mesh.update_face_normals();
  Decimater decimater(mesh);
  typename dthex::ModCurvatureSizingT<AppMesh>::Handle sizing;
  typename dthex::ModNormalizedLengthT<AppMesh>::Handle length;
  typename dthex::ModEdgeSwapT<AppMesh>::Handle swap;
  typename dthex::ModLocalSmoothingT<AppMesh>::Handle smoothing;
  typename dthex_test::ModCollapseCheckT<AppMesh>::Handle check;
  decimater.add(sizing);
  dthex::CurvatureSizingOptions options;
  options.eps = eps;
  decimater.module(sizing).set_options(options);
  decimater.add(length);
  if (callbacks) {
    decimater.add(swap);
    decimater.add(smoothing);
  }
  decimater.add(check);  // last binary module: its preprocess sees the mesh as collapsed
  if constexpr (std::is_same_v<Decimater, dthex::RevalidatingDecimaterT<AppMesh>>) {
    if (estimate) {
      OpenMesh::VPropHandleT<double> size = dthex::size_property(mesh);
      decimater.set_priority_estimate([&mesh, size](const typename Decimater::CollapseInfo& ci) {
        return dthex::ModNormalizedLengthT<AppMesh>::priority_estimate(mesh, size, ci);
      });
    }
  }
  EXPECT_TRUE(decimater.initialize());
  decimater.decimate();
  const auto& checker = decimater.module(check);
  const std::pair<size_t, size_t> result{checker.executed, checker.rejected};
  mesh.garbage_collection();
  return result;
}

size_t boundary_edges(const AppMesh& mesh) {
  size_t n = 0;
  for (auto e : mesh.edges()) n += mesh.is_boundary(e);
  return n;
}

}  // namespace

TEST(DecimaterReuse, StockDecimaterCoarsensASphereWithModuleHeadersOnly) {
  AppMesh mesh = app_icosphere(3);  // 642 vertices
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  {
    OpenMesh::Decimater::DecimaterT<AppMesh> decimater(mesh);
    dthex::ModCurvatureSizingT<AppMesh>::Handle sizing;
    dthex::ModNormalizedLengthT<AppMesh>::Handle length;
    decimater.add(sizing);
    decimater.add(length);
    ASSERT_TRUE(decimater.initialize());
    EXPECT_GT(decimater.decimate(), 500u);
  }
  mesh.garbage_collection();
  EXPECT_LT(mesh.n_vertices(), 60u);
  EXPECT_GE(mesh.n_vertices(), 12u);
  EXPECT_EQ(boundary_edges(mesh), 0u);
  EXPECT_EQ(int(mesh.n_vertices()) - int(mesh.n_edges()) + int(mesh.n_faces()), 2);
  // The sizing property is public: the app can read it.
  OpenMesh::VPropHandleT<double> size;
  ASSERT_TRUE(mesh.get_property_handle(size, dthex::size_property_name()));
  for (auto v : mesh.vertices()) EXPECT_NEAR(mesh.property(size, v), dthex::sizing_alpha(0.1), 0.05);
}

TEST(DecimaterReuse, PriorityModuleAloneIsNotEnoughForInitialize) {
  AppMesh mesh = app_icosphere(1);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  OpenMesh::Decimater::DecimaterT<AppMesh> decimater(mesh);
  dthex::ModCurvatureSizingT<AppMesh>::Handle sizing;
  decimater.add(sizing);
  EXPECT_FALSE(decimater.initialize());  // binary modules only: no priority module
}

TEST(DecimaterReuse, RevalidatingDecimaterNeverExecutesARejectedCollapse) {
  size_t stock_rejected = 0, ours_rejected = 0, stock_executed = 0, ours_executed = 0;
  for (double eps : {0.02, 0.05, 0.1}) {
    AppMesh a = app_icosphere(4), b = app_icosphere(4), c = app_icosphere(4);
    const auto stock = run_with_check<OpenMesh::Decimater::DecimaterT<AppMesh>>(a, true, eps);
    const auto ours = run_with_check<dthex::RevalidatingDecimaterT<AppMesh>>(b, true, eps);
    const auto lazy = run_with_check<dthex::RevalidatingDecimaterT<AppMesh>>(c, true, eps, true);
    stock_executed += stock.first, stock_rejected += stock.second;
    ours_executed += ours.first + lazy.first, ours_rejected += ours.second + lazy.second;
    EXPECT_EQ(boundary_edges(b), 0u);
    EXPECT_EQ(boundary_edges(c), 0u);
    // Lazy evaluation keeps the greedy result close to the thorough one.
    EXPECT_NEAR(double(lazy.first), double(ours.first), 0.05 * double(ours.first));
  }
  EXPECT_GT(ours_executed, 1000u);
  EXPECT_EQ(ours_rejected, 0u);
  // OpenMesh's DecimaterT only re-checks topology when it pops: after swaps and moves it
  // executes collapses its own modules would now refuse.
  EXPECT_GT(stock_rejected, 0u) << "stock executed " << stock_executed;
  std::printf("collapses against the modules' verdict: stock DecimaterT %zu of %zu, RevalidatingDecimaterT %zu of %zu\n",
              stock_rejected, stock_executed, ours_rejected, ours_executed);
}

TEST(DecimaterReuse, WithoutCallbacksStockDecimaterIsCorrect) {
  AppMesh mesh = app_icosphere(4);
  const auto stock = run_with_check<OpenMesh::Decimater::DecimaterT<AppMesh>>(mesh, false, 0.05);
  EXPECT_GT(stock.first, 1000u);
  EXPECT_EQ(stock.second, 0u);
}
