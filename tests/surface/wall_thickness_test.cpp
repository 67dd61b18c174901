// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/io/write_surface.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/wall_thickness.h>
#include "boundary_fixtures.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

using namespace dthex;
using dthex::testing::box_surface;

namespace {

std::vector<double> radii(const TriSurface& s, double start) {
  const TriangleBvh bvh(s);
  return inner_wall_radii(s, bvh, std::vector<double>(s.points.size(), start));
}

TriSurface flipped(TriSurface s) {
  for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

double longest_edge(const TriSurface& s) {
  double longest = 0;
  for (const auto& t : s.triangles)
    for (int i = 0; i < 3; ++i)
      longest = std::max(longest, (s.points[size_t(t[size_t(i)])] - s.points[size_t(t[size_t((i + 1) % 3)])]).norm());
  return longest;
}

// A membrane like a small ear drum: two spherical caps (sphere radius `sphere`, base radius
// `radius`) `thickness` apart along z, closed by a rounded rim (a half circle of `rim_rings`
// steps). Each sheet is rings of 6k vertices, k = 1..rings, around a pole, so its triangles
// are nearly equilateral; the surface is one sequence of rings from the top pole over the
// rim to the bottom pole, each pair zipped by angle.
TriSurface membrane_shell(double radius, double thickness, double sphere, int rings, int rim_rings) {
  TriSurface s;
  const double sagitta_base = std::sqrt(sphere * sphere - radius * radius);
  const auto cap_z = [&](double r) { return std::sqrt(sphere * sphere - r * r) - sagitta_base; };
  std::vector<std::vector<int>> sequence;  // vertex ids of each ring, by increasing angle
  std::vector<double> phases;
  const auto add_ring = [&](int count, double phase, const std::function<Vec3(double)>& at) {
    std::vector<int> ring;
    for (int i = 0; i < count; ++i) {
      ring.push_back(int(s.points.size()));
      s.points.push_back(at(2 * M_PI * (i + phase) / count));
    }
    sequence.push_back(ring);
    phases.push_back(phase);
  };
  const auto on_sheet = [&](double r, double z_offset) {
    return [=](double a) { return Vec3(r * std::cos(a), r * std::sin(a), cap_z(r) + z_offset); };
  };
  const double dr = radius / rings, half = thickness / 2;
  add_ring(1, 0, on_sheet(0, half));
  for (int k = 1; k <= rings; ++k) add_ring(6 * k, 0.5 * (k % 2), on_sheet(k * dr, half));
  for (int j = 1; j < rim_rings; ++j) {
    const double phi = M_PI * j / rim_rings;  // around the rim, from the top sheet down
    add_ring(6 * rings, 0.5 * ((rings + j) % 2), [=](double a) {
      const double r = radius + half * std::sin(phi);
      return Vec3(r * std::cos(a), r * std::sin(a), half * std::cos(phi));
    });
  }
  for (int k = rings; k >= 1; --k) add_ring(6 * k, 0.5 * ((k + rim_rings) % 2), on_sheet(k * dr, -half));
  add_ring(1, 0, on_sheet(0, -half));
  for (size_t i = 0; i + 1 < sequence.size(); ++i) {
    const std::vector<int>&a = sequence[i], &b = sequence[i + 1];
    const size_t na = a.size(), nb = b.size();
    // Each ring's vertex j stands at (j + phase) / n of the turn; the strip advances on the
    // ring whose next vertex comes first, a pole only ever on the other ring.
    size_t p = 0, q = 0;
    while ((na > 1 && p < na) || (nb > 1 && q < nb)) {
      const double next_a = (double(p + 1) + phases[i]) / double(na), next_b = (double(q + 1) + phases[i + 1]) / double(nb);
      const bool advance_a = na > 1 && p < na && (nb == 1 || q == nb || next_a <= next_b);
      if (advance_a) {
        s.triangles.push_back({a[p % na], b[q % nb], a[(p + 1) % na]});
        ++p;
      } else {
        s.triangles.push_back({a[p % na], b[q % nb], b[(q + 1) % nb]});
        ++q;
      }
    }
  }
  double volume6 = 0;
  for (const auto& t : s.triangles)
    volume6 += s.points[size_t(t[0])].dot(s.points[size_t(t[1])].cross(s.points[size_t(t[2])]));
  if (volume6 < 0)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

}  // namespace

TEST(WallThickness, SlabMeasuresHalfItsThicknessInsideAndTheStartWhereThatIsSmaller) {
  const TriSurface slab = box_surface(Vec3(0, 0, 0), Vec3(10, 10, 0.5), 20);
  for (const TriSurface& s : {slab, flipped(slab)}) {
    const std::vector<double> r = radii(s, 100.0), small = radii(s, 0.1);
    size_t checked = 0;
    for (size_t v = 0; v < s.points.size(); ++v) {
      const Vec3& p = s.points[v];
      if (p.x() < 2 || p.x() > 8 || p.y() < 2 || p.y() > 8) continue;  // away from the rim
      EXPECT_NEAR(r[v], 0.25, 1e-9) << "vertex " << v;
      EXPECT_EQ(small[v], 0.1) << "a ball thinner than the wall is already empty";
      ++checked;
    }
    EXPECT_GT(checked, 100u);
  }
}

TEST(WallThickness, ConvexEdgesOfACubeDoNotShrinkTheBall) {
  // Along an edge the ball leans on the two neighbouring faces long before it reaches the
  // opposite ones; counting them would size every feature line of a CAD part down to its
  // first ring. Only the opposite faces count: the ball along the bisector of an edge stops
  // at 1 / (1 + 1/sqrt 2) = 0.586, at a face centre at 0.5.
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 8);
  const std::vector<double> r = radii(cube, 10.0);
  for (size_t v = 0; v < cube.points.size(); ++v) {
    const Vec3& p = cube.points[v];
    int on_faces = 0;
    for (int c = 0; c < 3; ++c) on_faces += (std::abs(p[c]) < 1e-12 || std::abs(p[c] - 1) < 1e-12);
    if (on_faces == 2) EXPECT_NEAR(r[v], 1.0 / (1.0 + 1.0 / std::sqrt(2.0)), 1e-9) << "edge vertex " << v;
    if (on_faces == 1 && std::abs(p.x() - 0.5) + std::abs(p.y() - 0.5) + std::abs(p.z() - 0.5) < 0.5 + 1e-12)
      EXPECT_NEAR(r[v], 0.5, 1e-9) << "face-centre vertex " << v;
  }
}

TEST(WallThickness, SphereMeasuresItsRadius) {
  const TriSurface sphere = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : sphere.points) centre += p;
  centre /= double(sphere.points.size());
  double radius = 0;
  for (const Vec3& p : sphere.points) radius += (p - centre).norm();
  radius /= double(sphere.points.size());
  const std::vector<double> r = radii(sphere, 10 * radius);
  // Within 4%: the triangles are chords inside the sphere and the vertex normals tilt a
  // little, so the ball leans on a point slightly inside the true sphere.
  for (size_t v = 0; v < r.size(); ++v) EXPECT_NEAR(r[v], radius, 0.04 * radius) << "vertex " << v;
}

TEST(WallThickness, CoarseningSizesAThinWallByItsThickness) {
  // A 10 x 10 plate 0.5 thick: flat, so curvature alone allows triangles as wide as the plate.
  const TriSurface slab = box_surface(Vec3(0, 0, 0), Vec3(10, 10, 0.5), 20);
  CoarsenOptions curvature_only;
  curvature_only.max_size_per_thickness = 0;
  CoarsenOptions by_thickness;
  by_thickness.max_size_per_thickness = 1;
  const CoarsenResult wide = coarsen(slab, curvature_only), thin = coarsen(slab, by_thickness);
  // At least every vertex inside the two big faces (2 x 19 x 19); the rim's normals lean
  // sideways and some of its vertices see no opposite wall. Counted apart when the option
  // is off, and the same vertices.
  EXPECT_EQ(wide.thin_wall_vertices, 0u);
  EXPECT_GE(thin.thin_wall_vertices, 2u * 19 * 19);
  EXPECT_EQ(count_thin_wall_vertices(slab, curvature_only), thin.thin_wall_vertices);
  EXPECT_GT(longest_edge(wide.surface), 3.0);
  // Sizes 0.5 and new edges below sqrt(2) sizes; the input's own edges (0.5 and 0.71 on the
  // faces, 0.5 and 0.51 on the sides) are kept where nothing shorter was to collapse.
  EXPECT_LT(longest_edge(thin.surface), 0.75);
  EXPECT_GT(thin.surface.points.size(), 2 * wide.surface.points.size());
}

TEST(WallThickness, ThinPlateGetsBetterHexesSizedByThicknessAndTheSummarySaysSo) {
  // A 4 x 4 plate 0.4 thick. By curvature alone its faces coarsen to triangles several
  // times wider than the plate is thick: hexes flat across it (456 below 0.2, min 0.149). At
  // 0.5 thick the worst-hex stages lift every hex above 0.2, so the plate is thinner. Diced
  // once, as a predicted membrane is: the sizing is what is compared, in a third of the time.
  const std::string path = (dthex_test::fresh_dir("thin_plate") / "plate.off").string();
  write_surface(box_surface(Vec3(0, 0, 0), Vec3(4, 4, 0.4), 12), path);
  Progress quiet;
  PipelineOptions curvature_only, by_thickness;
  curvature_only.dice = by_thickness.dice = 1;
  curvature_only.thickness_ratio = 0;
  curvature_only.thickness_retry = false;  // the paper's sizing alone (--thickness-ratio 0)
  by_thickness.thickness_ratio = 1;
  const PipelineResult flat = run_pipeline(path, curvature_only, quiet);
  const PipelineResult sized = run_pipeline(path, by_thickness, quiet);
  std::printf("plate: min scaled Jacobian %.3f (%zu below 0.2) by curvature, %.3f (%zu) by thickness\n",
              flat.quality.scaled_jacobian_stats.min, flat.quality.below_0_2, sized.quality.scaled_jacobian_stats.min,
              sized.quality.below_0_2);
  EXPECT_EQ(sized.quality.inverted, 0u);
  EXPECT_GT(sized.quality.scaled_jacobian_stats.min, flat.quality.scaled_jacobian_stats.min + 0.05);
  EXPECT_LT(sized.quality.below_0_2, flat.quality.below_0_2);
  EXPECT_GT(sized.quality.shape_stats.avg, flat.quality.shape_stats.avg + 0.1);
  // The default run names the option; the sized one has nothing to suggest.
  ASSERT_GT(flat.quality.below_0_2, 0u);
  EXPECT_NE(summary_table(flat, curvature_only).find("--thickness-ratio 1"), std::string::npos);
  EXPECT_EQ(summary_table(sized, by_thickness).find("hint:"), std::string::npos);
}

TEST(WallThickness, DefaultMeshesAThinPlateTwiceAndKeepsTheThicknessSizedMesh) {
  // --thickness-ratio auto: the curvature-sized plate has poor hexes on a thin wall, so the
  // pipeline meshes it again sized by thickness and keeps that mesh, which is exactly the
  // mesh --thickness-ratio 1 gives. A thick box has nothing to retry. Diced once, like the
  // test above, for time.
  const auto dir = dthex_test::fresh_dir("thin_plate_auto");
  const std::string plate = (dir / "plate.off").string(), box = (dir / "box.off").string();
  write_surface(box_surface(Vec3(0, 0, 0), Vec3(4, 4, 0.4), 12), plate);
  write_surface(box_surface(Vec3(0, 0, 0), Vec3(4, 4, 4), 12), box);
  Progress quiet;
  PipelineOptions automatic, by_thickness;
  ASSERT_TRUE(automatic.thickness_retry);  // the default
  automatic.dice = by_thickness.dice = 1;
  // Predicted, the plate would be sized by thickness from the start (the membrane test
  // below); here the retry is what is tested.
  automatic.predict_thin_walls = false;
  by_thickness.thickness_ratio = 1;
  const PipelineResult kept = run_pipeline(plate, automatic, quiet);
  const PipelineResult sized = run_pipeline(plate, by_thickness, quiet);
  EXPECT_EQ(kept.thickness_ratio_used, 1.0);
  EXPECT_EQ(kept.hexes.nodes.size(), sized.hexes.nodes.size());
  EXPECT_EQ(kept.quality.scaled_jacobian_stats.min, sized.quality.scaled_jacobian_stats.min);
  EXPECT_TRUE(kept.thickness_retry.ran);
  EXPECT_TRUE(kept.thickness_retry.kept_thickness);
  EXPECT_EQ(kept.thickness_retry.thin_wall_vertices, kept.thin_wall_vertices);
  EXPECT_EQ(kept.thickness_retry.thickness.min_scaled_jacobian, kept.quality.scaled_jacobian_stats.min);
  EXPECT_NE(describe(kept.thickness_retry).find("kept the thickness-sized mesh"), std::string::npos)
      << describe(kept.thickness_retry);
  const std::string summary = summary_table(kept, automatic);
  EXPECT_NE(summary.find("meshed twice"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("hint:"), std::string::npos) << summary;
  // The first try is one stage line, and the stages still add up to no more than the total.
  double stages = 0;
  bool first_try_listed = false;
  for (const auto& stage : kept.stages) {
    stages += stage.seconds;
    first_try_listed |= stage.name == "curvature-sized try";
  }
  EXPECT_TRUE(first_try_listed);
  EXPECT_LE(stages, kept.total_seconds + 1e-6);

  const PipelineResult thick = run_pipeline(box, automatic, quiet);
  EXPECT_FALSE(thick.thickness_retry.ran) << describe(thick.thickness_retry);
  EXPECT_EQ(thick.thickness_ratio_used, 0.0);
}

TEST(WallThickness, MembraneIsMeshedOnceSizedByThicknessWithFewNodesAndSoundHexes) {
  // A small ear-drum-like shell: 2 wide, 0.05 thick (2.5% of its width), caps of radius 2.
  // Sized by curvature its coarse triangles would be many times wider than the wall is
  // thick; predicted a membrane, it is meshed once, sized by thickness and diced once, and
  // must meet the criteria of a thin-walled mesh against THex of the same input. (Wider
  // against its thickness than the ear drum would be slower; narrower, the rim's finer
  // sizing, graded inwards, would leave too little of it thin enough to be a membrane.)
  const std::string path = (dthex_test::fresh_dir("membrane") / "membrane.off").string();
  const TriSurface shell = membrane_shell(1.0, 0.05, 2.0, 32, 4);
  write_surface(shell, path);
  Progress quiet;
  PipelineOptions automatic, thex_only;
  thex_only.thex_only = true;
  const PipelineResult mesh = run_pipeline(path, automatic, quiet);
  const PipelineResult thex = run_pipeline(path, thex_only, quiet);
  const double diagonal = mesh.input_summary.bbox_diagonal;
  std::printf("membrane: %zu nodes (THex %zu), min scaled Jacobian %.3f, %zu inverted, Hausdorff %.3f%%, volume %+.2f%%\n",
              mesh.hexes.nodes.size(), thex.hexes.nodes.size(), mesh.quality.scaled_jacobian_stats.min,
              mesh.quality.inverted, 100 * mesh.hausdorff / diagonal,
              100 * (mesh.hex_volume / mesh.input_summary.volume - 1));
  const auto* predicted = mesh.stage_report<ThinWallPredictionReport>("predict thin walls");
  ASSERT_NE(predicted, nullptr);
  EXPECT_TRUE(predicted->membrane) << describe(StageReport(*predicted));
  EXPECT_NEAR(predicted->wall_thickness, 0.05, 0.005);
  EXPECT_EQ(mesh.dice, 1);
  EXPECT_EQ(mesh.thickness_ratio_used, predicted->thickness_ratio);
  EXPECT_FALSE(mesh.thickness_retry.ran);
  for (const auto& stage : mesh.stages) EXPECT_NE(stage.name, "curvature-sized try");
  EXPECT_NE(summary_table(mesh, automatic).find("a membrane, sized by wall thickness from the start"),
            std::string::npos);
  // The criteria of a thin-walled mesh: no inverted hex, scaled Jacobian at least 0.2,
  // conforming, on the input within 1% of its diagonal and 3% of its volume, under a third of
  // THex's nodes.
  EXPECT_EQ(mesh.quality.inverted, 0u);
  EXPECT_GE(mesh.quality.scaled_jacobian_stats.min, 0.2);
  EXPECT_TRUE(mesh.conforming);
  EXPECT_LE(mesh.hausdorff, 0.01 * diagonal);
  EXPECT_NEAR(mesh.hex_volume, mesh.input_summary.volume, 0.03 * mesh.input_summary.volume);
  EXPECT_LT(3 * mesh.hexes.nodes.size(), thex.hexes.nodes.size());
  // The floor is met thanks to the boundary let off the input at the rim: kept on it, a few
  // hexes there stay far below (where the coarse surface bridges the rim or, where it follows
  // it, at the tets with two faces on it; docs/CASE_STUDIES.md, Thin walls).
  PipelineOptions on_input;
  on_input.boundary_slack = 0;
  const PipelineResult held = run_pipeline(path, on_input, quiet);
  EXPECT_EQ(held.hexes.nodes.size(), mesh.hexes.nodes.size());
  EXPECT_LT(held.quality.scaled_jacobian_stats.min, 0.2);
}

TEST(WallThickness, ASphereIsNoThinWallAtAnyRatio) {
  // A sphere's wall is its diameter, far above its curvature size: no vertex is thin at any
  // ratio, also where h / (2 ratio) x 2 ratio rounds below h (ratios 3, 5, 1.25).
  const TriSurface sphere = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  for (double ratio : {1.0, 1.25, 2.0, 3.0, 5.0}) {
    CoarsenOptions options;
    options.max_size_per_thickness = ratio;
    EXPECT_EQ(count_thin_wall_vertices(sphere, options), 0u) << "ratio " << ratio;
  }
}
