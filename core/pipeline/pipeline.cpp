// SPDX-License-Identifier: MIT
#include <dthex/pipeline/pipeline.h>

#include <dthex/boundary/local_smooth.h>
#include <dthex/boundary/optimize_worst_regions.h>
#include <dthex/boundary/project_boundary.h>
#include <dthex/boundary/repair_boundary_folds.h>
#include <dthex/boundary/repair_worst_hexes.h>
#include <dthex/boundary/untangle.h>
#include <dthex/hexes/boundary_overlap.h>
#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/node_count.h>
#include <dthex/hexes/thex.h>
#include <dthex/io/read_surface.h>
#include <dthex/mesh/node_constraints.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/report/report.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/remesh_isotropic.h>
#include <dthex/surface/surface_distance.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/surface/wall_thickness.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tet_edits/flip_worst_tets.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tet_edits/split_crowded_vertices.h>
#include <dthex/tet_edits/thin_crowded_boundary_stars.h>
#include <dthex/tets/refine_flat_needles.h>
#include <dthex/tets/relax_interior_points.h>
#include <dthex/tets/remove_flat_valence3_vertices.h>
#include <dthex/tets/split_surface_tets.h>
#include <dthex/tets/tet_regions.h>
#include <dthex/tets/tetrahedralize.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <memory>
#include <numeric>
#include <optional>
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

// Times one stage, shows its report on the progress line and records it in the result.
// `fn` returns the stage's typed report, which timed_stage returns too.
template <class Fn>
auto timed_stage(PipelineResult& result, Progress& progress, const std::string& name, Fn&& fn) {
  progress.begin(name);
  const auto start = Clock::now();
  auto report = fn();
  const double seconds = seconds_since(start);
  StageRecord record{name, seconds, report};
  progress.end(describe(record.report));
  result.stages.push_back(std::move(record));
  return report;
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
  t.keep_nested_regions = options.nested == PipelineOptions::Nested::material;
  return t;
}

//! Runs one named step: the pipeline times and records it, the node prediction runs it
//! silently. The step returns its report. Both go through the same sequences below, so the
//! prediction cannot fall out of step with the pipeline.
using StageRunner = std::function<void(const std::string& name, const std::function<StageReport()>& step)>;

// After coarsening: the fixes the coarse surface needs before TetGen, into `report`.
void prepare_coarse_surface(TriSurface& coarse, const PipelineOptions& options, CoarsenStageReport& report) {
  // With projection, a flat three-triangle vertex would leave hexes no untangler makes good.
  report.flat_valence3_removed = options.project ? remove_flat_valence3_vertices(coarse) : 0;
  // Needles on flat cut faces would become sliver tets: refined in their plane.
  report.needles = refine_flat_needles(coarse);
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
// PipelineOptions::edit_boundary_tets off (a membrane) leaves out the edits of tets between
// boundary vertices.
void improve_tets_for_projection(TetMesh& tets, const PipelineOptions& options, const StageRunner& stage) {
  // Interior edges and faces between boundary vertices would give hexes that cannot all be
  // valid. First the clusters of such edges that one cone point replaces, then flips, which
  // add no point, and midpoint splits only where no flip is allowed.
  if (options.edit_boundary_tets)
    stage("flip boundary edges", [&] {
      BoundaryEdgesReport report;
      report.clusters_coned = cone_edge_clusters(tets);
      report.removed = remove_boundary_edges(tets);
      return StageReport(report);
    });
  // Then fewer tets (3-2 flips, then fewer interior points) where that does not lower the
  // local worst tet shape.
  stage("flip 3-2", [&] { return StageReport(flip_three_tet_edges(tets)); });
  stage("merge inner points", [&] { return StageReport(collapse_interior_vertices(tets)); });
  if (options.edit_boundary_tets) stage("split surface tets", [&] { return StageReport(split_surface_tets(tets)); });
  // Then the worst tets left (a boundary face with a point close above it, on thin walls):
  // first other connectivity around them, then the interior points moved.
  stage("flip worst tets", [&] { return StageReport(flip_worst_tets(tets)); });
  // The splits' points (and TetGen's) where the worst tet around each is best: THex hands a
  // tet's shape on to its hexes, and a point just above a boundary face makes flat ones.
  stage("relax inner points", [&] { return StageReport(relax_interior_points(tets)); });
  // Then the boundary vertices that too many tets share for the solid angle the surface
  // leaves them (a crease or a ridge): their hex corners would be too narrow for any smoothing.
  stage("thin boundary stars", [&] { return StageReport(thin_crowded_boundary_stars(tets)); });
  // Last, the interior vertices that too many tets share (the cones and merges above make
  // them): their hex corners would share the sphere too finely for any smoothing to widen.
  stage("split crowded vertices", [&] { return StageReport(split_crowded_vertices(tets)); });
}

// improve_tets_for_projection on each material region alone (tet_regions.h: its stages take a
// face with two tets for interior, an interface face too), the stage names then saying which.
void improve_tets_of_each_region(TetMesh& tets, const PipelineOptions& options, const StageRunner& stage) {
  if (tets.tet_region.empty()) return improve_tets_for_projection(tets, options, stage);
  std::vector<TetMesh> regions = split_tet_regions(tets);
  for (size_t r = 0; r < regions.size(); ++r)
    improve_tets_for_projection(regions[r], options, [&](const std::string& name, const std::function<StageReport()>& step) {
      stage(name + " (region " + std::to_string(r + 1) + ")", step);
    });
  tets = merge_tet_regions(regions);
}

// The tets a given eps gives, counted: coarsen and tet-mesh as the pipeline does. The final
// node count of any dicing follows from them (diced_thex_nodes): projection and untangling
// move nodes, they add none.
TetCounts predicted_tet_counts(const TriSurface& input, const PipelineOptions& options, double eps) {
  TriSurface coarse = coarsen(input, coarsen_options_for(options, eps)).surface;
  CoarsenStageReport unused;
  prepare_coarse_surface(coarse, options, unused);
  verify_coarse_surface(coarse, "coarse surface");
  TetMesh tets = tetrahedralize(coarse, tetgen_options_for(options));
  const StageRunner silently = [](const std::string&, const std::function<StageReport()>& step) { step(); };
  if (options.project) improve_tets_of_each_region(tets, options, silently);
  return count_tet_entities(tets);
}

// predicted_tet_counts, or nothing when the meshing at eps fails (MeshingError: a coarsening
// that still self-intersects after its repair rounds, a coarse surface that fails
// verification, TetGen refusing it). Counts the failure into `report`.
std::optional<TetCounts> try_tet_counts(const TriSurface& input, const PipelineOptions& options, double eps,
                                        ChooseEpsReport& report) {
  try {
    return predicted_tet_counts(input, options, eps);
  } catch (const MeshingError& e) {
    if (report.failed_probes++ == 0) report.first_failure = "eps " + std::to_string(eps) + ": " + e.what();
    return std::nullopt;
  }
}

// The factor between the eps tried when one fails (the search's ends, and a given eps).
constexpr double kEpsStep = 0.7;

// The counts at `eps`, or, when its meshing fails, at the nearest eps that works stepping by
// `factor` (below 1 towards smaller eps, above towards larger) while it stays short of
// `limit`; `eps` becomes the one counted. Nothing when none works.
std::optional<TetCounts> nearest_tet_counts(const TriSurface& input, const PipelineOptions& options, double& eps,
                                            double factor, double limit, ChooseEpsReport& report) {
  for (double tried = eps; factor < 1 ? tried > limit : tried < limit; tried *= factor)
    if (std::optional<TetCounts> counts = try_tet_counts(input, options, tried, report)) {
      eps = tried;
      return counts;
    }
  return std::nullopt;
}

// The largest dicing the search considers (the command line's bound for --dice).
constexpr int kMaxChosenDice = 8;

// Whether a dicing reaches `target` nodes (within the search's 10%) between the counts of the
// coarsest and the finest eps.
bool dice_reaches(size_t target, const TetCounts& coarsest, const TetCounts& finest, int dice) {
  return double(target) >= 0.9 * double(diced_thex_nodes(coarsest, dice)) &&
         double(target) <= 1.1 * double(diced_thex_nodes(finest, dice));
}

// PipelineOptions::choose_dice: options.dice when it reaches the target (it fits the boundary
// better than dice 1, and a higher one would make the tets coarser), else the nearest dicing
// towards the target that does; when none does, the last one tried (1 or kMaxChosenDice),
// whose range the caller then reports.
int choose_dice_for_nodes(size_t target, const TetCounts& coarsest, const TetCounts& finest,
                          const PipelineOptions& options) {
  if (!options.choose_dice || dice_reaches(target, coarsest, finest, options.dice)) return options.dice;
  const int step = double(target) > 1.1 * double(diced_thex_nodes(finest, options.dice)) ? 1 : -1;
  int dice = options.dice;
  while (dice + step >= 1 && dice + step <= kMaxChosenDice) {
    dice += step;
    if (dice_reaches(target, coarsest, finest, dice)) break;
  }
  return dice;
}

// Bisection on log(eps) between 0.001 and 0.9: the node count falls as eps grows (not
// strictly: it can step). Where the meshing fails at an end, the nearest eps inside that works
// is the end instead (a remeshed CAD part can fail at the finest, a thin wall at the coarsest);
// a failing probe between them is taken as too coarse, so the search goes on towards smaller
// eps. With PipelineOptions::choose_dice the dicing is chosen first, from the counts at the two
// ends (choose_dice_for_nodes).
ChooseEpsReport choose_eps_for_nodes(const TriSurface& input, const PipelineOptions& options,
                                     const std::string& input_path, Progress& progress) {
  const size_t target = options.target_nodes;
  ChooseEpsReport report;
  report.target_nodes = target;
  report.preferred_dice = options.dice;
  report.dice_given = !options.choose_dice;
  // The fine end: eps 0.001, or the nearest larger eps that meshes; the coarse end: eps 0.9,
  // or the nearest smaller eps that meshes (the fine end itself at worst).
  double fine_eps = 1e-3;
  const std::optional<TetCounts> fine = nearest_tet_counts(input, options, fine_eps, 1 / kEpsStep, 0.9, report);
  if (!fine)
    throw MeshingError("every eps from 0.001 to 0.9 failed (first: " + report.first_failure + ")");
  const TetCounts finest = *fine;
  double coarse_eps = 0.9;
  std::optional<TetCounts> coarsest = nearest_tet_counts(input, options, coarse_eps, kEpsStep, fine_eps, report);
  if (!coarsest) {
    coarse_eps = fine_eps;
    coarsest = finest;
  }
  report.finest_eps = fine_eps;
  report.coarsest_eps = coarse_eps;
  const int dice = choose_dice_for_nodes(target, *coarsest, finest, options);
  report.dice = dice;
  report.preferred_least = diced_thex_nodes(*coarsest, options.dice);
  report.preferred_most = diced_thex_nodes(finest, options.dice);
  const size_t most = diced_thex_nodes(finest, dice);
  const size_t least = diced_thex_nodes(*coarsest, dice);
  auto unreachable = [&](const std::string& why) {
    return InputError("--target-nodes " + std::to_string(target) + ": " + input_path + ": " + why);
  };
  // With choose_dice, `dice` is then the last dicing tried: none reaches the target.
  std::ostringstream max_edge_ratio;
  max_edge_ratio << options.max_edge_ratio;
  const std::string with_dice = std::string(options.choose_dice ? " even" : "") + " with --dice " + std::to_string(dice);
  // Between two dicings' ranges (a thin-walled input keeps many nodes at any eps). A smaller
  // --hmin lets the fine end keep more of the input's vertices (the coarsening adds none), a
  // larger --max-edge-ratio the coarse end fewer; --hmax moves neither end the right way.
  for (int d = 1; options.choose_dice && d < kMaxChosenDice; ++d)
    if (double(target) > 1.1 * double(diced_thex_nodes(finest, d)) &&
        double(target) < 0.9 * double(diced_thex_nodes(*coarsest, d + 1)))
      throw unreachable("it lies between what --dice " + std::to_string(d) + " reaches (at most about " +
                        std::to_string(diced_thex_nodes(finest, d)) + " nodes) and what --dice " +
                        std::to_string(d + 1) + " needs (at least " +
                        std::to_string(diced_thex_nodes(*coarsest, d + 1)) +
                        "); a smaller --hmin raises the first, up to what the input's own vertices give, and a "
                        "larger --max-edge-ratio (now " + max_edge_ratio.str() + ") lowers the second");
  if (double(target) > 1.1 * double(most))
    throw unreachable("at most about " + std::to_string(most) + " nodes are reachable" + with_dice + " (eps " +
                      std::to_string(fine_eps) + ", sizes floored at --hmin); use a " + (dice < kMaxChosenDice ? "larger --dice or " : "") +
                      "smaller --hmin");
  // At the coarsest eps the curvature sizes are about twice the radii, and no collapse makes an
  // edge longer than --max-edge-ratio x its size: that ratio, not --hmax (half the diagonal by
  // default, which bounds flat parts only), is what keeps the coarse surface finer (the bundled
  // liver: 837 nodes at the least, 507 with --max-edge-ratio 3, 837 with --hmax 100).
  if (double(target) < 0.9 * double(least)) {
    // A --hmax the user gave may be what holds the count (Spot with --dice 1: at least 4,169
    // nodes, 44,875 with --hmax 0.05), or not at all (a --hmax above the automatic one): it is
    // named when the coarsest eps without it gives fewer nodes.
    size_t least_without_h_max = least;
    if (options.h_max > 0) {
      PipelineOptions automatic = options;
      automatic.h_max = 0;
      ChooseEpsReport ignored;
      if (const std::optional<TetCounts> without = try_tet_counts(input, automatic, coarse_eps, ignored))
        least_without_h_max = diced_thex_nodes(*without, dice);
    }
    const bool h_max_bounds = least_without_h_max < least;
    std::ostringstream bounds;
    bounds << "the topology" << (h_max_bounds ? ", " : " and ") << "--max-edge-ratio " << max_edge_ratio.str();
    if (h_max_bounds) bounds << " and --hmax " << options.h_max << " (without it: " << least_without_h_max << ")";
    std::vector<std::string> ways;
    if (dice > 1) ways.push_back("a smaller --dice");
    if (h_max_bounds) ways.push_back("a larger --hmax");
    ways.push_back("a larger --max-edge-ratio (3 lets an edge grow to 3 times its curvature size)");
    std::string way_out = ways[0];
    for (size_t i = 1; i < ways.size(); ++i) way_out += (i + 1 == ways.size() ? " or " : ", ") + ways[i];
    throw unreachable("at least " + std::to_string(least) + " nodes are needed" + with_dice + " (eps " +
                      std::to_string(coarse_eps) + "; " + bounds.str() + " bound the coarsening); use " + way_out);
  }
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
    const std::optional<TetCounts> counts = try_tet_counts(input, options, std::exp(mid), report);
    if (!counts) {  // too coarse to mesh: towards smaller eps
      hi = mid;
      continue;
    }
    const size_t nodes = diced_thex_nodes(*counts, dice);
    consider(std::exp(mid), nodes);
    (nodes > target ? lo : hi) = mid;
  }
  if (std::abs(double(best) - double(target)) > 0.1 * double(target))
    throw unreachable("the node count jumps past it; the nearest reachable is " + std::to_string(best) +
                      " nodes (eps " + std::to_string(best_eps) + ", dice " + std::to_string(dice) + ")");
  report.eps = best_eps;
  return report;
}

}  // namespace

std::string tetgen_switches_for(const PipelineOptions& options) {
  if (!options.tetgen_switches.empty()) return options.tetgen_switches;
  if (options.thex_only) return kThexTetgenSwitches;
  if (options.min_dihedral_deg > 0) {
    std::ostringstream bounded;
    bounded << "pq1.5/" << options.min_dihedral_deg << "Y";
    return bounded.str();
  }
  return kDTHexTetgenSwitches;
}

PipelineResult read_and_verify(const std::string& input_path, Progress& progress,
                               std::unique_ptr<TriangleBvh>* search_tree, const PipelineOptions& options) {
  PipelineResult result;
  result.input_path = input_path;
  timed_stage(result, progress, "read", [&] {
    result.input = read_surface(input_path);
    return ReadReport{result.input.points.size(), result.input.triangles.size()};
  });
  if (options.repair == PipelineOptions::Repair::safe) {
    SurfaceRepairOptions repair_options;
    repair_options.islands.min_triangles = options.min_island_triangles;
    repair_options.islands.min_volume_fraction = options.min_island_volume_fraction;
    result.repairs = repair_surface(result.input, repair_options);
  }
  timed_stage(result, progress, "verify", [&] {
    VerifyOptions verify_options;
    verify_options.search_tree = search_tree;
    try {
      result.input_summary = summarize_surface(verify_surface(result.input, input_path, verify_options));
    } catch (const InputError& e) {
      if (!result.repairs.changed()) throw;
      throw InputError(std::string(e.what()) + " (ids after the safe repairs; --repair none checks the file as given)");
    }
    return result.input_summary;
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
// Poor hexes: inverted, or below scaled Jacobian 0.2.
bool poor_hexes(const PipelineResult& result) { return result.quality.inverted > 0 || result.quality.below_0_2 > 0; }

// Whether an unsound mesh made with `options` is made again at a finer eps (retry_finer).
bool finer_retry_possible(const PipelineOptions& options) {
  return options.finer_retry && options.target_nodes == 0 && !options.thex_only && options.project;
}

// One meshing of the verified input: what every stage reads, and the thin-wall count, made
// at most once.
struct Meshing {
  PipelineResult& result;
  const PipelineOptions& options;
  Progress& progress;
  const TriangleBvh& input_bvh;       // over result.input
  const TriangleBvh& coarsening_bvh;  // over result.coarsening_input()
  bool thin_walls_counted = false;
  // The thin-wall prediction's set-up of the coarsening, for the first coarsening (then freed).
  std::unique_ptr<CoarseningInput> prepared = nullptr;

  template <class Fn>
  auto stage(const std::string& name, Fn&& fn) {
    return timed_stage(result, progress, name, std::forward<Fn>(fn));
  }

  // With the thickness sizing off: are enough input vertices on walls thinner than their
  // curvature size that thin walls are the likely cause of poor hexes? Counted once.
  bool thin_walls_likely() {
    if (!thin_walls_counted)
      stage("thin walls", [&] {
        result.thin_wall_vertices =
            count_thin_wall_vertices(result.coarsening_input(), coarsen_options_for(options, result.eps));
        return ThinWallReport{result.thin_wall_vertices};
      });
    thin_walls_counted = true;
    return thin_walls_likely_cause(result);
  }
};

// PipelineOptions::target_nodes: the eps (and the dicing) that give about that many nodes.
void choose_eps(Meshing& m) {
  m.stage("choose eps", [&] {
    const ChooseEpsReport report =
        choose_eps_for_nodes(m.result.coarsening_input(), m.options, m.result.input_path, m.progress);
    m.result.eps = report.eps;
    m.result.dice = report.dice;
    return report;
  });
}

// One coarsening of coarsen_input at `eps`: stages "coarsen" and "verify coarse". `failed`
// (the larger eps that failed before) goes into the coarsen report.
void coarsen_input_at(Meshing& m, double eps, const std::vector<FailedEps>& failed) {
  PipelineResult& result = m.result;
  m.stage("coarsen", [&] {
    CoarsenOptions coarsen_options = coarsen_options_for(m.options, eps);
    coarsen_options.progress = [&](double f) { m.progress.update(f); };
    CoarsenStageReport report;
    report.failed = failed;
    report.eps = eps;
    report.coarsen = m.prepared ? coarsen(*m.prepared, coarsen_options)
                                : coarsen(result.coarsening_input(), coarsen_options, &m.coarsening_bvh);
    result.coarse = std::move(report.coarsen.surface);
    report.coarsen.surface = TriSurface{};
    report.coarsen.sizes.clear();
    result.thin_wall_vertices = report.coarsen.thin_wall_vertices;
    report.triangles = result.coarse.triangles.size();
    prepare_coarse_surface(result.coarse, m.options, report);
    return report;
  });
  m.stage("verify coarse", [&] {
    result.coarse_summary = verify_coarse_surface(result.coarse, result.input_path + " (coarse surface)");
    return result.coarse_summary;
  });
}

// How often, and by what factor, the eps is made smaller when the coarsening fails there.
constexpr int kEpsRetries = 4;
constexpr double kEpsRetryFactor = kEpsStep;

// The coarse surface TetGen meshes: the coarsened input, fixed and verified. A coarsening that
// fails (MeshingError: it still self-intersects after its repair rounds, or its surface fails
// verification) is tried again at kEpsRetryFactor x the eps, up to kEpsRetries times; the
// "coarsen" stage report lists the eps that failed, and result.eps is the one used.
void coarsen_input(Meshing& m) {
  PipelineResult& result = m.result;
  std::vector<FailedEps> failed;
  for (int attempt = 0;; ++attempt) {
    const size_t stages_before = result.stages.size();
    try {
      coarsen_input_at(m, result.eps, failed);
      return;
    } catch (const MeshingError& e) {
      if (attempt >= kEpsRetries) throw;
      failed.push_back(FailedEps{result.eps, e.what()});
      result.stages.resize(stages_before);  // the failed attempt's records (its time is in total_seconds)
      const double smaller = result.eps * kEpsRetryFactor;
      m.progress.end("failed");
      m.progress.message("eps " + std::to_string(result.eps) + " failed: " + e.what() + "; trying eps " +
                         std::to_string(smaller));
      result.eps = smaller;
    }
  }
}

// TetGen's tets of the coarse surface, with projection improved for it (improve_tets_of_each_region).
TetMesh mesh_with_tets(Meshing& m) {
  PipelineResult& result = m.result;
  TetMesh tets;
  m.stage("tetrahedralize", [&] {
    tets = tetrahedralize(result.coarse, tetgen_options_for(m.options));
    result.tets = tets.tets.size();
    result.tet_shape = summarize(tet_shapes(tets));
    return TetrahedralizeReport{result.tets};
  });
  if (!m.options.thex_only && m.options.project) {
    improve_tets_of_each_region(tets, m.options, [&](const std::string& name, const std::function<StageReport()>& step) {
      m.stage(name, [&] {
        StageReport report = step();
        result.tets = tets.tets.size();
        return report;
      });
    });
    result.tets = tets.tets.size();
    result.tet_shape = summarize(tet_shapes(tets));  // the tets THex gets
  }
  return tets;
}

// THex: each tet into four hexes (the tets are freed after).
void split_tets_into_hexes(Meshing& m, TetMesh tets) {
  m.stage("thex", [&] {
    m.result.hexes = thex(tets);
    return HexCountReport{m.result.hexes.hexes.size()};
  });
}

// Each hex into dice^3.
void dice_hexes(Meshing& m) {
  m.stage("dice", [&] {
    m.result.hexes = dice(m.result.hexes, m.result.dice);
    return HexCountReport{m.result.hexes.hexes.size()};
  });
}

// The boundary nodes onto the input surface (feature nodes held on their lines).
void project_onto_input(Meshing& m, const NodeConstraints& constraints) {
  m.stage("project", [&] {
    ProjectOptions project_options;
    project_options.constraints = &constraints;  // the relaxation leaves feature nodes on their lines
    return project_boundary(m.result.hexes, m.result.coarse, m.result.input, m.input_bvh, project_options);
  });
}

void untangle_hexes(Meshing& m, const NodeConstraints& constraints) {
  m.stage("untangle", [&] {
    UntangleOptions untangle_options;
    untangle_options.time_limit_seconds = m.options.time_limit_seconds;
    // The untangler only removes inversions and runs its global shape pass; the hexes
    // still below a useful scaled Jacobian are raised by the local smoother next, which
    // is far cheaper than the untangler's regional repairs and gets further.
    untangle_options.target_scaled_jacobian = 0;
    untangle_options.constraints = &constraints;
    const UntangleReport report = untangle_and_smooth(m.result.hexes, m.input_bvh, untangle_options);
    m.result.inverted_before_untangle = report.inverted_before;
    return report;
  });
}

// Stage "optimize worst regions" where hexes stayed below `level` (what the smoother reached):
// the nodes around the worst of them move together, up to that level. Returns the minimum after.
double optimize_worst_below(Meshing& m, const NodeConstraints& constraints, double level, double min_now) {
  if (min_now >= level) return min_now;
  return m.stage("optimize worst regions", [&] {
           OptimizeWorstRegionsOptions region_options;
           region_options.target = level;
           region_options.constraints = &constraints;
           region_options.surface = &m.input_bvh;
           region_options.knife_edge_zone = m.options.knife_edge_slide;
           region_options.surface_slack = m.options.boundary_slack;
           region_options.max_surface_offset = m.options.boundary_slack_cap * m.input_bvh.bounds().diagonal().norm();
           region_options.time_limit_seconds = m.options.time_limit_seconds;
           return optimize_worst_regions(m.result.hexes, region_options);
         })
      .min_after;
}

// Stage "slide on creases": the worst hexes left by the smoother and the regions often have a
// corner at a node on a crease line, which both hold still (the regions move interior nodes,
// and boundary nodes off creases only). Their crease nodes move along their lines, raising the
// hexes within kCreaseSlideBand of the minimum (so the minimum cannot fall), and where that
// gains, the regions run again around the freed hexes. A slide that folds boundary faces into
// the mesh is undone: a node moved along a concave crease can turn a quad over there, and the
// fold repair would then lower the hexes around it (the shared armadillo's worst 0.243 -> 0.202).
// `quads` and `owners` are the mesh's boundary_quads() and their hexes, found by the first
// slide that needs them (empty until then; the topology does not change between rounds).
// Returns the minimum after.
double slide_worst_on_creases(Meshing& m, const NodeConstraints& constraints, const LocalSmoothOptions& smoothed_with,
                              double min_now, std::vector<std::array<int, 4>>& quads, std::vector<int>& owners) {
  const double level = smoothed_with.lift_to_scaled_jacobian;
  if (min_now >= level) return min_now;
  LocalSmoothOptions along = smoothed_with;
  along.slide_along_creases = true;
  along.shape_sweeps = 0;
  along.lift_step = 0;
  along.target_scaled_jacobian = std::min(level, min_now + kCreaseSlideBand);
  HexMesh& hexes = m.result.hexes;
  const CreaseSlideStageReport slid = m.stage("slide on creases", [&] {
    CreaseSlideStageReport report;
    const std::vector<Vec3> before = hexes.nodes;
    report.smooth = smooth_worst_hexes(hexes, m.input_bvh, along);
    if (report.smooth.moves == 0) return report;
    if (quads.empty()) quads = boundary_quads(hexes, &owners);
    report.faces_inside_after = find_boundary_faces_inside(hexes, quads, owners).faces_inside;
    if (report.faces_inside_after == 0) return report;
    std::vector<Vec3> after = std::move(hexes.nodes);
    hexes.nodes = before;
    report.faces_inside_before = find_boundary_faces_inside(hexes, quads, owners).faces_inside;
    report.undone = report.faces_inside_after > report.faces_inside_before;
    if (!report.undone) hexes.nodes = std::move(after);
    return report;
  });
  if (slid.undone || !(slid.smooth.min_scaled_jacobian_after > min_now)) return min_now;
  return optimize_worst_below(m, constraints, level, slid.smooth.min_scaled_jacobian_after);
}

// The local smoother on the worst hexes (lifting them past its target where it reaches it),
// the regions around those it leaves behind, then the region repair of those still poor.
void smooth_and_repair_worst(Meshing& m, const NodeConstraints& constraints) {
  const PipelineOptions& options = m.options;
  LocalSmoothOptions smooth_options;
  smooth_options.time_limit_seconds = options.time_limit_seconds;
  smooth_options.constraints = &constraints;
  smooth_options.knife_edge_slide = options.knife_edge_slide;
  if (options.min_dihedral_deg > 0) {
    smooth_options.target_scaled_jacobian = kLiftedTargetScaledJacobian;
    smooth_options.lift_to_scaled_jacobian = kLiftedTargetScaledJacobian + 0.1;
  }
  const LocalSmoothReport smoothed =
      m.stage("smooth worst", [&] { return smooth_worst_hexes(m.result.hexes, m.input_bvh, smooth_options); });
  const double target = smooth_options.target_scaled_jacobian;
  double min_now =
      optimize_worst_below(m, constraints, std::max(target, smoothed.lifted_to), smoothed.min_scaled_jacobian_after);
  // A few hexes that the smoother could not bring to its target hold its lift back; with them
  // raised, the lift is made now. Not where many hexes sit just above the target (a thin
  // wall's): lifting them reshapes much of the mesh, for little (the ear drum: 9% of its hexes
  // below the lift's first step; its worst hex 0.287 -> 0.304 for average shape 0.617 -> 0.577,
  // worst shape 0.108 -> 0.010, and 5 s). Nor where the regions fell short of the target: a
  // hex the joint move of its region could not raise holds the minimum, the smoother's node
  // by node moves would not raise it either, and its lift would only reshape the hexes above
  // (the armadillo: the regions ended at 0.280, the lift took 8.8 s and left 0.280).
  if (smoothed.lifted_to == 0 && smooth_options.lift_step > 0 && min_now >= target &&
      double(tally_scaled_jacobians(m.result.hexes, target + smooth_options.lift_step).below) <=
          kMostHexesToLift * double(m.result.hexes.hexes.size())) {
    const LocalSmoothReport lifted =
        m.stage("lift worst", [&] { return smooth_worst_hexes(m.result.hexes, m.input_bvh, smooth_options); });
    min_now =
        optimize_worst_below(m, constraints, std::max(target, lifted.lifted_to), lifted.min_scaled_jacobian_after);
  }
  // Each slide and regions frees hexes the next can raise: again while a round gains.
  std::vector<std::array<int, 4>> quads;
  std::vector<int> owners;
  for (int round = 0; round < kCreaseSlideRounds; ++round) {
    const double was = min_now;
    min_now = slide_worst_on_creases(m, constraints, smooth_options, min_now, quads, owners);
    if (!(min_now > was + 1e-3)) break;
  }
  RepairWorstHexesOptions repair_options;
  repair_options.constraints = &constraints;
  repair_options.knife_edge_slide = options.knife_edge_slide;
  repair_options.time_limit_seconds = options.time_limit_seconds;
  if (options.min_dihedral_deg > 0) repair_options.target_scaled_jacobian = kLiftedTargetScaledJacobian;
  // Only where a hex is still inverted: after the smoother and the regions, every run seen
  // that started from a valid minimum below the threshold ended its first round lower and was
  // undone, at a cost (skull_hollow sized by curvature alone: 34-44 s; the 16-degree wedge,
  // the 4 x 4 x 0.4 plate, the aneurysm at --dice 3), while from inverted hexes it gains (an
  // armadillo variant -0.024 -> 0.032). Hexes left below the threshold make this mesh poor: if
  // thin walls are then the likely cause, run_pipeline meshes again sized by thickness whatever
  // the repair reaches, so the repair waits for that mesh.
  if (options.repair_worst_hexes && min_now <= 0 &&
      !(thickness_retry_possible(options) && m.thin_walls_likely()))
    m.stage("repair worst", [&] {
      RepairWorstStageReport report;
      report.repair = repair_worst_hexes(m.result.hexes, m.input_bvh, repair_options);
      report.threshold = repair_options.threshold;
      report.hexes = m.result.hexes.hexes.size();
      return report;
    });
}

// The conformity check, made once: by the fold repair, which needs its boundary quads and
// probes, or else by the measurement.
struct Conformity {
  ConformityReport report;
  std::vector<std::array<int, 4>> quads;
  bool known = false;
};

// Boundary faces folded into the mesh's own volume, moved out where that can be done. With
// `finer_try_follows` (the input is meshed again at a finer eps if this mesh is unsound) the
// folds are only counted: in every unsound try measured (Spot at eps 0.2 and 0.21 and sized
// by thickness, the knot at 0.5, the aneurysm at 0.4) the repair left folds, after 2.6-8.8 s,
// and the finer try was sound. The repair then runs on the mesh kept, if that has folds.
void repair_folds(Meshing& m, Conformity& conformity, bool finer_try_follows) {
  m.stage("repair folds", [&] {
    RepairFoldsStageReport stage;
    std::vector<int> owners;
    conformity.report = check_conformity(m.result.hexes, &conformity.quads, &owners);
    conformity.known = true;
    if (conformity.report.boundary_faces_inside == 0) return stage;
    if (finer_try_follows) {
      stage.deferred = true;
      stage.repair.faces_inside_before = stage.repair.faces_inside_after = conformity.report.boundary_faces_inside;
      return stage;
    }
    RepairBoundaryFoldsOptions repair_options;
    repair_options.time_limit_seconds = m.options.time_limit_seconds;
    stage.repair = repair_boundary_folds(m.result.hexes, m.input_bvh, conformity.quads, owners, repair_options);
    if (stage.repair.moved_nodes > 0) conformity.known = false;
    return stage;
  });
}

// Each material region's hexes judged alone: counts, worst hex, and conformity (its boundary
// with the interfaces closed and not folded into its own volume).
void measure_regions(PipelineResult& result) {
  const HexMesh& mesh = result.hexes;
  int n_regions = 0;
  for (int r : mesh.region) n_regions = std::max(n_regions, r + 1);
  result.regions.assign(size_t(n_regions), RegionMeasure());
  for (RegionMeasure& r : result.regions) r.min_scaled_jacobian = 1;
  for (size_t h = 0; h < mesh.hexes.size(); ++h) {
    RegionMeasure& r = result.regions[size_t(mesh.region[h])];
    ++r.hexes;
    const double sj = result.quality.scaled_jacobian[h];
    r.inverted += sj <= 0;
    r.min_scaled_jacobian = std::min(r.min_scaled_jacobian, sj);
  }
  for (size_t r = 0; r < result.regions.size(); ++r) {
    const ConformityReport c = check_conformity(region_submesh(mesh, int(r)));
    result.regions[r].conforming = c.conforming();
    result.regions[r].boundary_faces_inside = c.boundary_faces_inside;
  }
}

// Quality, conformity, volume and the distance to the input.
void measure(Meshing& m, Conformity& conformity) {
  PipelineResult& result = m.result;
  m.stage("measure", [&] {
    result.quality = measure_hex_quality(result.hexes);
    // The fold repair's check stands unless it moved nodes (then everything is checked again).
    if (!conformity.known) conformity.report = check_conformity(result.hexes, &conformity.quads);
    result.conforming = conformity.report.conforming();
    result.boundary_faces_inside = conformity.report.boundary_faces_inside;
    result.first_inside_point = conformity.report.first_inside_point;
    std::vector<std::array<int, 4>> quads = conformity.quads;
    if (!result.hexes.region.empty()) {
      measure_regions(result);
      for (const RegionMeasure& r : result.regions) result.conforming = result.conforming && r.conforming;
      const std::vector<std::array<int, 4>> interface = interface_quads(result.hexes);
      quads.insert(quads.end(), interface.begin(), interface.end());
    }
    const TriSurface boundary = quads_to_triangles(result.hexes.nodes, quads);
    result.hex_volume = enclosed_volume(boundary);
    const TriangleBvh boundary_bvh(boundary);
    const SurfaceDistance distance = surface_distance(boundary, boundary_bvh, result.input, m.input_bvh);
    result.hausdorff = distance.hausdorff;
    result.mean_distance = distance.mean;
    result.worst_hexes = worst_by(result.quality.scaled_jacobian, 10);
    return MeasureReport{result.quality.inverted, result.quality.below_0_2,
                         result.quality.scaled_jacobian_stats.min, result.conforming, result.boundary_faces_inside};
  });
}

// Every stage after verification, into `result` (which holds the verified input and, if it
// was remeshed, the remeshed surface; `coarsening_bvh` is the tree over the one coarsened).
void mesh_verified_input(PipelineResult& result, const TriangleBvh& input_bvh, const TriangleBvh& coarsening_bvh,
                         const PipelineOptions& options, Progress& progress, bool finer_try_follows,
                         std::unique_ptr<CoarseningInput> prepared = nullptr) {
  Meshing m{result, options, progress, input_bvh, coarsening_bvh, false, std::move(prepared)};
  result.thickness_ratio_used = options.thickness_ratio;
  result.eps = options.eps;
  result.dice = options.dice;
  if (options.target_nodes > 0 && !options.thex_only) choose_eps(m);
  if (options.thex_only) {
    result.coarse = result.input;
    result.coarse_summary = result.input_summary;
  } else {
    coarsen_input(m);
    m.prepared.reset();
  }
  split_tets_into_hexes(m, mesh_with_tets(m));
  if (!options.thex_only && result.dice > 1) dice_hexes(m);
  Conformity conformity;
  if (!options.thex_only && options.project) {
    // The topology is final and projection has not moved a node yet: the boundary quads and
    // nodes and the feature nodes, found once for the stages below (each search sorts every
    // hex face).
    const NodeConstraints constraints = node_constraints(result.hexes, result.coarse);
    project_onto_input(m, constraints);
    untangle_hexes(m, constraints);
    smooth_and_repair_worst(m, constraints);
    repair_folds(m, conformity, finer_try_follows);
  }
  measure(m, conformity);
  // Poor hexes left with the wall-thickness sizing off: are thin walls the likely cause?
  if (poor_hexes(result) && !options.thex_only && options.thickness_ratio <= 0) m.thin_walls_likely();
}

// An input of needles (PipelineOptions::remesh) is remeshed with even triangles into
// result.remeshed. A remeshing that gave up, or a remeshed surface that fails verification or
// is no better (no fewer needles, or a smaller smallest angle), is dropped (the report says
// why): the input itself is then coarsened, as without the option.
void remesh_if_needed(PipelineResult& result, const TriangleBvh& input_bvh, const PipelineOptions& options,
                      Progress& progress) {
  if (options.thex_only || options.remesh == PipelineOptions::Remesh::never) return;
  const double needles = needle_share(result.input);
  if (options.remesh == PipelineOptions::Remesh::automatic && needles < kRemeshNeedleShare) return;
  timed_stage(result, progress, "remesh input", [&] {
    RemeshIsotropicOptions remesh_options;
    remesh_options.progress = [&](double f) { progress.update(f); };
    RemeshStageReport report;
    report.needle_share_before = needles;
    TriSurface remeshed = remesh_isotropic(result.input, remesh_options, &report.remesh, &input_bvh);
    using Outcome = RemeshStageReport::Outcome;
    if (report.remesh.gave_up) {
      report.outcome = Outcome::gave_up;
      return report;
    }
    try {
      verify_surface(remeshed, result.input_path + " (remeshed)");
    } catch (const InputError& e) {
      report.outcome = Outcome::failed_verification;
      report.failure = e.what();
      return report;
    }
    // It must have fewer needles and no smaller angle, or it is no better to start from.
    report.needle_share_after = needle_share(remeshed);
    if (report.needle_share_after >= needles || report.remesh.min_angle_after_deg < report.remesh.min_angle_before_deg) {
      report.outcome = Outcome::no_better;
      return report;
    }
    result.remeshed = std::move(remeshed);
    report.outcome = Outcome::kept;
    return report;
  });
}

// Whether the fold repair of `r` was left for a finer try (repair_folds): its folds are then
// still there, to be repaired if the mesh is kept (repair_left_folds).
bool fold_repair_left(const PipelineResult& r) {
  const RepairFoldsStageReport* folds = r.stage_report<RepairFoldsStageReport>("repair folds");
  return folds && folds->deferred;
}

MeshTryReport try_report(const PipelineResult& r) {
  MeshTryReport t;
  t.thickness_ratio = r.thickness_ratio_used;
  t.eps = r.eps;
  t.inverted = r.quality.inverted;
  t.min_scaled_jacobian = r.quality.scaled_jacobian_stats.min;
  t.conforming = r.conforming;
  t.fold_repair_left = fold_repair_left(r);
  return t;
}

// The order in which two meshes of one input are preferred (better_try).
bool better_mesh(const PipelineResult& a, const PipelineResult& b) { return better_try(try_report(a), try_report(b)); }

// The seconds of a mesh's own stages, after the first `shared_stages` (reading, verifying,
// remeshing) that every try of an input shares.
double meshing_seconds(const PipelineResult& r, size_t shared_stages) {
  double sum = 0;
  for (size_t i = shared_stages; i < r.stages.size(); ++i) sum += r.stages[i].seconds;
  return sum;
}

// The verified input of `result` meshed once more with `options`, into `again` (which starts
// with the first `shared_stages` stages of `result`, the ones every try shares). A failure
// (TetGen refusing the surface, memory) is returned in the try's report, not thrown: it must
// not cost the mesh already made.
MeshTryReport mesh_again(const PipelineResult& result, PipelineResult& again, size_t shared_stages,
                         const TriangleBvh& input_bvh, const TriangleBvh& coarsening_bvh,
                         const PipelineOptions& options, Progress& progress, bool finer_try_follows) {
  // What reading and verifying made, which every try shares: the search tree too, so the kept
  // try still has it (input_bvh is that tree) and the safe repairs' report.
  again.input_path = result.input_path;
  again.input = result.input;
  again.input_tree = result.input_tree;
  again.repairs = result.repairs;
  again.input_summary = result.input_summary;
  again.remeshed = result.remeshed;
  again.stages.assign(result.stages.begin(), result.stages.begin() + long(shared_stages));
  MeshTryReport report;
  report.thickness_ratio = options.thickness_ratio;
  report.eps = options.eps;
  try {
    mesh_verified_input(again, input_bvh, coarsening_bvh, options, progress, finer_try_follows);
    return try_report(again);
  } catch (const MeshingError& e) {
    report.failed = true;
    report.failure = e.what();
  } catch (const std::bad_alloc&) {
    report.failed = true;
    report.failure = "out of memory";
  }
  return report;
}

// Thin walls sized by curvature alone are the commonest cause of poor hexes: `result`, meshed
// so, is meshed again sized by the wall thickness (--thickness-ratio 1) and the better of the
// two kept (better_mesh), with the other as one stage line and result.thickness_retry saying
// what was done. The first `shared_stages` stages (reading, verifying, remeshing) are shared.
// Returns whether the thickness-sized mesh was kept.
bool retry_sized_by_thickness(PipelineResult& result, size_t shared_stages, const TriangleBvh& input_bvh,
                              const TriangleBvh& coarsening_bvh, const PipelineOptions& thickness_options,
                              Progress& progress) {
  // The thin-wall count is of the surface the coarsening started from.
  const std::string counted = result.remeshed.triangles.empty() ? " input vertices" : " vertices of the remeshed input";
  progress.message("poor hexes (min scaled Jacobian " + std::to_string(result.quality.scaled_jacobian_stats.min) +
                   ") and " + std::to_string(result.thin_wall_vertices) + counted +
                   " on thin walls: meshing again sized by wall thickness (--thickness-ratio 1)");
  PipelineResult retry;
  const MeshTryReport thickness_try =
      mesh_again(result, retry, shared_stages, input_bvh, coarsening_bvh, thickness_options, progress,
                 finer_retry_possible(thickness_options));
  ThicknessRetryReport report;
  report.ran = true;
  report.thin_wall_vertices = result.thin_wall_vertices;
  report.coarsening_vertices = result.coarsening_input().points.size();
  report.remeshed_input = !result.remeshed.triangles.empty();
  report.curvature = try_report(result);
  report.thickness = thickness_try;
  report.kept_thickness = !thickness_try.failed && better_mesh(retry, result);
  if (report.kept_thickness) {  // the kept mesh's stages, and the first try as one line
    const StageRecord first{"curvature-sized try", meshing_seconds(result, shared_stages), report.curvature};
    result = std::move(retry);
    result.stages.insert(result.stages.begin() + long(shared_stages), first);
  } else {
    result.stages.push_back(StageRecord{"thickness-sized try", meshing_seconds(retry, shared_stages), thickness_try});
  }
  result.thickness_retry = report;
  result.thin_wall_vertices = report.thin_wall_vertices;
  return report.kept_thickness;
}

// An eps as the summary shows it.
std::string eps_text(double eps) {
  std::ostringstream out;
  out << std::setprecision(3) << eps;
  return out.str();
}

// A mesh a solver can take: no inverted hex, and a closed boundary that does not fold into it.
bool sound_mesh(const PipelineResult& result) { return result.quality.inverted == 0 && result.conforming; }

// The fold repair left for a finer try (repair_folds) runs on the mesh kept, if that is one
// whose repair was left: its folds are repaired and it is measured again.
void repair_left_folds(PipelineResult& result, const TriangleBvh& input_bvh, const TriangleBvh& coarsening_bvh,
                       const PipelineOptions& used, Progress& progress) {
  if (!fold_repair_left(result)) return;
  Meshing m{result, used, progress, input_bvh, coarsening_bvh, false, nullptr};
  Conformity conformity;
  repair_folds(m, conformity, false);
  measure(m, conformity);
  if (result.finer_retry.ran) result.finer_retry.tries[result.finer_retry.kept] = try_report(result);
}

// PipelineOptions::finer_retry: how often the eps is made smaller (by kEpsStep) for an unsound
// mesh. Each retry costs about a run at the finer eps (Spot at --eps 0.2: 14 s unsound, then 4
// s sound at 0.14).
constexpr int kFinerRetries = 2;

// An unsound `result`, meshed with `used`: projection folded the boundary of a coarse surface
// that is too coarse where the input curves (Spot at --eps 0.2, the aneurysm at 0.4, the knot
// at 0.5), and the untangling and the fold repair could not undo it all. It is meshed again at
// kEpsStep x the eps while the mesh stays unsound, up to kFinerRetries times, and the best of
// the meshes kept (better_mesh); the others are each one stage line, and result.finer_retry
// says what was done.
void retry_finer(PipelineResult& result, size_t shared_stages, const TriangleBvh& input_bvh,
                 const TriangleBvh& coarsening_bvh, const PipelineOptions& used, Progress& progress) {
  FinerRetryReport report;
  report.ran = true;
  report.tries.push_back(try_report(result));
  std::vector<double> seconds{meshing_seconds(result, shared_stages)};
  const ThicknessRetryReport thickness_retry = result.thickness_retry;
  const size_t thin_wall_vertices = result.thin_wall_vertices;
  PipelineOptions finer = used;
  finer.eps = result.eps;
  // `result` holds the best mesh so far, its stages those of the tries before it.
  std::vector<StageRecord> before;
  while (report.tries.size() <= size_t(kFinerRetries) && !sound_mesh(result)) {
    finer.eps *= kEpsStep;
    const MeshTryReport& last = report.tries.back();
    progress.message("the mesh at eps " + eps_text(last.eps) + " is unsound (" + describe(StageReport{last}) +
                     "): meshing again at eps " + eps_text(finer.eps));
    PipelineResult retry;
    const bool another_follows = report.tries.size() < size_t(kFinerRetries);
    const MeshTryReport tried =
        mesh_again(result, retry, shared_stages, input_bvh, coarsening_bvh, finer, progress, another_follows);
    report.tries.push_back(tried);
    seconds.push_back(meshing_seconds(retry, shared_stages));
    if (!tried.failed && better_mesh(retry, result)) {
      // The tries before the new best become stage lines, in the order they ran.
      for (size_t k = report.kept; k + 1 < report.tries.size(); ++k)
        before.push_back(StageRecord{"eps " + eps_text(report.tries[k].eps) + " try", seconds[k], report.tries[k]});
      report.kept = report.tries.size() - 1;
      result = std::move(retry);
    }
  }
  result.stages.insert(result.stages.begin() + long(shared_stages), before.begin(), before.end());
  for (size_t k = report.kept + 1; k < report.tries.size(); ++k)
    result.stages.push_back(StageRecord{"eps " + eps_text(report.tries[k].eps) + " try", seconds[k], report.tries[k]});
  result.thickness_retry = thickness_retry;
  result.thin_wall_vertices = thin_wall_vertices;
  result.finer_retry = report;
}

// Walls thinner than their curvature size, predicted before the first mesh (docs/METHOD.md,
// Thin walls). Where at least kThinWallShare of the vertices lie on walls
// kThinWallSizePerThickness times thinner than their curvature size, the curvature-sized mesh
// is poor and the retry keeps the thickness-sized one, so that one is made from the start.
// Where kMembraneShare lie on walls kMembraneSizePerThickness times thinner, the input is a
// membrane: the curvature-sized try cannot succeed, and sized at one thickness and diced as
// usual it has several times the nodes of THex. It is sized at kMembraneThicknessRatio
// thicknesses with one hex layer per THex layer (dice 1), so the hexes across the wall are
// THex's two per tet layer, and no coarse edge shorter than the wall is thick (unless the
// input's mean edge is longer): where the input's triangles are long and thin, as around a
// rounded rim, the coarsening can then collapse them, and the tets there are not slivers.
// A remeshed input (`remeshed`) has even triangles: it keeps the coarsening's own floor, its
// mean edge, so that a rim or a cone narrower than the wall is thick is sized by its curvature.
constexpr double kThinWallSizePerThickness = 2;
constexpr double kThinWallShare = 0.025;
constexpr double kMembraneSizePerThickness = 4;
constexpr double kMembraneShare = 0.25;
constexpr double kMembraneThicknessRatio = 1.25;

// The mean edge length of `surface` (the coarsening's automatic h_min).
double mean_edge_length(const TriSurface& surface) {
  double sum = 0;
  for (const auto& t : surface.triangles)
    for (int i = 0; i < 3; ++i) sum += (surface.points[size_t(t[size_t(i)])] - surface.points[size_t(t[size_t((i + 1) % 3)])]).norm();
  return surface.triangles.empty() ? 0 : sum / double(3 * surface.triangles.size());
}

// The ball a membrane's thickness is searched from, as a fraction of the bounding-box diagonal.
constexpr double kMembraneSearchRadius = 0.05;

ThinWallPredictionReport predict_thin_walls(const CoarseningInput& prepared, const PipelineOptions& options, double eps,
                                            double bbox_diagonal, bool remeshed) {
  const TriSurface& surface = prepared.surface();
  ThinWallPredictionReport report;
  report.vertices = surface.points.size();
  CoarsenOptions coarsen_options = coarsen_options_for(options, eps);
  coarsen_options.max_size_per_thickness = kThinWallSizePerThickness;
  report.thinner_twice = count_thin_wall_vertices(prepared, coarsen_options);
  if (double(report.thinner_twice) < kThinWallShare * double(report.vertices)) return report;
  coarsen_options.max_size_per_thickness = kMembraneSizePerThickness;
  report.thinner_four_times = count_thin_wall_vertices(prepared, coarsen_options);
  report.membrane = double(report.thinner_four_times) >= kMembraneShare * double(report.vertices);
  report.thickness_ratio = report.membrane ? kMembraneThicknessRatio : 1.0;
  if (report.membrane) {
    report.wall_thickness = median_wall_thickness(surface, prepared.bvh(), kMembraneSearchRadius * bbox_diagonal);
    const double floor = remeshed ? 0.0 : report.wall_thickness;
    report.h_min = options.h_min > 0 ? options.h_min : std::max(mean_edge_length(surface), floor);
  }
  // The dicing is ours to choose unless it was given (PipelineOptions::choose_dice).
  report.dice = report.membrane && options.choose_dice ? 1 : options.dice;
  return report;
}

// PipelineOptions::strict: an inverted hex or a boundary face inside the mesh is a failure.
void check_strict(const PipelineResult& result, const PipelineOptions& options) {
  if (!options.strict) return;
  if (result.quality.inverted > 0) {
    std::ostringstream out;
    out << result.input_path << ": " << result.quality.inverted << " hexes remain inverted (worst: hex "
        << result.worst_hexes.front() << ", scaled Jacobian " << result.quality.scaled_jacobian_stats.min
        << "); --strict writes nothing";
    throw MeshingError(out.str());
  }
  if (result.quality.gauss_inverted > 0) {
    std::ostringstream out;
    out << result.input_path << ": " << result.quality.gauss_inverted
        << " hexes have det J <= 0 at a Gauss point (min scaled Jacobian there "
        << result.quality.gauss_scaled_jacobian_min << "); --strict writes nothing";
    throw MeshingError(out.str());
  }
  if (result.boundary_faces_inside > 0) {
    std::ostringstream out;
    out << result.input_path << ": " << result.boundary_faces_inside
        << " boundary faces lie inside the mesh (first near " << result.first_inside_point.transpose()
        << "); --strict writes nothing";
    throw MeshingError(out.str());
  }
}

}  // namespace

PipelineResult run_pipeline(const std::string& input_path, const PipelineOptions& options, Progress& progress) {
  const auto start = Clock::now();
  std::unique_ptr<TriangleBvh> input_tree;
  PipelineResult result = read_and_verify(input_path, progress, &input_tree, options);
  if (!input_tree) input_tree = std::make_unique<TriangleBvh>(result.input);
  result.input_tree = std::move(input_tree);
  // Owned here too: a retry's result replaces `result`, and the tree must outlive every try.
  const std::shared_ptr<const TriangleBvh> input_tree_held = result.input_tree;
  const TriangleBvh& input_bvh = *input_tree_held;
  remesh_if_needed(result, input_bvh, options, progress);
  const std::unique_ptr<TriangleBvh> remeshed_bvh =
      result.remeshed.triangles.empty() ? nullptr : std::make_unique<TriangleBvh>(result.remeshed);
  const TriangleBvh& coarsening_bvh = remeshed_bvh ? *remeshed_bvh : input_bvh;
  // Thin walls predicted: the first mesh is sized by thickness, and is the only one.
  PipelineOptions first = options;
  std::unique_ptr<CoarseningInput> prepared;
  if (thickness_retry_possible(options) && options.predict_thin_walls) {
    const ThinWallPredictionReport predicted = timed_stage(result, progress, "predict thin walls", [&] {
      // The coarsening's set-up (features, curvature), made once for this and the first coarsening.
      prepared = std::make_unique<CoarseningInput>(result.coarsening_input(), coarsen_options_for(options, options.eps),
                                                   &coarsening_bvh);
      return predict_thin_walls(*prepared, options, options.eps, result.input_summary.bbox_diagonal,
                                !result.remeshed.triangles.empty());
    });
    if (predicted.thickness_ratio > 0) first.thickness_ratio = predicted.thickness_ratio, first.dice = predicted.dice;
    if (predicted.membrane) first.edit_boundary_tets = false, first.h_min = predicted.h_min;
  }
  const size_t shared_stages = result.stages.size();
  mesh_verified_input(result, input_bvh, coarsening_bvh, first, progress, finer_retry_possible(first),
                      std::move(prepared));
  PipelineOptions used = first;  // the options of the mesh kept
  if (first.thickness_ratio <= 0 && thickness_retry_possible(options) && poor_hexes(result) &&
      thin_walls_likely_cause(result)) {
    PipelineOptions thickness_options = options;
    thickness_options.thickness_ratio = 1;
    if (retry_sized_by_thickness(result, shared_stages, input_bvh, coarsening_bvh, thickness_options, progress))
      used = thickness_options;
  }
  if (finer_retry_possible(options) && !sound_mesh(result))
    retry_finer(result, shared_stages, input_bvh, coarsening_bvh, used, progress);
  repair_left_folds(result, input_bvh, coarsening_bvh, used, progress);
  result.total_seconds = seconds_since(start);
  check_strict(result, options);
  return result;
}

MeshSets find_result_sets(const PipelineResult& result, const std::string& input_path,
                          const std::vector<UserSetSpec>& user_sets) {
  MeshSetsOptions options;
  options.input_tree = result.input_tree.get();
  MeshSets sets = find_mesh_sets(result.hexes, result.input, options);
  const SurfaceNames names = read_surface_names(input_path);
  name_parts_by_input(sets, result.hexes, names.surface, names.triangle_name, names.names);
  add_user_sets(sets, result.hexes, user_sets);
  return sets;
}

bool better_try(const MeshTryReport& a, const MeshTryReport& b) {
  if (a.failed || b.failed) return !a.failed && b.failed;
  const bool repair_left = a.fold_repair_left || b.fold_repair_left;
  if (!repair_left && a.conforming != b.conforming) return a.conforming;
  if (a.inverted != b.inverted) return a.inverted < b.inverted;
  if (a.conforming != b.conforming) return a.conforming;
  return a.min_scaled_jacobian > b.min_scaled_jacobian;
}

}  // namespace dthex
