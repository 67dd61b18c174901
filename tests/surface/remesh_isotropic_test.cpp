// SPDX-License-Identifier: MIT
#include <dthex/surface/remesh_isotropic.h>

#include <dthex/io/read_surface.h>
#include <dthex/io/write_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/triangle_crossing.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/features.h>
#include <dthex/surface/surface_distance.h>
#include <dthex/surface/verify_surface.h>
#include "boundary_fixtures.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

using namespace dthex;
using dthex::testing::box_surface;

namespace {

// A 5 x 0.5 x 0.5 rod as a CAD export makes it: its long faces are strips of 2.5 x 0.0625
// needles, its ends even grids.
TriSurface needle_rod() { return box_surface(Vec3(0, 0, 0), Vec3(5, 0.5, 0.5), {2, 8, 8}); }

double smallest_angle_deg(const TriSurface& s) {
  double smallest = 180;
  for (const auto& t : s.triangles)
    for (int i = 0; i < 3; ++i) {
      const Vec3& p = s.points[size_t(t[size_t(i)])];
      const Vec3 u = (s.points[size_t(t[size_t((i + 1) % 3)])] - p).normalized();
      const Vec3 w = (s.points[size_t(t[size_t((i + 2) % 3)])] - p).normalized();
      smallest = std::min(smallest, std::acos(std::clamp(u.dot(w), -1.0, 1.0)) * 180 / M_PI);
    }
  return smallest;
}

double smallest_shape(const TriSurface& s) {
  double smallest = 1;
  for (const auto& t : s.triangles)
    smallest = std::min(smallest, triangle_shape(s.points[size_t(t[0])], s.points[size_t(t[1])], s.points[size_t(t[2])]));
  return smallest;
}


// A membrane 2 wide and `thickness` thick, its middle pulled down into a cone (an ear drum's
// umbo), closed by a rounded rim, and sampled as a scan of one is often exported: rings of
// one vertex count around two poles, so that the triangles at the poles are needles.
TriSurface umbo_shell(double thickness) {
  const double radius = 1, depth = 0.3, cone = 0.3;
  const int rings = 16, around = 96, rim_rings = 4;
  TriSurface s;
  std::vector<std::vector<int>> sequence;  // vertex ids of each ring, by increasing angle
  const auto height = [&](double r) { return -depth * std::max(0.0, 1 - r / cone) - 0.1 * depth * (1 - r * r); };
  const auto add_ring = [&](int count, const std::function<Vec3(double)>& at) {
    std::vector<int> ring;
    for (int i = 0; i < count; ++i) {
      ring.push_back(int(s.points.size()));
      s.points.push_back(at(2 * M_PI * i / count));
    }
    sequence.push_back(ring);
  };
  const double dr = radius / rings, half = thickness / 2;
  const auto sheet = [&](double r, double z) { return [=](double a) { return Vec3(r * std::cos(a), r * std::sin(a), height(r) + z); }; };
  add_ring(1, sheet(0, half));
  for (int k = 1; k <= rings; ++k) add_ring(around, sheet(k * dr, half));
  for (int j = 1; j < rim_rings; ++j) {
    const double phi = M_PI * j / rim_rings;  // around the rim, from the top sheet down
    add_ring(around, [=](double a) {
      const double r = radius + half * std::sin(phi);
      return Vec3(r * std::cos(a), r * std::sin(a), half * std::cos(phi));
    });
  }
  for (int k = rings; k >= 1; --k) add_ring(around, sheet(k * dr, -half));
  add_ring(1, sheet(0, -half));
  for (size_t i = 0; i + 1 < sequence.size(); ++i) {
    const std::vector<int>&a = sequence[i], &b = sequence[i + 1];
    if (a.size() == 1) {  // the top pole's fan
      for (size_t j = 0; j < b.size(); ++j) s.triangles.push_back({a[0], b[j], b[(j + 1) % b.size()]});
      continue;
    }
    if (b.size() == 1) {  // the bottom pole's
      for (size_t j = 0; j < a.size(); ++j) s.triangles.push_back({a[j], b[0], a[(j + 1) % a.size()]});
      continue;
    }
    for (size_t j = 0; j < a.size(); ++j) {  // two rings of one count: a strip of quads
      const size_t k = (j + 1) % a.size();
      s.triangles.push_back({a[j], b[j], b[k]});
      s.triangles.push_back({a[j], b[k], a[k]});
    }
  }
  if (enclosed_volume(s) < 0)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}
}  // namespace

TEST(RemeshIsotropic, NeedleShareTellsCadStripsFromEvenTriangles) {
  // The rod: 128 of its 384 triangles are needles (longest edge squared over twice the area
  // is 40 on the long faces, 2 on the ends); an even box has none, and neither do the scans.
  EXPECT_NEAR(needle_share(needle_rod()), 128.0 / 384.0, 1e-12);
  EXPECT_EQ(needle_share(box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 6)), 0.0);
  const TriSurface femur = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/femur_proximal_ct.off");
  EXPECT_LT(needle_share(femur), kRemeshNeedleShare / 10);
}

TEST(RemeshIsotropic, AutomaticEdgeIsTheMeanAreaEdgeUnlessTheWallIsThinner) {
  // A unit cube of 6 x 6 quads per face: each triangle has area 1/72, so an equilateral
  // triangle of that area has edge sqrt(4 / (72 sqrt 3)) = 0.1791; the cube is far thicker.
  EXPECT_NEAR(remesh_edge_length(box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 6)), std::sqrt(4 / (72 * std::sqrt(3.0))),
              1e-9);
  // The rod's mean triangle (area 10.5 / 384) gives an edge of 0.2513, but it is 0.5 thick:
  // the inner ball touching a face has radius 0.25, and that is the edge.
  EXPECT_NEAR(remesh_edge_length(needle_rod()), 0.25, 0.01);
}

TEST(RemeshIsotropic, RodOfNeedlesBecomesEvenTrianglesOnTheSameSurface) {
  const TriSurface rod = needle_rod();
  RemeshIsotropicReport report;
  TriSurface even = remesh_isotropic(rod, {}, &report);
  ASSERT_NO_THROW(verify_surface(even, "remeshed rod"));  // closed, manifold, oriented, no self-intersection

  EXPECT_NEAR(report.edge_length, 0.25, 0.01);
  EXPECT_LT(report.min_angle_before_deg, 2);
  EXPECT_GT(report.min_angle_after_deg, 20);
  EXPECT_NEAR(smallest_angle_deg(even), report.min_angle_after_deg, 1e-9);
  // About area / (sqrt 3 / 4 L^2) = 10.5 / 0.02706 = 388 triangles of edge 0.25.
  EXPECT_GT(even.triangles.size(), 300u);
  EXPECT_LT(even.triangles.size(), 600u);

  // Every vertex on the rod's surface, every edge of it still there (its 8 corners kept,
  // the volume exactly the box's), and the edges near the length asked for.
  const TriangleBvh rod_bvh(rod);
  for (const Vec3& p : even.points) EXPECT_LT(std::sqrt(rod_bvh.closest_point(p).distance_sq), 1e-12);
  EXPECT_NEAR(enclosed_volume(even), 5 * 0.5 * 0.5, 1e-12);
  EXPECT_EQ(detect_features(even).corners.size(), 8u);
  size_t near_length = 0, edges = 0;
  for (const auto& t : even.triangles)
    for (int i = 0; i < 3; ++i, ++edges) {
      const double length = (even.points[size_t(t[size_t(i)])] - even.points[size_t(t[size_t((i + 1) % 3)])]).norm();
      near_length += length > 0.5 * report.edge_length && length < 1.5 * report.edge_length;
    }
  EXPECT_GT(double(near_length), 0.9 * double(edges));
}

TEST(RemeshIsotropic, CurvedSurfaceStaysOnItself) {
  // The paper's sphere, remeshed finer than it is: new vertices lie on its triangles (not on
  // the sphere), and the volume changes by less than the chords' own error.
  const TriSurface sphere = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  RemeshIsotropicOptions options;
  options.edge_length = 0.1;
  TriSurface even = remesh_isotropic(sphere, options);
  ASSERT_NO_THROW(verify_surface(even, "remeshed sphere"));
  EXPECT_GT(even.triangles.size(), 2 * sphere.triangles.size());
  const TriangleBvh bvh(sphere);
  for (const Vec3& p : even.points) EXPECT_LT(std::sqrt(bvh.closest_point(p).distance_sq), 1e-9);
  EXPECT_NEAR(enclosed_volume(even) / enclosed_volume(sphere), 1.0, 0.01);
  EXPECT_GT(smallest_angle_deg(even), 20);
}

TEST(RemeshIsotropic, CoarseningTheRemeshedRodLeavesNoNeedles) {
  // Why the step exists: the coarsening moves vertices along the existing edges, so the
  // rod's strips stay strips; from the remeshed rod it makes even triangles.
  const TriSurface rod = needle_rod();
  CoarsenOptions options;
  options.max_size_per_thickness = 1;
  const double from_needles = smallest_shape(coarsen(rod, options).surface);
  const double from_even = smallest_shape(coarsen(remesh_isotropic(rod), options).surface);
  std::printf("coarse rod: smallest triangle shape %.3f from the needles, %.3f remeshed first\n", from_needles,
              from_even);
  EXPECT_LT(from_needles, 0.2);
  EXPECT_GT(from_even, 0.4);
}

TEST(RemeshIsotropic, PipelineRemeshesANeedleRodAndMeshesItWell) {
  const std::string path = (dthex_test::fresh_dir("needle_rod") / "rod.off").string();
  write_surface(needle_rod(), path);
  Progress quiet;
  const PipelineResult r = run_pipeline(path, PipelineOptions{}, quiet);
  ASSERT_FALSE(r.remeshed.triangles.empty());
  EXPECT_NE(std::find_if(r.stages.begin(), r.stages.end(), [](const StageRecord& s) { return s.name == "remesh input"; }),
            r.stages.end());
  EXPECT_EQ(r.quality.inverted, 0u);
  EXPECT_TRUE(r.conforming);
  EXPECT_GE(r.quality.scaled_jacobian_stats.min, 0.2);
  // Faces and edges are flat and straight: the boundary is the rod's, to rounding.
  EXPECT_LT(r.hausdorff, 1e-9);
  EXPECT_NEAR(r.hex_volume, 1.25, 1e-9);

  // An even input is not remeshed at auto, and --remesh off keeps even the rod as it is.
  PipelineOptions never;
  never.remesh = PipelineOptions::Remesh::never;
  never.thickness_retry = false;
  never.project = false;  // only the coarse surface matters here
  const PipelineResult kept = run_pipeline(path, never, quiet);
  EXPECT_TRUE(kept.remeshed.triangles.empty());
  const std::string box = (dthex_test::fresh_dir("even_box") / "box.off").string();
  write_surface(box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 6), box);
  PipelineOptions automatic;
  automatic.project = false;
  EXPECT_TRUE(run_pipeline(box, automatic, quiet).remeshed.triangles.empty());
}

TEST(RemeshIsotropic, PipelineKeepsASpikeThatRemeshingWouldMakeWorse) {
  // A tet 1024 long on a unit corner (a fuzzer's find): 3 of its 4 triangles are needles, but
  // its feature lines meet at 0.056 degrees at the tip, where no even triangles fit. Remeshed
  // at the tip's thickness it would become so many triangles that coarsening them takes
  // minutes; the remeshing is bounded (100 times the input's triangles, at least 1,000) and a result with
  // a smaller smallest angle (or one that fails verification, or that only grows) is not used.
  TriSurface spike;
  spike.points = {Vec3(0, 0, 0), Vec3(-1024, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  spike.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  EXPECT_GT(needle_share(spike), kRemeshNeedleShare);
  EXPECT_GT(remesh_edge_length(spike), 1.5);  // 1,000 triangles over its area of about 1,540

  const std::string path = (dthex_test::fresh_dir("spike") / "spike.off").string();
  write_surface(spike, path);
  Progress quiet;
  PipelineOptions options;
  options.project = false;
  const PipelineResult r = run_pipeline(path, options, quiet);
  EXPECT_TRUE(r.remeshed.triangles.empty());
  const auto stage =
      std::find_if(r.stages.begin(), r.stages.end(), [](const StageRecord& s) { return s.name == "remesh input"; });
  ASSERT_NE(stage, r.stages.end());
  // Where the feature lines converge, collapses across them are refused while splits go on:
  // the remeshing gives up once the mesh has grown 16-fold past what its length asks for.
  const RemeshStageReport* report = std::get_if<RemeshStageReport>(&stage->report);
  ASSERT_NE(report, nullptr);
  EXPECT_TRUE(report->remesh.gave_up);
  EXPECT_EQ(report->outcome, RemeshStageReport::Outcome::gave_up);
  EXPECT_NE(describe(stage->report).find("the input is coarsened as it is"), std::string::npos);
  EXPECT_EQ(r.coarse.triangles.size(), 4u);
}

TEST(RemeshIsotropic, ThinWallIsRemeshedWithoutCrossingItsOtherSide) {
  // The umbo shell, 0.05 thick, remeshed at edge 0.15, three times its thickness (what the
  // automatic length avoids, forced here): chords that long around the rim and the cone dip
  // through the other side of the wall, and those edits are refused. The result is a valid
  // surface on the input, and no triangle of it passes through an input triangle facing away.
  TriSurface shell = umbo_shell(0.05);
  ASSERT_NO_THROW(verify_surface(shell, "umbo shell"));
  EXPECT_GT(needle_share(shell), kRemeshNeedleShare);  // the poles' fans
  RemeshIsotropicOptions options;
  options.edge_length = 0.15;
  RemeshIsotropicReport report;
  TriSurface even = remesh_isotropic(shell, options, &report);
  ASSERT_NO_THROW(verify_surface(even, "remeshed umbo shell"));
  EXPECT_GT(report.refused_crossings, 0u);
  EXPECT_GT(report.min_angle_after_deg, 15);
  const TriangleBvh bvh(shell);
  size_t off_input = 0;
  for (const Vec3& p : even.points) off_input += std::sqrt(bvh.closest_point(p).distance_sq) > 1e-9;
  EXPECT_EQ(off_input, report.off_input_vertices);
  const std::vector<Vec3> normals = unit_triangle_normals(shell.points, shell.triangles);
  size_t crossing = 0;
  for (const auto& t : even.triangles) {
    const std::array<Vec3, 3> corners{even.points[size_t(t[0])], even.points[size_t(t[1])], even.points[size_t(t[2])]};
    const Vec3 n = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalized();
    const Vec3 centroid = (corners[0] + corners[1] + corners[2]) / 3;
    std::array<Vec3, 3> shrunk;  // not counting a corner on the input
    Eigen::AlignedBox3d box;
    for (size_t k = 0; k < 3; ++k) box.extend(shrunk[k] = centroid + 0.999 * (corners[k] - centroid));
    bvh.for_each_in_box(box, [&](int f) {
      const auto& c = shell.triangles[size_t(f)];
      if (normals[size_t(f)].dot(n) < -0.5 &&
          triangles_cross(shrunk, {shell.points[size_t(c[0])], shell.points[size_t(c[1])], shell.points[size_t(c[2])]}))
        ++crossing;
    });
  }
  EXPECT_EQ(crossing, 0u);
}
