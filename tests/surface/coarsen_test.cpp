// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/features.h>
#include <dthex/surface/verify_surface.h>

#include <dthex/modules/DTHexGeometry.hh>
#include "boundary_fixtures.h"
#include "bundled_meshes.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

using namespace dthex;

namespace {


double diagonal(const TriSurface& s) {
  Eigen::AlignedBox3d box;
  for (const auto& p : s.points) box.extend(p);
  return box.diagonal().norm();
}

//! Closed, manifold, consistently oriented: every directed edge once, its reverse once.
void expect_closed_oriented_manifold(const TriSurface& s, const std::string& name) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
  size_t bad = 0;
  for (const auto& [e, count] : directed) {
    const auto reverse = directed.find({e.second, e.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0u) << name << ": edges not shared by exactly two consistently oriented triangles";
  // Vertex manifoldness: the triangles around each vertex form a single fan.
  std::vector<std::map<int, int>> next(s.points.size());  // around v: a -> b for triangle (v, a, b)
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) next[size_t(t[size_t(k)])][t[size_t((k + 1) % 3)]] = t[size_t((k + 2) % 3)];
  size_t non_manifold = 0;
  for (const auto& fan : next) {
    if (fan.empty()) continue;
    size_t steps = 0;
    int a = fan.begin()->first;
    do {
      auto it = fan.find(a);
      if (it == fan.end()) break;
      a = it->second;
      ++steps;
    } while (a != fan.begin()->first && steps <= fan.size());
    if (steps != fan.size()) ++non_manifold;
  }
  EXPECT_EQ(non_manifold, 0u) << name << ": non-manifold vertices";
}

int euler_characteristic(const TriSurface& s) {
  std::set<std::pair<int, int>> edges;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[size_t(k)], t[size_t((k + 1) % 3)]));
  return int(s.points.size()) - int(edges.size()) + int(s.triangles.size());
}

void check_coarse_surface(const TriSurface& input, const CoarsenOptions& options, const std::string& name) {
  const CoarsenResult r = coarsen(input, options);
  const TriSurface& c = r.surface;
  SCOPED_TRACE(name);
  ASSERT_GT(c.points.size(), 3u);
  EXPECT_LT(c.points.size(), input.points.size() / 2);
  expect_closed_oriented_manifold(c, name);
  EXPECT_TRUE(self_intersections(c).empty());
  EXPECT_EQ(euler_characteristic(c), euler_characteristic(input));
  // The foundation's verification (closed, manifold, oriented, no self-intersections) passes.
  TriSurface verified = c, input_copy = input;
  SurfaceStats stats, input_stats;
  EXPECT_NO_THROW(stats = verify_surface(verified, name + " (coarse)"));
  ASSERT_NO_THROW(input_stats = verify_surface(input_copy, name));
  EXPECT_EQ(stats.genus, input_stats.genus);
  EXPECT_EQ(stats.components, input_stats.components);
  // Every vertex lies on the input surface.
  const TriangleBvh bvh(input);
  const double diag = diagonal(input);
  double worst = 0;
  for (const auto& p : c.points) worst = std::max(worst, std::sqrt(bvh.closest_point(p).distance_sq));
  EXPECT_LT(worst, 1e-9 * diag);
  // Every feature corner of the input survives, at its place.
  const Features features = detect_features(input, options.feature_angle_deg);
  std::set<std::array<double, 3>> coarse_points;
  for (const auto& p : c.points) coarse_points.insert({p.x(), p.y(), p.z()});
  for (int v : features.corners) {
    const Vec3& p = input.points[size_t(v)];
    EXPECT_TRUE(coarse_points.count({p.x(), p.y(), p.z()})) << "feature corner " << v << " removed";
  }
  // Every edge the coarsening made is below the normalized-length bound (edges kept from
  // the input, between unmoved input vertices, are what the input gave us).
  std::map<std::array<double, 3>, int> input_index;
  for (size_t i = 0; i < input.points.size(); ++i)
    input_index[{input.points[i].x(), input.points[i].y(), input.points[i].z()}] = int(i);
  std::set<std::pair<int, int>> input_edges;
  for (const auto& t : input.triangles)
    for (int k = 0; k < 3; ++k) input_edges.insert(std::minmax(t[size_t(k)], t[size_t((k + 1) % 3)]));
  ASSERT_EQ(r.sizes.size(), c.points.size());
  size_t too_long = 0, checked = 0;
  for (const auto& t : c.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      if (a > b) continue;
      const auto ia = input_index.find({c.points[size_t(a)].x(), c.points[size_t(a)].y(), c.points[size_t(a)].z()});
      const auto ib = input_index.find({c.points[size_t(b)].x(), c.points[size_t(b)].y(), c.points[size_t(b)].z()});
      if (ia != input_index.end() && ib != input_index.end() && input_edges.count(std::minmax(ia->second, ib->second)))
        continue;
      ++checked;
      const double l = normalized_length((c.points[size_t(a)] - c.points[size_t(b)]).norm(), r.sizes[size_t(a)],
                                         r.sizes[size_t(b)]);
      if (!(l < options.max_normalized_length)) ++too_long;
    }
  EXPECT_GT(checked, 0u);
  EXPECT_EQ(too_long, 0u);
}

}  // namespace

TEST(Coarsen, Sphere728AtEps01GivesACoarseClosedSphere) {
  const TriSurface input = dthex_test::read_bundled_mesh("sphere728.off");
  const CoarsenResult r = coarsen(input);
  EXPECT_GE(r.surface.points.size(), 12u);
  EXPECT_LE(r.surface.points.size(), 40u);
  EXPECT_EQ(euler_characteristic(r.surface), 2);
  expect_closed_oriented_manifold(r.surface, "sphere728");
  EXPECT_EQ(r.collapses, input.points.size() - r.surface.points.size());
  // Coarse but well shaped.
  EXPECT_GT(summarize(triangle_shapes(r.surface)).min, 0.5);
}

TEST(Coarsen, Sphere728AtEps01CoarsensUntilEveryEdgeIsNearItsSize) {
  // The paper's sphere (r = 1, edges ~r/5): h = 2 sqrt(0.1 * 1.9) r = 0.872 r everywhere.
  // The paper ends at the 12-vertex icosahedron (edges 1.05 r = 1.21 h). Judging the
  // sqrt(2) bound on the intermediate mesh of a halfedge collapse (before the kept vertex
  // is smoothed) stopped at 20 vertices with edges down to 0.67 h; judged where the
  // smoothing puts the kept vertex, it goes on to 14 (the last two collapses to the
  // icosahedron need a transient edge of >= 1.46 h).
  const TriSurface input = dthex_test::read_bundled_mesh("sphere728.off");
  CoarsenOptions options;
  options.judge_after_smoothing = true;
  const CoarsenResult r = coarsen(input, options);
  EXPECT_GE(r.surface.points.size(), 12u);
  EXPECT_LE(r.surface.points.size(), 14u);
  EXPECT_EQ(euler_characteristic(r.surface), 2);
  ASSERT_EQ(r.sizes.size(), r.surface.points.size());
  double shortest = 1e9, longest = 0;
  for (const auto& t : r.surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      EXPECT_NEAR(r.sizes[size_t(a)], 2.0 * std::sqrt(0.1 * 1.9), 0.01);
      const double l = normalized_length((r.surface.points[size_t(a)] - r.surface.points[size_t(b)]).norm(),
                                         r.sizes[size_t(a)], r.sizes[size_t(b)]);
      shortest = std::min(shortest, l);
      longest = std::max(longest, l);
    }
  EXPECT_GT(shortest, 0.75);
  EXPECT_LT(longest, std::sqrt(2.0));
  EXPECT_GT(summarize(triangle_shapes(r.surface)).min, 0.7);

  // Judged on the intermediate mesh, as the paper prints the bound, it stops early, with
  // short edges left.
  CoarsenOptions in_place;
  in_place.judge_after_smoothing = false;
  const CoarsenResult early = coarsen(input, in_place);
  EXPECT_GE(early.surface.points.size(), 18u);
  double early_shortest = 1e9;
  for (const auto& t : early.surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      early_shortest = std::min(early_shortest, normalized_length((early.surface.points[size_t(a)] -
                                                                   early.surface.points[size_t(b)]).norm(),
                                                                  early.sizes[size_t(a)], early.sizes[size_t(b)]));
    }
  EXPECT_LT(early_shortest, 0.75);
}

TEST(Coarsen, UniformInputAtTheSizeFloorIsKeptEvenJudgedAfterSmoothing) {
  // The icosahedron: every edge equals the mean edge length, the automatic h_min, so every
  // normalized length is 1 up to rounding: nothing is short, nothing collapses.
  CoarsenOptions options;
  options.judge_after_smoothing = true;
  const CoarsenResult r = coarsen(dthex_test::read_bundled_mesh("icosahedron.off"), options);
  EXPECT_EQ(r.surface.points.size(), 12u);
  EXPECT_EQ(r.collapses, 0u);
}

TEST(Coarsen, LargerEpsGivesFewerVertices) {
  const TriSurface input = dthex_test::read_bundled_mesh("sphere728.off");
  size_t previous = input.points.size() + 1;
  std::vector<size_t> counts;
  for (double eps : {0.005, 0.01, 0.05, 0.1, 0.3}) {
    CoarsenOptions options;
    options.eps = eps;
    const size_t n = coarsen(input, options).surface.points.size();
    counts.push_back(n);
    EXPECT_LE(n, previous) << "eps " << eps;
    previous = n;
  }
  EXPECT_LT(counts.back(), counts.front());
}

TEST(Coarsen, BundledMeshesStayValid) {
  for (const char* name : {"liver.off", "spot.off", "vertebra_L1.off", "heart.off"}) {
    CoarsenOptions options;
    check_coarse_surface(dthex_test::read_bundled_mesh(name), options, name);
  }
}

TEST(Coarsen, JudgedAfterSmoothingBundledMeshesStayValidAndGetCoarser) {
  // Same invariants (every edge the coarsening made below the bound, vertices on the input,
  // topology kept, no self-intersection) with the kept vertex placed, and fewer vertices.
  for (const char* name : {"liver.off", "spot.off", "heart.off"}) {
    CoarsenOptions options;
    options.judge_after_smoothing = true;
    check_coarse_surface(dthex_test::read_bundled_mesh(name), options, name);
    const size_t placed = coarsen(dthex_test::read_bundled_mesh(name), options).surface.points.size();
    CoarsenOptions in_place;
    in_place.judge_after_smoothing = false;
    EXPECT_LT(placed, coarsen(dthex_test::read_bundled_mesh(name), in_place).surface.points.size()) << name;
  }
}

namespace {

//! The bundled sphere (r = 1) with an inward copy at r = 0.97 as a cavity: a wall far thinner
//! than the coarse edges, which tempts a vertex across it.
TriSurface thin_spherical_shell() {
  const TriSurface sphere = dthex_test::read_bundled_mesh("sphere728.off");
  TriSurface shell = sphere;
  const int n = int(sphere.points.size());
  for (const Vec3& p : sphere.points) shell.points.push_back(0.97 * p);
  for (const auto& t : sphere.triangles) shell.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  return shell;
}

//! The coarse shell is still a valid two-sheet surface (no self-intersection, the cavity
//! kept) and coarser than the input.
void expect_valid_coarser_shell(const TriSurface& coarse, const TriSurface& shell) {
  EXPECT_TRUE(self_intersections(coarse).empty());
  TriSurface verified = coarse;
  SurfaceStats stats;
  ASSERT_NO_THROW(stats = verify_surface(verified, "coarse shell"));
  EXPECT_EQ(stats.components, 2u);
  EXPECT_EQ(stats.cavities, 1u);
  EXPECT_LT(coarse.points.size(), shell.points.size());
}

}  // namespace

TEST(Coarsen, JudgedAfterSmoothingThinShellStaysOnItsOwnSide) {
  // The placed vertex is pulled back only onto input triangles facing its way: the outer
  // sphere's vertices never land on the cavity 0.03 below (which would fold the shell).
  const TriSurface shell = thin_spherical_shell();
  CoarsenOptions options;
  options.judge_after_smoothing = true;
  const CoarsenResult r = coarsen(shell, options);
  expect_valid_coarser_shell(r.surface, shell);
}

TEST(Coarsen, BundledMeshesStayValidWithoutCallbacksAndWithGlobalSmoothing) {
  CoarsenOptions plain;
  plain.edge_swap = false;
  plain.local_smoothing = false;
  check_coarse_surface(dthex_test::read_bundled_mesh("liver.off"), plain, "liver, no callbacks");
  CoarsenOptions global;
  global.local_smoothing = false;
  global.global_smoothing = true;
  const TriSurface spot = dthex_test::read_bundled_mesh("spot.off");
  const CoarsenResult r = coarsen(spot, global);
  EXPECT_GT(r.global_smoothing_iterations, 0u);
  EXPECT_TRUE(self_intersections(r.surface).empty());
  const TriangleBvh bvh(spot);
  for (const auto& p : r.surface.points) EXPECT_LT(std::sqrt(bvh.closest_point(p).distance_sq), 1e-9 * diagonal(spot));
}

TEST(Coarsen, CubeKeepsCornersAndFeatureLines) {
  // Unit cube, each face an 8 x 8 grid: 8 corners, 12 feature lines.
  TriSurface cube;
  std::map<std::array<int, 3>, int> index;
  const int n = 8;
  auto vertex = [&](std::array<int, 3> g) {
    auto it = index.find(g);
    if (it != index.end()) return it->second;
    cube.points.push_back(Vec3(g[0], g[1], g[2]) / n);
    return index[g] = int(cube.points.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto g = [&](int a, int b) {
            std::array<int, 3> p{};
            p[size_t(axis)] = side * n;
            p[size_t((axis + 1) % 3)] = a;
            p[size_t((axis + 2) % 3)] = b;
            return vertex(p);
          };
          const int v00 = g(i, j), v10 = g(i + 1, j), v11 = g(i + 1, j + 1), v01 = g(i, j + 1);
          if (side == 1) {
            cube.triangles.push_back({v00, v10, v11});
            cube.triangles.push_back({v00, v11, v01});
          } else {
            cube.triangles.push_back({v00, v11, v10});
            cube.triangles.push_back({v00, v01, v11});
          }
        }
  const Features features = detect_features(cube);
  EXPECT_EQ(features.corners.size(), 8u);
  EXPECT_EQ(features.edges.size(), 12u * n);
  CoarsenOptions options;
  check_coarse_surface(cube, options, "cube");
  const CoarsenResult r = coarsen(cube, options);
  // Flat faces coarsen to a handful of vertices; the 12 feature lines stay straight.
  EXPECT_LT(r.surface.points.size(), 100u);
  for (const auto& p : r.surface.points) {
    int on_face = 0;
    for (int k = 0; k < 3; ++k) on_face += (std::fabs(p[k]) < 1e-12 || std::fabs(p[k] - 1) < 1e-12);
    EXPECT_GE(on_face, 1);
  }
  EXPECT_EQ(detect_features(r.surface).corners.size(), 8u);
}

// A flat face off the axes has its points on its plane only to within their coordinates'
// last bits. The coarsening's self-intersection check read that noise as triangles crossing
// on every such face: a cube turned 70 degrees about (1, 2, 3) failed at every eps with
// hundreds of "self-intersecting" pairs, as did the fandisk turned any way but by 90 degrees.
TEST(Coarsen, ARotatedCubeCoarsensAsTheCubeDoes) {
  const TriSurface cube = dthex::testing::box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 16);
  TriSurface rotated = cube;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(70 * M_PI / 180, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (Vec3& p : rotated.points) p = turn * p;
  CoarsenOptions options;
  options.max_repair_rounds = 0;  // no crossing to repair on either
  const CoarsenResult straight = coarsen(cube, options);
  CoarsenResult turned;
  ASSERT_NO_THROW(turned = coarsen(rotated, options));
  EXPECT_EQ(turned.repair_rounds, 0);
  check_coarse_surface(rotated, options, "rotated cube");
  // The same kind of surface: corners and feature lines kept, about as coarse.
  EXPECT_EQ(detect_features(turned.surface).corners.size(), 8u);
  EXPECT_NEAR(double(turned.surface.points.size()), double(straight.surface.points.size()),
              0.3 * double(straight.surface.points.size()));
}

TEST(Coarsen, CtFemurStaysValid) {
  // 72,868 triangles of CT staircase: the case where quadric decimation self-intersected.
  CoarsenOptions options;
  double last_progress = -1;
  bool monotone = true;
  options.progress = [&](double f) {
    monotone = monotone && f >= last_progress && f <= 1.0;
    last_progress = f;
  };
  check_coarse_surface(dthex_test::read_bundled_mesh("femur_proximal_ct.off"), options, "femur_proximal_ct");
  EXPECT_TRUE(monotone);
  EXPECT_DOUBLE_EQ(last_progress, 1.0);
}

TEST(Coarsen, ThinShellNeedsAndGetsTheSelfIntersectionRepair) {
  // A spherical shell: outer sphere r = 1 and a cavity r = 0.97 (inward). At eps 0.1 a
  // coarse chord of the outer sphere dips ~0.1 inward and would cut the inner sphere.
  const TriSurface shell = thin_spherical_shell();
  const CoarsenResult r = coarsen(shell);
  EXPECT_GE(r.repair_rounds, 1);
  expect_valid_coarser_shell(r.surface, shell);
}

namespace {

//! The largest angle (degrees) between a coarse triangle's normal and the normal of the
//! input triangle closest to its centroid.
double largest_turn_from_input(const TriSurface& coarse, const TriSurface& input) {
  const TriangleBvh bvh(input);
  auto normal = [](const TriSurface& s, int t) {
    const auto& tri = s.triangles[size_t(t)];
    const Vec3 a = s.points[size_t(tri[0])];
    return Vec3((s.points[size_t(tri[1])] - a).cross(s.points[size_t(tri[2])] - a).normalized());
  };
  double largest = 0;
  for (size_t t = 0; t < coarse.triangles.size(); ++t) {
    const auto& tri = coarse.triangles[t];
    const Vec3 centroid = (coarse.points[size_t(tri[0])] + coarse.points[size_t(tri[1])] + coarse.points[size_t(tri[2])]) / 3;
    const TriangleBvh::ClosestPoint cp = bvh.closest_point(centroid);
    const double c = std::clamp(normal(coarse, int(t)).dot(normal(input, cp.triangle)), -1.0, 1.0);
    largest = std::max(largest, std::acos(c) * 180 / M_PI);
  }
  return largest;
}

}  // namespace

// Judged after smoothing, turns of a few tens of degrees per collapse added up where spot's
// head narrows: a coarse triangle ended facing away from the input under it (more than 90
// degrees), and the hexes there stayed inverted after projection. With the surface bound
// (60 degrees by default) no collapse makes a triangle turn that far from the input, and
// the surface stays valid.
TEST(Coarsen, SurfaceDeviationBoundKeepsTrianglesFacingTheInput) {
  const TriSurface input = dthex_test::read_bundled_mesh("spot.off");
  CoarsenOptions bounded;
  bounded.judge_after_smoothing = true;
  CoarsenOptions unbounded = bounded;
  unbounded.max_surface_deviation_deg = 180;
  const double turn_unbounded = largest_turn_from_input(coarsen(input, unbounded).surface, input);
  const CoarsenResult r = coarsen(input, bounded);
  const double turn_bounded = largest_turn_from_input(r.surface, input);
  std::printf("spot: largest turn from the input %.1f deg unbounded, %.1f deg bounded (%zu vertices)\n",
              turn_unbounded, turn_bounded, r.surface.points.size());
  EXPECT_GT(turn_unbounded, 90.0);
  EXPECT_LT(turn_bounded, 75.0);
  check_coarse_surface(input, bounded, "spot.off");
}

// The rough pass (forced here on an input below its default threshold) does most of the
// collapses, and the surface it leads to is as valid and of the same kind as the one the full
// decimation makes alone: the same checks pass, about as many vertices, shapes as good, and
// no triangle turned further from the input than the surface bound allows, though the rough
// pass itself does not test that bound.
TEST(Coarsen, RoughPassDoesMostCollapsesAndGivesTheSameKindOfSurface) {
  const TriSurface input = dthex_test::read_bundled_mesh("femur_proximal_ct.off");
  CoarsenOptions full;
  full.rough_pass_from_vertices = 0;
  CoarsenOptions rough;
  rough.rough_pass_from_vertices = 1;
  const CoarsenResult a = coarsen(input, full), b = coarsen(input, rough);
  EXPECT_EQ(a.rough_collapses, 0u);
  EXPECT_GT(b.rough_collapses, b.collapses / 2);
  EXPECT_EQ(b.collapses, input.points.size() - b.surface.points.size());
  EXPECT_NEAR(double(b.surface.points.size()), double(a.surface.points.size()), 0.25 * double(a.surface.points.size()));
  EXPECT_GT(summarize(triangle_shapes(b.surface)).avg, summarize(triangle_shapes(a.surface)).avg - 0.05);
  const double turn_full = largest_turn_from_input(a.surface, input), turn_rough = largest_turn_from_input(b.surface, input);
  std::printf("femur: %zu / %zu vertices, largest turn from the input %.1f / %.1f deg (full / with rough pass)\n",
              a.surface.points.size(), b.surface.points.size(), turn_full, turn_rough);
  EXPECT_LT(turn_rough, 75.0);
  check_coarse_surface(input, rough, "femur_proximal_ct.off");
}

// One prepared input serves several coarsenings and thin-wall counts: each gives bit for bit
// what it gives with a set-up of its own that was not cut in halves ahead, at the eps the
// input was prepared for (the run that takes the halves cut ahead), at another (whose sizes
// are made again from the radii) and with the thickness cap.
TEST(Coarsen, PreparedInputGivesWhatEachRunMakesAlone) {
  const TriSurface input = dthex_test::read_bundled_mesh("vertebra_L1.off");
  CoarsenOptions prepared_for;
  ASSERT_GE(input.points.size(), prepared_for.split_from_vertices);  // coarsened in halves
  CoarsenOptions coarser = prepared_for;
  coarser.eps = 0.3;
  CoarsenOptions capped = prepared_for;
  capped.max_size_per_thickness = 1;
  CoarseningInput prepared(input, prepared_for);
  std::vector<size_t> vertices;
  for (const CoarsenOptions& options : {prepared_for, coarser, capped}) {
    CoarseningInput own(input, options, nullptr, false);
    const CoarsenResult alone = coarsen(own, options), shared = coarsen(prepared, options);
    EXPECT_TRUE(shared.surface.points == alone.surface.points);
    EXPECT_EQ(shared.surface.triangles, alone.surface.triangles);
    EXPECT_EQ(shared.sizes, alone.sizes);
    EXPECT_EQ(shared.thin_wall_vertices, alone.thin_wall_vertices);
    EXPECT_EQ(count_thin_wall_vertices(prepared, options), count_thin_wall_vertices(input, options));
    vertices.push_back(shared.surface.points.size());
  }
  EXPECT_LT(vertices[1], vertices[0]);  // the other eps was not given the prepared sizes
  EXPECT_GT(count_thin_wall_vertices(prepared, capped), 0u);
  CoarsenOptions other_angle = prepared_for;
  other_angle.feature_angle_deg = 30;
  EXPECT_THROW(coarsen(prepared, other_angle), std::invalid_argument);
}
