// SPDX-License-Identifier: MIT
#include <dthex/pipeline/pipeline.h>

#include <dthex/boundary/local_smooth.h>
#include <dthex/boundary/project_boundary.h>
#include <dthex/boundary/repair_boundary_folds.h>
#include <dthex/boundary/repair_worst_hexes.h>
#include <dthex/boundary/untangle.h>
#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/node_count.h>
#include <dthex/hexes/thex.h>
#include <dthex/io/read_surface.h>
#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/remesh_isotropic.h>
#include <dthex/surface/surface_distance.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tet_edits/flip_worst_tets.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tets/refine_flat_needles.h>
#include <dthex/tets/relax_interior_points.h>
#include <dthex/tets/remove_flat_valence3_vertices.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tetrahedralize.h>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>
#include <sstream>

namespace dthex {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

SurfaceSummary summarize_surface(const SurfaceStats& stats) {
  SurfaceSummary s;
  s.vertices = stats.vertices;
  s.triangles = stats.triangles;
  s.components = stats.components;
  s.cavities = stats.cavities;
  s.genus = stats.genus;
  s.volume = stats.volume;
  s.bbox_diagonal = stats.bbox_diagonal;
  s.flipped_components = stats.flipped_components;
  s.shape = stats.triangle_shape;
  return s;
}

std::string count_text(const char* what, size_t n) {
  std::ostringstream out;
  out << n << ' ' << what;
  return out.str();
}

// Times one stage, reports it on the progress line and records it in the result.
template <class Fn>
auto timed_stage(PipelineResult& result, Progress& progress, const std::string& name, Fn&& fn) {
  progress.begin(name);
  const auto start = Clock::now();
  auto detail = fn();
  const double seconds = seconds_since(start);
  progress.end(detail);
  result.stages.push_back({name, seconds, detail});
  return detail;
}

std::vector<size_t> worst_by(const std::vector<double>& values, size_t how_many) {
  std::vector<size_t> ids(values.size());
  std::iota(ids.begin(), ids.end(), size_t(0));
  how_many = std::min(how_many, ids.size());
  std::partial_sort(ids.begin(), ids.begin() + long(how_many), ids.end(),
                    [&](size_t a, size_t b) { return values[a] < values[b]; });
  ids.resize(how_many);
  return ids;
}

CoarsenOptions coarsen_options_for(const PipelineOptions& options, double eps) {
  CoarsenOptions c;
  c.eps = eps;
  c.h_min = options.h_min;
  c.h_max = options.h_max;
  c.max_normalized_length = options.max_edge_ratio;
  c.max_size_per_thickness = options.thickness_ratio;
  c.global_smoothing = options.global_smoothing;
  c.judge_after_smoothing = options.judge_after_smoothing;
  return c;
}

TetgenOptions tetgen_options_for(const PipelineOptions& options) {
  TetgenOptions t;
  t.switches = tetgen_switches_for(options);
  t.time_limit_seconds = options.time_limit_seconds;
  return t;
}

//! Runs one named step: the pipeline times and reports it, the node prediction runs it
//! silently. The step returns its one-line result. Both go through the same sequences
//! below, so the prediction cannot fall out of step with the pipeline.
using StageRunner = std::function<void(const std::string& name, const std::function<std::string()>& step)>;

// After coarsening: the fixes the coarse surface needs before TetGen. Returns what they did
// ("" if nothing).
std::string prepare_coarse_surface(TriSurface& coarse, const PipelineOptions& options) {
  std::string detail;
  // With projection, a flat three-triangle vertex would leave hexes no untangler makes good.
  const size_t flat = options.project ? remove_flat_valence3_vertices(coarse) : 0;
  if (flat) detail += ", " + count_text("flat three-triangle vertices removed", flat);
  // Needles on flat cut faces would become sliver tets: refined in their plane.
  const RefineFlatNeedlesReport needles = refine_flat_needles(coarse);
  if (needles.vertices_added)
    detail += ", " + std::to_string(needles.needles_before) + " needles on flat faces refined (" +
              count_text("vertices added", needles.vertices_added) + ", " + std::to_string(needles.needles_after) +
              " left)";
  return detail;
}

// The guard in front of TetGen: a self-intersecting coarse surface would crash it.
SurfaceSummary verify_coarse_surface(TriSurface& coarse, const std::string& name) {
  try {
    return summarize_surface(verify_surface(coarse, name));
  } catch (const InputError& e) {
    throw MeshingError(std::string("coarsening produced an invalid surface: ") + e.what());
  }
}

// With projection, TetGen's tets are changed so that THex's hexes can all be valid once
// the boundary is on the smooth input surface.
void improve_tets_for_projection(TetMesh& tets, const StageRunner& stage) {
  // Interior edges and faces between boundary vertices would give hexes that cannot all be
  // valid. First the clusters of such edges that one cone point replaces, then flips, which
  // add no point, and midpoint splits only where no flip is allowed.
  stage("flip boundary edges", [&] {
    const size_t coned = cone_edge_clusters(tets);
    const RemoveBoundaryEdgesReport removed = remove_boundary_edges(tets);
    return count_text("clusters coned", coned) + ", then of " + std::to_string(removed.candidates) +
           " interior edges between boundary vertices " + std::to_string(removed.removed) + " flipped away and " +
           std::to_string(removed.split) + " split, " + count_text("tets", tets.tets.size());
  });
  // Then fewer tets (3-2 flips, then fewer interior points) where that does not lower the
  // local worst tet shape.
  stage("flip 3-2", [&] {
    const FlipThreeTetEdgesReport flips = flip_three_tet_edges(tets);
    return count_text("three-tet edges flipped", flips.flips) + ", " + count_text("tets", tets.tets.size());
  });
  stage("merge inner points", [&] {
    const CollapseInteriorVerticesReport collapsed = collapse_interior_vertices(tets);
    return count_text("interior vertices merged into a neighbour", collapsed.collapsed) + ", " +
           count_text("tets", tets.tets.size());
  });
  stage("split surface tets", [&] {
    const SplitSurfaceTetsReport split = split_surface_tets(tets);
    return count_text("tets split", split.split_tets) + ", " + count_text("interior edges split", split.split_edges) +
           ", " + count_text("interior faces split", split.split_faces);
  });
  // Then the worst tets left (a boundary face with a point close above it, on thin walls):
  // first other connectivity around them, then the interior points moved.
  stage("flip worst tets", [&] {
    const FlipWorstTetsReport flips = flip_worst_tets(tets);
    std::ostringstream out;
    out << count_text("edges removed", flips.edge_removals) << ", " << count_text("faces flipped 2-3", flips.face_flips)
        << ", worst tet shape " << flips.worst_before << " -> " << flips.worst_after;
    return out.str();
  });
  // The splits' points (and TetGen's) where the worst tet around each is best: THex hands a
  // tet's shape on to its hexes, and a point just above a boundary face makes flat ones.
  stage("relax inner points", [&] {
    const RelaxInteriorPointsReport relaxed = relax_interior_points(tets);
    std::ostringstream out;
    out << count_text("interior points moved", relaxed.moved) << ", worst tet shape " << relaxed.worst_before << " -> "
        << relaxed.worst_after;
    return out.str();
  });
}

// Final node count for a given eps: coarsen and tet-mesh as the pipeline does, then count
// what THex and dicing would make (projection and untangling move nodes, they add none).
size_t predicted_nodes(const TriSurface& input, const PipelineOptions& options, double eps) {
  TriSurface coarse = coarsen(input, coarsen_options_for(options, eps)).surface;
  prepare_coarse_surface(coarse, options);
  verify_coarse_surface(coarse, "coarse surface");
  TetMesh tets = tetrahedralize(coarse, tetgen_options_for(options));
  const StageRunner silently = [](const std::string&, const std::function<std::string()>& step) { step(); };
  if (options.project) improve_tets_for_projection(tets, silently);
  return diced_thex_nodes(count_tet_entities(tets), options.dice);
}

// Bisection on log(eps): the node count falls as eps grows (not strictly: it can step).
double choose_eps_for_nodes(const TriSurface& input, const PipelineOptions& options, const std::string& input_path,
                            Progress& progress) {
  const size_t target = options.target_nodes;
  double fine_eps = 1e-3, coarse_eps = 0.9;
  const size_t most = predicted_nodes(input, options, fine_eps);
  const size_t least = predicted_nodes(input, options, coarse_eps);
  auto unreachable = [&](const std::string& why) {
    return InputError("--target-nodes " + std::to_string(target) + ": " + input_path + ": " + why);
  };
  if (double(target) > 1.1 * double(most))
    throw unreachable("at most about " + std::to_string(most) + " nodes are reachable with --dice " +
                      std::to_string(options.dice) + " (eps 0.001, sizes floored at --hmin); use a larger --dice or --hmin");
  if (double(target) < 0.9 * double(least))
    throw unreachable("at least " + std::to_string(least) + " nodes are needed with --dice " +
                      std::to_string(options.dice) + " (eps 0.9; the topology and --hmax bound the coarsening); "
                      "use a smaller --dice or a larger --hmax");
  double best_eps = fine_eps;
  size_t best = most;
  auto consider = [&](double eps, size_t nodes) {
    if (std::abs(double(nodes) - double(target)) < std::abs(double(best) - double(target))) {
      best = nodes;
      best_eps = eps;
    }
  };
  consider(coarse_eps, least);
  double lo = std::log(fine_eps), hi = std::log(coarse_eps);
  const int max_probes = 16;
  for (int probe = 0; probe < max_probes; ++probe) {
    progress.update(double(probe + 1) / max_probes);
    if (std::abs(double(best) - double(target)) <= 0.05 * double(target)) break;
    const double mid = 0.5 * (lo + hi);
    const size_t nodes = predicted_nodes(input, options, std::exp(mid));
    consider(std::exp(mid), nodes);
    (nodes > target ? lo : hi) = mid;
  }
  if (std::abs(double(best) - double(target)) > 0.1 * double(target))
    throw unreachable("the node count jumps past it; the nearest reachable is " + std::to_string(best) +
                      " nodes (eps " + std::to_string(best_eps) + ")");
  return best_eps;
}

}  // namespace

std::string tetgen_switches_for(const PipelineOptions& options) {
  if (!options.tetgen_switches.empty()) return options.tetgen_switches;
  return options.thex_only ? kThexTetgenSwitches : kDthexTetgenSwitches;
}

PipelineResult read_and_verify(const std::string& input_path, Progress& progress,
                               std::unique_ptr<TriangleBvh>* search_tree) {
  PipelineResult result;
  result.input_path = input_path;
  timed_stage(result, progress, "read", [&] {
    result.input = read_surface(input_path);
    return count_text("triangles", result.input.triangles.size());
  });
  timed_stage(result, progress, "verify", [&] {
    VerifyOptions verify_options;
    verify_options.search_tree = search_tree;
    result.input_summary = summarize_surface(verify_surface(result.input, input_path, verify_options));
    std::ostringstream out;
    out << result.input_summary.components << " component(s), genus " << result.input_summary.genus;
    if (result.input_summary.flipped_components) out << ", orientation flipped";
    return out.str();
  });
  return result;
}

namespace {

// Whether a poor mesh of these options can be meshed again sized by wall thickness
// (PipelineOptions::thickness_retry), and whether thin walls are the likely cause of it.
bool thickness_retry_possible(const PipelineOptions& options) {
  return options.thickness_retry && options.thickness_ratio <= 0 && options.target_nodes == 0 && !options.thex_only &&
         options.project;
}
bool thin_walls_likely_cause(const PipelineResult& result) {
  return result.thin_wall_vertices * 20 >= result.coarsening_input().points.size();
}

// Every stage after verification, into `result` (which holds the verified input and, if it
// was remeshed, the remeshed surface; `coarsening_bvh` is the tree over the one coarsened).
void mesh_verified_input(PipelineResult& result, const TriangleBvh& input_bvh, const TriangleBvh& coarsening_bvh,
                         const PipelineOptions& options, Progress& progress) {
  const std::string& input_path = result.input_path;
  result.thickness_ratio_used = options.thickness_ratio;
  result.eps = options.eps;
  // With the thickness sizing off: are enough input vertices on walls thinner than their
  // curvature size that thin walls are the likely cause of poor hexes? Counted once.
  bool thin_walls_counted = false;
  auto count_thin_walls = [&] {
    if (!thin_walls_counted)
      timed_stage(result, progress, "thin walls", [&] {
        result.thin_wall_vertices =
            count_thin_wall_vertices(result.coarsening_input(), coarsen_options_for(options, result.eps));
        return count_text("input vertices", result.thin_wall_vertices) + " on walls thinner than their size";
      });
    thin_walls_counted = true;
    return thin_walls_likely_cause(result);
  };
  if (options.target_nodes > 0 && !options.thex_only) {
    timed_stage(result, progress, "choose eps", [&] {
      result.eps = choose_eps_for_nodes(result.coarsening_input(), options, input_path, progress);
      return "eps " + std::to_string(result.eps) + " for about " + std::to_string(options.target_nodes) + " nodes";
    });
  }

  if (options.thex_only) {
    result.coarse = result.input;
    result.coarse_summary = result.input_summary;
  } else {
    timed_stage(result, progress, "coarsen", [&] {
      CoarsenOptions coarsen_options = coarsen_options_for(options, result.eps);
      coarsen_options.progress = [&](double f) { progress.update(f); };
      CoarsenResult coarse = coarsen(result.coarsening_input(), coarsen_options, &coarsening_bvh);
      result.coarse = std::move(coarse.surface);
      result.thin_wall_vertices = coarse.thin_wall_vertices;
      std::string detail = count_text("triangles", result.coarse.triangles.size());
      if (coarse.thin_wall_vertices)
        detail += " (" + count_text("input vertices", coarse.thin_wall_vertices) + " sized by wall thickness)";
      if (coarse.cut_vertices)
        detail += ", in two halves at once (cut through " + count_text("vertices", coarse.cut_vertices) + ")";
      return detail + prepare_coarse_surface(result.coarse, options);
    });
    timed_stage(result, progress, "verify coarse", [&] {
      result.coarse_summary = verify_coarse_surface(result.coarse, input_path + " (coarse surface)");
      return count_text("vertices", result.coarse_summary.vertices);
    });
  }

  TetMesh tets;
  timed_stage(result, progress, "tetrahedralize", [&] {
    tets = tetrahedralize(result.coarse, tetgen_options_for(options));
    result.tets = tets.tets.size();
    result.tet_shape = summarize(tet_shapes(tets));
    return count_text("tets", result.tets);
  });
  if (!options.thex_only && options.project) {
    improve_tets_for_projection(tets, [&](const std::string& name, const std::function<std::string()>& step) {
      timed_stage(result, progress, name, [&] {
        const std::string detail = step();
        result.tets = tets.tets.size();
        return detail;
      });
    });
    result.tet_shape = summarize(tet_shapes(tets));  // the tets THex gets
  }

  timed_stage(result, progress, "thex", [&] {
    result.hexes = thex(tets);
    return count_text("hexes", result.hexes.hexes.size());
  });
  tets = TetMesh{};

  if (!options.thex_only && options.dice > 1) {
    timed_stage(result, progress, "dice", [&] {
      result.hexes = dice(result.hexes, options.dice);
      return count_text("hexes", result.hexes.hexes.size());
    });
  }

  if (!options.thex_only && options.project) {
    // The topology is final and projection has not moved a node yet: the boundary quads and
    // nodes and the feature nodes, found once for the projection, the untangler and the
    // smoothers (each search sorts every hex face).
    const NodeConstraints constraints = node_constraints(result.hexes, result.coarse);
    timed_stage(result, progress, "project", [&] {
      ProjectOptions project_options;
      project_options.constraints = &constraints;  // the relaxation leaves feature nodes on their lines
      const ProjectReport report =
          project_boundary(result.hexes, result.coarse, result.input, input_bvh, project_options);
      std::ostringstream out;
      out << report.projected_nodes << " boundary nodes projected (largest move " << report.max_displacement << ")";
      if (report.far_nodes) out << ", " << report.far_nodes << " beyond their facet's reach";
      if (report.unconstrained_nodes) out << ", " << report.unconstrained_nodes << " with no surface facing their way";
      if (report.relaxed_moves) out << ", then relaxed on the surface (" << report.relaxed_moves << " moves)";
      return out.str();
    });
    timed_stage(result, progress, "untangle", [&] {
      UntangleOptions untangle_options;
      untangle_options.time_limit_seconds = options.time_limit_seconds;
      // The untangler only removes inversions and runs its global shape pass; the hexes
      // still below a useful scaled Jacobian are raised by the local smoother next, which
      // is far cheaper than the untangler's regional repairs and gets further.
      untangle_options.target_scaled_jacobian = 0;
      untangle_options.constraints = &constraints;
      const UntangleReport report = untangle_and_smooth(result.hexes, input_bvh, untangle_options);
      result.inverted_before_untangle = report.inverted_before;
      std::ostringstream out;
      out << report.inverted_before << " inverted before, " << report.inverted_after << " after";
      if (report.undone) out << " (its result had more, so it was undone)";
      return out.str();
    });
    double smoothed_min = 0;
    timed_stage(result, progress, "smooth worst", [&] {
      LocalSmoothOptions smooth_options;
      smooth_options.time_limit_seconds = options.time_limit_seconds;
      smooth_options.constraints = &constraints;
      smooth_options.knife_edge_slide = options.knife_edge_slide;
      const LocalSmoothReport report = smooth_worst_hexes(result.hexes, input_bvh, smooth_options);
      smoothed_min = report.min_scaled_jacobian_after;
      std::ostringstream out;
      out << "min scaled Jacobian " << report.min_scaled_jacobian_before << " -> " << report.min_scaled_jacobian_after
          << ", avg shape " << report.avg_shape_before << " -> " << report.avg_shape_after;
      return out.str();
    });
    RepairWorstHexesOptions repair_options;
    repair_options.constraints = &constraints;
    repair_options.knife_edge_slide = options.knife_edge_slide;
    repair_options.time_limit_seconds = options.time_limit_seconds;
    // Hexes left below the threshold make this mesh poor. If thin walls are then the likely
    // cause, run_pipeline meshes again sized by thickness whatever the repair reaches, so the
    // repair waits for that mesh (on skull_hollow's curvature-sized mesh it ran 70 s for nothing).
    if (options.repair_worst_hexes && smoothed_min < repair_options.threshold &&
        !(thickness_retry_possible(options) && count_thin_walls()))
      timed_stage(result, progress, "repair worst", [&] {
        const RepairWorstHexesReport report = repair_worst_hexes(result.hexes, input_bvh, repair_options);
        std::ostringstream out;
        out << count_text("hexes", report.below_before) << " below scaled Jacobian " << repair_options.threshold;
        if (report.too_many)
          out << ", " << std::round(1000.0 * double(report.below_before) / double(result.hexes.hexes.size())) / 10
              << "% of the mesh: too many for a local repair, not run";
        else if (report.undone)
          out << ": the region solve and smoothing ended worse (min " << report.min_after_region_solve
              << "), undone";
        else
          out << " -> " << report.below_after << ", min scaled Jacobian " << report.min_scaled_jacobian_before << " -> "
              << report.min_scaled_jacobian_after;
        if (report.time_limit_reached) out << " (time limit reached)";
        return out.str();
      });
  }

  // The conformity check, made once: by the fold repair, which needs its boundary quads and
  // probes, or else by the measurement.
  ConformityReport conformity;
  std::vector<std::array<int, 4>> quads;
  bool conformity_known = false;
  if (!options.thex_only && options.project) {
    timed_stage(result, progress, "repair folds", [&] {
      std::vector<int> owners;
      conformity = check_conformity(result.hexes, &quads, &owners);
      conformity_known = true;
      if (conformity.boundary_faces_inside == 0) return std::string("no boundary faces inside the mesh");
      RepairBoundaryFoldsOptions repair_options;
      repair_options.time_limit_seconds = options.time_limit_seconds;
      const RepairBoundaryFoldsReport report = repair_boundary_folds(result.hexes, input_bvh, quads, owners, repair_options);
      if (report.moved_nodes > 0) conformity_known = false;
      std::ostringstream out;
      out << report.faces_inside_before << " boundary faces inside -> " << report.faces_inside_after;
      if (report.undone)
        out << " (no move lowered the count: undone)";
      else
        out << ", " << count_text("nodes moved", report.moved_nodes) << ", min scaled Jacobian around them "
            << report.region_min_scaled_jacobian_before << " -> " << report.region_min_scaled_jacobian_after;
      if (report.time_limit_reached) out << " (time limit reached)";
      return out.str();
    });
  }

  timed_stage(result, progress, "measure", [&] {
    result.quality = measure_hex_quality(result.hexes);
    // The fold repair's check stands unless it moved nodes (then everything is checked again).
    if (!conformity_known) conformity = check_conformity(result.hexes, &quads);
    result.conforming = conformity.conforming();
    result.boundary_faces_inside = conformity.boundary_faces_inside;
    result.first_inside_point = conformity.first_inside_point;
    const TriSurface boundary = quads_to_triangles(result.hexes.nodes, quads);
    result.hex_volume = enclosed_volume(boundary);
    const TriangleBvh boundary_bvh(boundary);
    const SurfaceDistance distance = surface_distance(boundary, boundary_bvh, result.input, input_bvh);
    result.hausdorff = distance.hausdorff;
    result.mean_distance = distance.mean;
    result.worst_hexes = worst_by(result.quality.scaled_jacobian, 10);
    std::string text = count_text("inverted", result.quality.inverted);
    if (result.boundary_faces_inside > 0)
      text += ", " + count_text("boundary faces", result.boundary_faces_inside) + " inside the mesh";
    return text;
  });
  // Poor hexes left with the wall-thickness sizing off: are thin walls the likely cause?
  const bool poor = result.quality.inverted > 0 || result.quality.below_0_2 > 0;
  if (poor && !options.thex_only && options.thickness_ratio <= 0) count_thin_walls();
}

// An input of needles (PipelineOptions::remesh) is remeshed with even triangles into
// result.remeshed. A remeshing that gave up, or a remeshed surface that fails verification or
// is no better (no fewer needles, or a smaller smallest angle), is dropped with a message: the
// input itself is then coarsened, as without the option.
void remesh_if_needed(PipelineResult& result, const TriangleBvh& input_bvh, const PipelineOptions& options,
                      Progress& progress) {
  if (options.thex_only || options.remesh == PipelineOptions::Remesh::never) return;
  const double needles = needle_share(result.input);
  if (options.remesh == PipelineOptions::Remesh::automatic && needles < kRemeshNeedleShare) return;
  timed_stage(result, progress, "remesh input", [&] {
    RemeshIsotropicOptions remesh_options;
    remesh_options.progress = [&](double f) { progress.update(f); };
    RemeshIsotropicReport report;
    TriSurface remeshed = remesh_isotropic(result.input, remesh_options, &report, &input_bvh);
    std::ostringstream out;
    out << std::round(needles * 100) << "% needles; ";
    if (report.gave_up) {
      out << "the remeshing at edge " << report.edge_length
          << " only grew the mesh (feature lines that meet at a hair's angle), so the input is coarsened as it is";
      return out.str();
    }
    try {
      verify_surface(remeshed, result.input_path + " (remeshed)");
    } catch (const InputError& e) {
      out << "the remeshed surface failed verification (" << e.what() << "), so the input is coarsened as it is";
      return out.str();
    }
    // It must have fewer needles and no smaller angle, or it is no better to start from.
    const double needles_after = needle_share(remeshed);
    if (needles_after >= needles || report.min_angle_after_deg < report.min_angle_before_deg) {
      out << "the remeshed surface was no better (" << std::round(needles_after * 100) << "% needles, smallest angle "
          << std::setprecision(3) << report.min_angle_before_deg << " -> " << report.min_angle_after_deg
          << " degrees), so the input is coarsened as it is";
      return out.str();
    }
    result.remeshed = std::move(remeshed);
    out << report.triangles_before << " -> " << report.triangles_after << " triangles of edge " << report.edge_length
        << ", smallest angle " << std::setprecision(3) << report.min_angle_before_deg << " -> "
        << report.min_angle_after_deg << " degrees";
    return out.str();
  });
}

// The order in which two meshes of one input are preferred: a conforming mesh, then fewer
// inverted hexes, then the higher minimum scaled Jacobian.
bool better_mesh(const PipelineResult& a, const PipelineResult& b) {
  if (a.conforming != b.conforming) return a.conforming;
  if (a.quality.inverted != b.quality.inverted) return a.quality.inverted < b.quality.inverted;
  return a.quality.scaled_jacobian_stats.min > b.quality.scaled_jacobian_stats.min;
}

std::string min_sj_text(const PipelineResult& r) {
  std::ostringstream out;
  out << "min scaled Jacobian " << std::setprecision(3) << r.quality.scaled_jacobian_stats.min;
  if (r.quality.inverted) out << ", " << count_text("inverted", r.quality.inverted);
  if (!r.conforming) out << ", not conforming";
  return out.str();
}

}  // namespace

PipelineResult run_pipeline(const std::string& input_path, const PipelineOptions& options, Progress& progress) {
  const auto start = Clock::now();
  std::unique_ptr<TriangleBvh> input_tree;
  PipelineResult result = read_and_verify(input_path, progress, &input_tree);
  if (!input_tree) input_tree = std::make_unique<TriangleBvh>(result.input);
  const TriangleBvh& input_bvh = *input_tree;
  remesh_if_needed(result, input_bvh, options, progress);
  const std::unique_ptr<TriangleBvh> remeshed_bvh =
      result.remeshed.triangles.empty() ? nullptr : std::make_unique<TriangleBvh>(result.remeshed);
  const TriangleBvh& coarsening_bvh = remeshed_bvh ? *remeshed_bvh : input_bvh;
  const size_t verify_stages = result.stages.size();
  mesh_verified_input(result, input_bvh, coarsening_bvh, options, progress);

  // Thin walls sized by curvature alone are the commonest cause of poor hexes; when they are
  // the likely cause here, mesh again sized by the thickness and keep the better mesh.
  const bool poor = result.quality.inverted > 0 || result.quality.below_0_2 > 0;
  if (thickness_retry_possible(options) && poor && thin_walls_likely_cause(result)) {
    PipelineResult retry;
    retry.input_path = result.input_path;
    retry.input = result.input;
    retry.input_summary = result.input_summary;
    retry.remeshed = result.remeshed;
    retry.stages.assign(result.stages.begin(), result.stages.begin() + long(verify_stages));
    PipelineOptions thickness_options = options;
    thickness_options.thickness_ratio = 1;
    // The thin-wall count is of the surface the coarsening started from.
    const std::string counted = result.remeshed.triangles.empty() ? " input vertices" : " vertices of the remeshed input";
    progress.message("poor hexes (min scaled Jacobian " + std::to_string(result.quality.scaled_jacobian_stats.min) +
                     ") and " + std::to_string(result.thin_wall_vertices) + counted +
                     " on thin walls: meshing again sized by wall thickness (--thickness-ratio 1)");
    // A failure of the second try (TetGen refusing the finer surface, memory) must not cost
    // the mesh already made: it is kept, and the summary says why the other is missing.
    std::string retry_failure;
    try {
      mesh_verified_input(retry, input_bvh, coarsening_bvh, thickness_options, progress);
    } catch (const MeshingError& e) {
      retry_failure = e.what();
    } catch (const std::bad_alloc&) {
      retry_failure = "out of memory";
    }
    // The seconds of each mesh's own stages (after the shared read and verify).
    auto meshing_seconds = [&](const PipelineResult& r) {
      double sum = 0;
      for (size_t i = verify_stages; i < r.stages.size(); ++i) sum += r.stages[i].seconds;
      return sum;
    };
    const bool keep_retry = retry_failure.empty() && better_mesh(retry, result);
    std::ostringstream out;
    out << result.thin_wall_vertices << " of " << result.coarsening_input().points.size() << counted
        << " lie on walls thinner than their curvature size, so the input was meshed twice:\n"
        << "  sized by curvature (" << min_sj_text(result) << ") and by wall thickness, --thickness-ratio 1 ("
        << (retry_failure.empty() ? min_sj_text(retry) : "failed: " + retry_failure) << ");\n  kept the "
        << (keep_retry ? "thickness" : "curvature") << "-sized mesh";
    const size_t thin = result.thin_wall_vertices;
    if (keep_retry) {  // the kept mesh's stages, and the first try as one line
      const StageRecord first{"curvature-sized try", meshing_seconds(result), min_sj_text(result)};
      result = std::move(retry);
      result.stages.insert(result.stages.begin() + long(verify_stages), first);
    } else {
      result.stages.push_back(StageRecord{"thickness-sized try", meshing_seconds(retry),
                                          retry_failure.empty() ? min_sj_text(retry) : "failed: " + retry_failure});
    }
    result.thickness_retry = out.str();
    result.thin_wall_vertices = thin;
  }

  result.total_seconds = seconds_since(start);
  if (options.strict && result.quality.inverted > 0) {
    std::ostringstream out;
    out << input_path << ": " << result.quality.inverted << " hexes remain inverted (worst: hex "
        << result.worst_hexes.front() << ", scaled Jacobian " << result.quality.scaled_jacobian_stats.min
        << "); --strict writes nothing";
    throw MeshingError(out.str());
  }
  if (options.strict && result.boundary_faces_inside > 0) {
    std::ostringstream out;
    out << input_path << ": " << result.boundary_faces_inside
        << " boundary faces lie inside the mesh (first near " << result.first_inside_point.transpose()
        << "); --strict writes nothing";
    throw MeshingError(out.str());
  }
  return result;
}

}  // namespace dthex
