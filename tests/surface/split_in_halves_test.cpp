// SPDX-License-Identifier: MIT
#include <dthex/surface/split_in_halves.h>

#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/features.h>
#include <dthex/surface/verify_surface.h>

#include <dthex/modules/DTHexGeometry.hh>

#include "boundary_fixtures.h"
#include "bundled_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace dthex;

namespace {


//! The input as the coarsening prepares it: features marked, a size per vertex (its index,
//! so a size that lands on the wrong vertex is seen).
SurfaceMesh prepared(const TriSurface& surface) {
  SurfaceMesh mesh = to_openmesh(surface);
  mark_features(mesh);
  OpenMesh::VPropHandleT<double> size;
  mesh.add_property(size, size_property_name());
  for (auto v : mesh.vertices()) mesh.property(size, v) = double(v.idx());
  return mesh;
}

//! Each triangle as its vertex triple rotated to start at the smallest (orientation kept).
std::multiset<std::array<int, 3>> triangle_set(const TriSurface& s) {
  std::multiset<std::array<int, 3>> out;
  for (auto t : s.triangles) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

//! Sizes and extra locks as the coarsening's repair rounds pass them: size 1000 + the vertex's
//! index (a size on the wrong vertex is seen), a lock on every `lock_every`-th vertex.
struct GivenExtras {
  std::vector<double> sizes;
  std::vector<char> locked;
  GivenExtras(size_t vertices, size_t lock_every) : sizes(vertices), locked(vertices, 0) {
    for (size_t v = 0; v < vertices; ++v) {
      sizes[v] = 1000.0 + double(v);
      locked[v] = v % lock_every == 0;
    }
  }
  SplitExtras extras() const { return SplitExtras{&sizes, &locked}; }
};

}  // namespace

// The halves hold every triangle once, split near the middle, each an open manifold
// surface (OpenMesh holds it) whose boundary is exactly the locked cut; statuses and sizes
// travel with their vertices; joined untouched, they give the whole mesh back.
TEST(SplitInHalves, HalvesCoverTheMeshMeetOnALockedCutAndJoinBack) {
  for (const char* name : {"femur_proximal_ct.off", "heart.off", "vertebra_L1.off"}) {
    SCOPED_TRACE(name);
    const TriSurface surface = dthex_test::read_bundled_mesh(name);
    const SurfaceMesh whole = prepared(surface);
    SurfaceHalves split;
    ASSERT_TRUE(split_in_halves(whole, split));
    const size_t f0 = split.halves[0].n_faces(), f1 = split.halves[1].n_faces();
    EXPECT_EQ(f0 + f1, whole.n_faces());
    EXPECT_GT(f0, whole.n_faces() * 2 / 5);
    EXPECT_GT(f1, whole.n_faces() * 2 / 5);
    EXPECT_GT(split.cut_vertices, 0u);

    std::vector<int> in_halves(whole.n_vertices(), 0);
    for (int p = 0; p < 2; ++p) {
      const SurfaceMesh& half = split.halves[size_t(p)];
      OpenMesh::VPropHandleT<double> size;
      ASSERT_TRUE(half.get_property_handle(size, size_property_name()));
      size_t boundary = 0;
      for (auto v : half.vertices()) {
        const SurfaceMesh::VertexHandle w(split.whole_vertex[size_t(p)][size_t(v.idx())]);
        ++in_halves[size_t(w.idx())];
        EXPECT_EQ(half.point(v), whole.point(w));
        EXPECT_EQ(half.property(size, v), double(w.idx()));
        EXPECT_EQ(half.status(v).feature(), whole.status(w).feature());
        if (half.is_boundary(v)) {
          ++boundary;
          EXPECT_TRUE(half.status(v).locked()) << "cut vertex " << w.idx() << " is not locked";
        } else {
          EXPECT_EQ(half.status(v).locked(), whole.status(w).locked());
        }
      }
      EXPECT_EQ(boundary, split.cut_vertices);
      for (auto e : half.edges()) {
        const auto h = half.halfedge_handle(e, 0);
        const auto wh = whole.find_halfedge(
            SurfaceMesh::VertexHandle(split.whole_vertex[size_t(p)][size_t(half.from_vertex_handle(h).idx())]),
            SurfaceMesh::VertexHandle(split.whole_vertex[size_t(p)][size_t(half.to_vertex_handle(h).idx())]));
        ASSERT_TRUE(wh.is_valid());
        EXPECT_EQ(half.status(e).feature(), whole.status(whole.edge_handle(wh)).feature());
      }
    }
    // Every vertex is in a half; exactly the cut is in both.
    EXPECT_EQ(size_t(std::count(in_halves.begin(), in_halves.end(), 0)), 0u);
    EXPECT_EQ(size_t(std::count(in_halves.begin(), in_halves.end(), 2)), split.cut_vertices);

    const SurfaceMesh joined = join_halves(split, whole);
    const TriSurface back = from_openmesh(joined);
    EXPECT_EQ(back.points, surface.points);
    EXPECT_EQ(triangle_set(back), triangle_set(surface));
    OpenMesh::VPropHandleT<double> size;
    ASSERT_TRUE(joined.get_property_handle(size, size_property_name()));
    for (auto v : joined.vertices()) {
      EXPECT_EQ(joined.property(size, v), double(v.idx()));
      EXPECT_EQ(joined.status(v).locked(), whole.status(v).locked());  // the cut's locks are gone
    }
  }
}

TEST(SplitInHalves, NothingToSplitIsRefused) {
  SurfaceHalves split;
  EXPECT_FALSE(split_in_halves(SurfaceMesh(), split));
}

// Coarsened in two halves at once, then joined and coarsened again: a valid closed surface
// like the one run over the whole, of nearly the same size. Without the last pass the cut
// would stay at the input's resolution (hundreds of extra triangles on these meshes).
TEST(SplitInHalves, CoarseningInHalvesMatchesOneRun) {
  for (const char* name : {"femur_proximal_ct.off", "heart.off"}) {
    SCOPED_TRACE(name);
    const TriSurface input = dthex_test::read_bundled_mesh(name);
    CoarsenOptions halves, whole;
    whole.split_from_vertices = 0;
    const CoarsenResult a = coarsen(input, halves), b = coarsen(input, whole);
    EXPECT_GT(a.cut_vertices, 100u);
    EXPECT_EQ(b.cut_vertices, 0u);
    // Closed, manifold, oriented, not self-intersecting (verify_surface throws otherwise),
    // no unused vertex, the input's genus and orientation.
    TriSurface coarse = a.surface, given = input;
    SurfaceStats stats;
    ASSERT_NO_THROW(stats = verify_surface(coarse, name));
    EXPECT_EQ(stats.genus, 0);
    EXPECT_EQ(stats.components, 1u);
    EXPECT_EQ(stats.unreferenced_vertices, 0u);
    EXPECT_EQ(stats.flipped_components, verify_surface(given, name).flipped_components);
    const double na = double(a.surface.triangles.size()), nb = double(b.surface.triangles.size());
    EXPECT_LT(std::abs(na - nb), 0.05 * nb) << na << " triangles in halves, " << nb << " in one run";
    double worst = 1;
    for (double s : triangle_shapes(a.surface)) worst = std::min(worst, s);
    EXPECT_GE(worst, 0.2);
  }
}

namespace {

//! The heart and a copy of it beside it along its longest extent, twice its length away.
TriSurface two_hearts() {
  const TriSurface heart = dthex_test::read_bundled_mesh("heart.off");
  Eigen::AlignedBox3d box;
  for (const Vec3& p : heart.points) box.extend(p);
  int axis = 0;
  const double shift = 2 * box.sizes().maxCoeff(&axis);
  TriSurface two = heart;
  const int n = int(heart.points.size());
  for (Vec3 p : heart.points) {
    p[axis] += shift;
    two.points.push_back(p);
  }
  for (const auto& t : heart.triangles) two.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  return two;
}

}  // namespace

// Two bodies side by side: the median plane falls between them, so the halves share no
// vertex (an empty cut), each holds one body, and they join back into both.
TEST(SplitInHalves, TwoSeparateBodiesAreCutBetweenThem) {
  const TriSurface two = two_hearts();
  const SurfaceMesh whole = prepared(two);
  SurfaceHalves split;
  ASSERT_TRUE(split_in_halves(whole, split));
  EXPECT_EQ(split.cut_vertices, 0u);
  EXPECT_EQ(split.halves[0].n_faces(), two.triangles.size() / 2);
  EXPECT_EQ(split.halves[1].n_faces(), two.triangles.size() / 2);
  const TriSurface back = from_openmesh(join_halves(split, whole));
  EXPECT_EQ(back.points, two.points);
  EXPECT_EQ(triangle_set(back), triangle_set(two));
}

// Coarsened in halves, each body is coarsened whole on its core: two valid bodies of about
// the size of one body coarsened on its own, twice.
TEST(SplitInHalves, TwoSeparateBodiesCoarsenedInHalvesStayTwo) {
  const TriSurface two = two_hearts();
  const CoarsenResult both = coarsen(two);
  EXPECT_EQ(both.cut_vertices, 0u);
  CoarsenOptions whole;
  whole.split_from_vertices = 0;
  const double one = double(coarsen(dthex_test::read_bundled_mesh("heart.off"), whole).surface.triangles.size());
  TriSurface coarse = both.surface;
  SurfaceStats stats;
  ASSERT_NO_THROW(stats = verify_surface(coarse, "two hearts"));
  EXPECT_EQ(stats.components, 2u);
  EXPECT_LT(std::abs(double(both.surface.triangles.size()) - 2 * one), 0.05 * 2 * one);
}

// The coarsening's repair rounds pass their sizes and extra locks instead of copying the mesh:
// the halves carry them, and the joined mesh keeps the extra locks but not the cut's.
TEST(SplitInHalves, GivenSizesAndLocksTravelWithTheirVertices) {
  const SurfaceMesh whole = prepared(dthex_test::read_bundled_mesh("heart.off"));
  const GivenExtras given(whole.n_vertices(), 7);
  const std::vector<double>& sizes = given.sizes;
  const std::vector<char>& locked = given.locked;
  const SplitExtras extras = given.extras();
  SurfaceHalves split;
  ASSERT_TRUE(split_in_halves(whole, split, extras));
  for (int p = 0; p < 2; ++p) {
    const SurfaceMesh& half = split.halves[size_t(p)];
    OpenMesh::VPropHandleT<double> size;
    ASSERT_TRUE(half.get_property_handle(size, size_property_name()));
    for (auto v : half.vertices()) {
      const size_t w = size_t(split.whole_vertex[size_t(p)][size_t(v.idx())]);
      EXPECT_EQ(half.property(size, v), sizes[w]);
      if (locked[w]) EXPECT_TRUE(half.status(v).locked()) << "vertex " << w;
    }
  }
  const SurfaceMesh joined = join_halves(split, whole, extras);
  ASSERT_EQ(joined.n_vertices(), whole.n_vertices());
  OpenMesh::VPropHandleT<double> size;
  ASSERT_TRUE(joined.get_property_handle(size, size_property_name()));
  for (auto v : joined.vertices()) {
    EXPECT_EQ(joined.property(size, v), sizes[size_t(v.idx())]);
    EXPECT_EQ(joined.status(v).locked(), whole.status(v).locked() || locked[size_t(v.idx())]);
  }
}

// Cut first and marked later (as the coarsening does while it measures the sizes), the halves
// are those split_in_halves makes at once: the same triangles in the same order, vertices,
// status bits and sizes, edge features (a box has them on its twelve edges).
TEST(SplitInHalves, CutFirstAndMarkedLaterGivesTheSameHalves) {
  const SurfaceMesh whole = prepared(dthex::testing::box_surface(Vec3(0, 0, 0), Vec3(3, 2, 1), {30, 20, 10}));
  const GivenExtras given(whole.n_vertices(), 5);
  const SplitExtras extras = given.extras();
  SurfaceHalves at_once, in_two_steps;
  ASSERT_TRUE(split_in_halves(whole, at_once, extras));
  ASSERT_TRUE(split_connectivity(whole, in_two_steps));
  mark_halves(whole, in_two_steps, extras);
  EXPECT_EQ(in_two_steps.cut_vertices, at_once.cut_vertices);
  EXPECT_GT(at_once.cut_vertices, 0u);
  size_t feature_edges = 0;
  for (int p = 0; p < 2; ++p) {
    const SurfaceMesh &a = at_once.halves[size_t(p)], &b = in_two_steps.halves[size_t(p)];
    EXPECT_EQ(in_two_steps.whole_vertex[size_t(p)], at_once.whole_vertex[size_t(p)]);
    const TriSurface sa = from_openmesh(a), sb = from_openmesh(b);
    EXPECT_EQ(sb.triangles, sa.triangles);
    EXPECT_TRUE(sb.points == sa.points);
    OpenMesh::VPropHandleT<double> size_a, size_b;
    ASSERT_TRUE(a.get_property_handle(size_a, size_property_name()));
    ASSERT_TRUE(b.get_property_handle(size_b, size_property_name()));
    size_t differ = 0;
    for (auto v : a.vertices())
      differ += a.status(v).bits() != b.status(v).bits() || a.property(size_a, v) != b.property(size_b, v);
    for (auto e : a.edges()) {
      differ += a.status(e).bits() != b.status(e).bits();
      feature_edges += a.status(e).feature();
    }
    EXPECT_EQ(differ, 0u) << "half " << p;
  }
  EXPECT_GT(feature_edges, 0u);
}
