// SPDX-License-Identifier: MIT
#include <dthex/report/report.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <variant>

#ifndef DTHEX_VERSION
#define DTHEX_VERSION "dev"
#endif

namespace dthex {
namespace {

std::string format(const char* fmt, double a, double b, double c, double d) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, fmt, a, b, c, d);
  return buffer;
}

std::string quality_row(const std::string& name, size_t count, const QualityStats& s) {
  char head[64];
  std::snprintf(head, sizeof head, "  %-16s %10zu ", name.c_str(), count);
  return head + format("%8.4f %8.4f %8.4f %8.4f\n", s.avg, s.std_dev, s.min, s.max);
}

nlohmann::json stats_json(const QualityStats& s) {
  return {{"count", s.count}, {"avg", s.avg}, {"std", s.std_dev}, {"min", s.min}, {"max", s.max}};
}

nlohmann::json surface_json(const SurfaceSummary& s) {
  return {{"vertices", s.vertices},   {"triangles", s.triangles},        {"components", s.components},
          {"cavities", s.cavities},   {"genus", s.genus},                {"volume", s.volume},
          {"bbox_diagonal", s.bbox_diagonal}, {"flipped_components", s.flipped_components},
          {"triangle_shape", stats_json(s.shape)}};
}

// ---------------------------------------------------------------- stage reports as prose

std::string count_text(const char* what, size_t n) {
  std::ostringstream out;
  out << n << ' ' << what;
  return out.str();
}

std::string text(const ReadReport& r) { return count_text("triangles", r.triangles); }

std::string text(const SurfaceSummary& s) {
  std::ostringstream out;
  out << count_text("vertices", s.vertices) << ", " << s.components << " component(s), genus " << s.genus;
  if (s.flipped_components) out << ", orientation flipped";
  return out.str();
}

std::string text(const RemeshStageReport& r) {
  using Outcome = RemeshStageReport::Outcome;
  std::ostringstream out;
  out << std::round(r.needle_share_before * 100) << "% needles; ";
  switch (r.outcome) {
    case Outcome::gave_up:
      out << "the remeshing at edge " << r.remesh.edge_length
          << " only grew the mesh (feature lines that meet at a hair's angle), so the input is coarsened as it is";
      break;
    case Outcome::failed_verification:
      out << "the remeshed surface failed verification (" << r.failure << "), so the input is coarsened as it is";
      break;
    case Outcome::no_better:
      out << "the remeshed surface was no better (" << std::round(r.needle_share_after * 100)
          << "% needles, smallest angle " << std::setprecision(3) << r.remesh.min_angle_before_deg << " -> "
          << r.remesh.min_angle_after_deg << " degrees), so the input is coarsened as it is";
      break;
    case Outcome::kept:
      out << r.remesh.triangles_before << " -> " << r.remesh.triangles_after << " triangles of edge "
          << r.remesh.edge_length << ", smallest angle " << std::setprecision(3) << r.remesh.min_angle_before_deg
          << " -> " << r.remesh.min_angle_after_deg << " degrees";
      break;
  }
  return out.str();
}

std::string text(const ThinWallReport& r) {
  return count_text("input vertices", r.vertices) + " on walls thinner than their size";
}

std::string short_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return buffer;
}

std::string text(const ThinWallPredictionReport& r) {
  std::ostringstream out;
  out << r.thinner_twice << " of " << r.vertices << " vertices on walls 2x thinner than their curvature size";
  if (r.thinner_four_times) out << ", " << r.thinner_four_times << " 4x";
  if (r.thickness_ratio <= 0) return out.str() + ": sized by curvature";
  out << ": " << (r.membrane ? "a membrane, " : "") << "sized by wall thickness from the start (--thickness-ratio "
      << r.thickness_ratio << ", dice " << r.dice;
  if (r.membrane) out << ", wall " << short_number(r.wall_thickness) << " thick, --hmin " << short_number(r.h_min);
  out << ")";
  return out.str();
}

std::string text(const ChooseEpsReport& r) {
  std::string out = "eps " + std::to_string(r.eps) + " for about " + std::to_string(r.target_nodes) + " nodes, dice " +
                    std::to_string(r.dice);
  const std::string range = std::to_string(r.preferred_least) + "-" + std::to_string(r.preferred_most);
  if (r.dice_given)
    out += " as given";
  else if (r.dice == r.preferred_dice)
    out += " (it reaches " + range + " nodes)";
  else
    out += " (dice " + std::to_string(r.preferred_dice) + " reaches only " + range + " nodes)";
  if (r.failed_probes)
    out += "; the meshing failed at " + count_text("eps tried", r.failed_probes) +
           ", the nearest eps that works taken instead (first: " + r.first_failure + ")";
  return out;
}

std::string text(const CoarsenStageReport& r) {
  std::string out;
  for (const FailedEps& f : r.failed) out += "eps " + short_number(f.eps) + " failed: " + f.failure + "; ";
  if (!r.failed.empty()) out += "used " + short_number(r.eps) + ": ";
  out += count_text("triangles", r.triangles);
  if (r.coarsen.thin_wall_vertices)
    out += " (" + count_text("input vertices", r.coarsen.thin_wall_vertices) + " sized by wall thickness)";
  if (r.coarsen.cut_vertices)
    out += ", in two halves at once (cut through " + count_text("vertices", r.coarsen.cut_vertices) + ")";
  if (r.flat_valence3_removed) out += ", " + count_text("flat three-triangle vertices removed", r.flat_valence3_removed);
  const size_t taken_back = r.needles.rounds_taken_back;
  if (r.needles.vertices_added)
    out += ", " + std::to_string(r.needles.needles_before) + " needles on flat faces refined (" +
           count_text("vertices added", r.needles.vertices_added) + ", " + std::to_string(r.needles.needles_after) +
           " left" + (taken_back ? "; " + count_text("later rounds", taken_back) + " that left more taken back" : "") +
           ")";
  else if (taken_back)
    out += ", " + std::to_string(r.needles.needles_before) +
           " needles on flat faces left as they were (refining them left more)";
  return out;
}

std::string text(const TetrahedralizeReport& r) { return count_text("tets", r.tets); }

std::string text(const BoundaryEdgesReport& r) {
  return count_text("clusters coned", r.clusters_coned) + ", then of " + std::to_string(r.removed.candidates) +
         " interior edges between boundary vertices " + std::to_string(r.removed.removed) + " flipped away and " +
         std::to_string(r.removed.split) + " split, " + count_text("tets", r.removed.tets_after);
}

std::string text(const FlipThreeTetEdgesReport& r) {
  return count_text("three-tet edges flipped", r.flips) + ", " + count_text("tets", r.tets_after);
}

std::string text(const CollapseInteriorVerticesReport& r) {
  return count_text("interior vertices merged into a neighbour", r.collapsed) + ", " +
         count_text("tets", r.tets_after);
}

std::string text(const SplitSurfaceTetsReport& r) {
  return count_text("tets split", r.split_tets) + ", " + count_text("interior edges split", r.split_edges) + ", " +
         count_text("interior faces split", r.split_faces);
}

std::string text(const FlipWorstTetsReport& r) {
  std::ostringstream out;
  out << count_text("edges removed", r.edge_removals) << ", " << count_text("faces flipped 2-3", r.face_flips)
      << ", worst tet shape " << r.worst_before << " -> " << r.worst_after;
  return out.str();
}

std::string text(const RelaxInteriorPointsReport& r) {
  std::ostringstream out;
  out << count_text("interior points moved", r.moved) << ", worst tet shape " << r.worst_before << " -> "
      << r.worst_after;
  return out.str();
}

std::string text(const SplitCrowdedVerticesReport& r) {
  return count_text("crowded interior vertices split", r.split) + ", most tets at an interior vertex " +
         std::to_string(r.most_tets_before) + " -> " + std::to_string(r.most_tets_after) + ", " +
         count_text("tets", r.tets_after);
}

std::string text(const ThinCrowdedBoundaryStarsReport& r) {
  std::ostringstream out;
  out << count_text("interior edges removed", r.edges_removed) << " and "
      << count_text("interior points merged", r.merged) << " at "
      << count_text("crowded boundary vertices", r.crowded_before) << " (" << r.crowded_after
      << " left), lowest corner bound " << r.lowest_bound_before << " -> " << r.lowest_bound_after << ", "
      << count_text("tets", r.tets_after);
  return out.str();
}

std::string text(const OptimizeWorstRegionsReport& r) {
  std::ostringstream out;
  out << "min scaled Jacobian " << r.min_before << " -> " << r.min_after;
  if (r.steps > 0)
    out << " in " << count_text("steps", size_t(r.steps)) << " (" << count_text("worst hexes", r.seeds) << ", "
        << count_text("nodes", r.moved_nodes) << " around them moved together)";
  if (r.off_surface_steps > 0)
    out << ", the last " << r.off_surface_steps << " from " << r.min_on_surface << " with "
        << count_text("boundary nodes", r.nodes_off_surface) << " let off the input (at most " << r.largest_offset
        << ")";
  if (r.too_many_seeds) out << ", then too many hexes near the minimum";
  if (r.seeds_without_gain)
    out << (r.steps ? ", then" : ":") << " no gain from the nodes around "
        << count_text("worst hexes", r.seeds_without_gain);
  if (r.time_limit_reached) out << ", time limit reached";
  return out.str();
}

std::string text(const HexCountReport& r) { return count_text("hexes", r.hexes); }

std::string text(const ProjectReport& r) {
  std::ostringstream out;
  out << r.projected_nodes << " boundary nodes projected (largest move " << r.max_displacement << ")";
  if (r.far_nodes) out << ", " << r.far_nodes << " beyond their facet's reach";
  if (r.unconstrained_nodes) out << ", " << r.unconstrained_nodes << " with no surface facing their way";
  if (r.relaxed_moves) out << ", then relaxed on the surface (" << r.relaxed_moves << " moves)";
  return out.str();
}

std::string text(const UntangleReport& r) {
  std::ostringstream out;
  out << r.inverted_before << " inverted before, " << r.inverted_after << " after";
  if (r.undone) out << " (its result had more, so it was undone)";
  if (r.stalled)
    out << "; stopped after " << std::round(r.stalled_after_seconds) << " s: the inverted count had stopped falling";
  return out.str();
}

std::string text(const LocalSmoothReport& r) {
  std::ostringstream out;
  out << "min scaled Jacobian " << r.min_scaled_jacobian_before << " -> " << r.min_scaled_jacobian_after
      << ", avg shape " << r.avg_shape_before << " -> " << r.avg_shape_after;
  return out.str();
}

std::string text(const CreaseSlideStageReport& s) {
  if (!s.undone) return text(s.smooth);
  std::ostringstream out;
  out << "undone: the slide (min scaled Jacobian " << s.smooth.min_scaled_jacobian_before << " -> "
      << s.smooth.min_scaled_jacobian_after << ") left " << count_text("boundary faces", s.faces_inside_after)
      << " inside the mesh, " << s.faces_inside_before << " before it";
  return out.str();
}

std::string text(const RepairWorstStageReport& s) {
  const RepairWorstHexesReport& r = s.repair;
  std::ostringstream out;
  out << count_text("hexes", r.below_before) << " below scaled Jacobian " << s.threshold;
  if (r.too_many)
    out << ", " << std::round(1000.0 * double(r.below_before) / double(std::max<size_t>(s.hexes, 1))) / 10
        << "% of the mesh: too many for a local repair, not run";
  else if (r.undone)
    out << ": the region solve and smoothing ended worse (min " << r.min_after_region_solve << "), undone";
  else
    out << " -> " << r.below_after << ", min scaled Jacobian " << r.min_scaled_jacobian_before << " -> "
        << r.min_scaled_jacobian_after;
  if (r.time_limit_reached) out << " (time limit reached)";
  return out.str();
}

std::string text(const RepairBoundaryFoldsReport& r) {
  if (r.faces_inside_before == 0) return "no boundary faces inside the mesh";
  std::ostringstream out;
  out << r.faces_inside_before << " boundary faces inside -> " << r.faces_inside_after;
  if (r.undone)
    out << " (no move lowered the count: undone)";
  else
    out << ", " << count_text("nodes moved", r.moved_nodes) << ", min scaled Jacobian around them "
        << r.region_min_scaled_jacobian_before << " -> " << r.region_min_scaled_jacobian_after;
  if (r.time_limit_reached) out << " (time limit reached)";
  else if (r.faces_inside_after > 0 && r.phases_ended_without_gain > 0)
    out << " (regions not widened further: a wider one removed no fold)";
  return out.str();
}

std::string text(const RepairFoldsStageReport& s) {
  if (!s.deferred) return text(s.repair);
  return count_text("boundary faces", s.repair.faces_inside_before) +
         " inside: repair left for the mesh kept (meshed again at a finer eps first)";
}

std::string text(const MeasureReport& r) {
  std::string out = count_text("inverted", r.inverted);
  if (r.boundary_faces_inside > 0) out += ", " + count_text("boundary faces", r.boundary_faces_inside) + " inside the mesh";
  return out;
}

std::string text(const MeshTryReport& r) {
  if (r.failed) return "failed: " + r.failure;
  std::ostringstream out;
  out << "min scaled Jacobian " << std::setprecision(3) << r.min_scaled_jacobian;
  if (r.inverted) out << ", " << count_text("inverted", r.inverted);
  if (!r.conforming) out << ", not conforming";
  if (r.fold_repair_left) out << "; fold repair left for a finer try";
  return out.str();
}

// ---------------------------------------------------------------- stage reports as JSON

using nlohmann::json;

json fields(const ReadReport& r) { return {{"vertices", r.vertices}, {"triangles", r.triangles}}; }

json fields(const SurfaceSummary& s) { return surface_json(s); }

json fields(const RemeshIsotropicReport& r) {
  return {{"triangles_before", r.triangles_before},       {"triangles_after", r.triangles_after},
          {"edge_length", r.edge_length},                 {"min_angle_before_deg", r.min_angle_before_deg},
          {"min_angle_after_deg", r.min_angle_after_deg}, {"gave_up", r.gave_up}};
}

json fields(const RemeshStageReport& r) {
  using Outcome = RemeshStageReport::Outcome;
  json j = fields(r.remesh);
  j["outcome"] = r.outcome == Outcome::kept                  ? "kept"
                 : r.outcome == Outcome::gave_up             ? "gave_up"
                 : r.outcome == Outcome::failed_verification ? "failed_verification"
                                                             : "no_better";
  j["needle_share_before"] = r.needle_share_before;
  j["needle_share_after"] = r.needle_share_after;
  if (!r.failure.empty()) j["failure"] = r.failure;
  return j;
}

json fields(const ThinWallReport& r) { return {{"thin_wall_vertices", r.vertices}}; }

json fields(const ThinWallPredictionReport& r) {
  return {{"vertices", r.vertices},           {"thinner_twice", r.thinner_twice},
          {"thinner_four_times", r.thinner_four_times}, {"thickness_ratio", r.thickness_ratio},
          {"dice", r.dice},                   {"membrane", r.membrane},
          {"wall_thickness", r.wall_thickness}, {"h_min", r.h_min}};
}

json fields(const ChooseEpsReport& r) {
  return {{"eps", r.eps},
          {"target_nodes", r.target_nodes},
          {"dice", r.dice},
          {"dice_reason", r.dice_given                     ? "given"
                          : r.dice == r.preferred_dice     ? "preferred_reaches_target"
                                                           : "preferred_cannot_reach_target"},
          {"preferred_dice", r.preferred_dice},
          {"preferred_dice_nodes", {r.preferred_least, r.preferred_most}},
          {"finest_eps", r.finest_eps},
          {"coarsest_eps", r.coarsest_eps},
          {"failed_probes", r.failed_probes},
          {"first_failure", r.first_failure}};
}

json fields(const CoarsenStageReport& s) {
  const CoarsenResult& c = s.coarsen;
  json j = {{"triangles", s.triangles},
          {"input_vertices", c.input_vertices},
          {"collapses", c.collapses},
          {"swaps", c.swaps},
          {"smoothing_moves", c.smoothing_moves},
          {"global_smoothing_iterations", c.global_smoothing_iterations},
          {"feature_edges", c.feature_edges},
          {"feature_corners", c.feature_corners},
          {"repair_rounds", c.repair_rounds},
          {"cut_vertices", c.cut_vertices},
          {"thin_wall_vertices", c.thin_wall_vertices},
          {"h_min", c.h_min},
          {"h_max", c.h_max},
          {"flat_valence3_removed", s.flat_valence3_removed},
          {"flat_needles_before", s.needles.needles_before},
          {"flat_needles_after", s.needles.needles_after},
          {"flat_needle_vertices_added", s.needles.vertices_added},
          {"flat_needle_flips", s.needles.flips},
          {"flat_needle_rounds_taken_back", s.needles.rounds_taken_back}};
  // The larger eps whose coarsening failed first (only when one did).
  if (!s.failed.empty()) {
    json failed = json::array();
    for (const FailedEps& f : s.failed) failed.push_back({{"eps", f.eps}, {"failure", f.failure}});
    j["eps"] = s.eps;
    j["failed_eps"] = failed;
  }
  return j;
}

json fields(const TetrahedralizeReport& r) { return {{"tets", r.tets}}; }

json fields(const BoundaryEdgesReport& r) {
  return {{"clusters_coned", r.clusters_coned}, {"candidates", r.removed.candidates}, {"removed", r.removed.removed},
          {"split", r.removed.split},           {"tets_before", r.removed.tets_before}, {"tets_after", r.removed.tets_after}};
}

json fields(const FlipThreeTetEdgesReport& r) {
  return {{"flips", r.flips}, {"tets_before", r.tets_before}, {"tets_after", r.tets_after}};
}

json fields(const CollapseInteriorVerticesReport& r) {
  return {{"collapsed", r.collapsed}, {"tets_before", r.tets_before}, {"tets_after", r.tets_after}};
}

json fields(const SplitSurfaceTetsReport& r) {
  return {{"split_tets", r.split_tets},
          {"split_edges", r.split_edges},
          {"split_faces", r.split_faces},
          {"coned_clusters", r.coned_clusters}};
}

json fields(const FlipWorstTetsReport& r) {
  return {{"edge_removals", r.edge_removals},
          {"face_flips", r.face_flips},
          {"worst_before", r.worst_before},
          {"worst_after", r.worst_after}};
}

json fields(const RelaxInteriorPointsReport& r) {
  return {{"moved", r.moved}, {"worst_before", r.worst_before}, {"worst_after", r.worst_after}};
}

json fields(const ThinCrowdedBoundaryStarsReport& r) {
  return {{"edges_removed", r.edges_removed},
          {"merged", r.merged},
          {"crowded_before", r.crowded_before},
          {"crowded_after", r.crowded_after},
          {"lowest_bound_before", r.lowest_bound_before},
          {"lowest_bound_after", r.lowest_bound_after},
          {"tets_before", r.tets_before},
          {"tets_after", r.tets_after}};
}

json fields(const SplitCrowdedVerticesReport& r) {
  return {{"split", r.split},
          {"crowded_before", r.crowded_before},
          {"crowded_after", r.crowded_after},
          {"most_tets_before", r.most_tets_before},
          {"most_tets_after", r.most_tets_after},
          {"tets_before", r.tets_before},
          {"tets_after", r.tets_after}};
}

json fields(const OptimizeWorstRegionsReport& r) {
  return {{"steps", r.steps},
          {"seeds", r.seeds},
          {"seeds_without_gain", r.seeds_without_gain},
          {"moved_nodes", r.moved_nodes},
          {"min_before", r.min_before},
          {"min_after", r.min_after},
          {"min_on_surface", r.min_on_surface},
          {"off_surface_steps", r.off_surface_steps},
          {"nodes_off_surface", r.nodes_off_surface},
          {"largest_offset", r.largest_offset},
          {"too_many_seeds", r.too_many_seeds},
          {"time_limit_reached", r.time_limit_reached}};
}

json fields(const HexCountReport& r) { return {{"hexes", r.hexes}}; }

json fields(const ProjectReport& r) {
  return {{"projected_nodes", r.projected_nodes},
          {"far_nodes", r.far_nodes},
          {"unconstrained_nodes", r.unconstrained_nodes},
          {"max_displacement", r.max_displacement},
          {"relaxed_moves", r.relaxed_moves}};
}

json fields(const UntangleReport& r) {
  return {{"inverted_before", r.inverted_before},
          {"inverted_after", r.inverted_after},
          {"min_scaled_jacobian", r.min_scaled_jacobian},
          {"avg_shape", r.avg_shape},
          {"min_shape", r.min_shape},
          {"worst_hexes", r.worst_hexes},
          {"sliding_boundary_nodes", r.sliding_boundary_nodes},
          {"rounds", r.rounds},
          {"seconds", r.seconds},
          {"time_limit_reached", r.time_limit_reached},
          {"stalled", r.stalled},
          {"undone", r.undone}};
}

json fields(const LocalSmoothReport& r) {
  return {{"min_scaled_jacobian_before", r.min_scaled_jacobian_before},
          {"min_scaled_jacobian_after", r.min_scaled_jacobian_after},
          {"avg_shape_before", r.avg_shape_before},
          {"avg_shape_after", r.avg_shape_after},
          {"moves", r.moves},
          {"sweeps", r.sweeps},
          {"time_limit_reached", r.time_limit_reached}};
}

json fields(const CreaseSlideStageReport& s) {
  json j = fields(s.smooth);
  j["faces_inside_before"] = s.faces_inside_before;
  j["faces_inside_after"] = s.faces_inside_after;
  j["undone"] = s.undone;
  return j;
}

json fields(const RepairWorstStageReport& s) {
  const RepairWorstHexesReport& r = s.repair;
  return {{"threshold", s.threshold},
          {"hexes", s.hexes},
          {"below_before", r.below_before},
          {"below_after", r.below_after},
          {"min_scaled_jacobian_before", r.min_scaled_jacobian_before},
          {"min_scaled_jacobian_after", r.min_scaled_jacobian_after},
          {"min_after_region_solve", r.min_after_region_solve},
          {"rounds", r.rounds},
          {"undone", r.undone},
          {"too_many", r.too_many},
          {"time_limit_reached", r.time_limit_reached}};
}

json fields(const RepairBoundaryFoldsReport& r) {
  return {{"faces_inside_before", r.faces_inside_before},
          {"faces_inside_after", r.faces_inside_after},
          {"regions", r.regions},
          {"moved_nodes", r.moved_nodes},
          {"region_min_scaled_jacobian_before", r.region_min_scaled_jacobian_before},
          {"region_min_scaled_jacobian_after", r.region_min_scaled_jacobian_after},
          {"undone", r.undone},
          {"time_limit_reached", r.time_limit_reached},
          {"phases_ended_without_gain", r.phases_ended_without_gain}};
}

json fields(const RepairFoldsStageReport& s) {
  json j = fields(s.repair);
  j["deferred"] = s.deferred;
  return j;
}

json fields(const MeasureReport& r) {
  return {{"inverted", r.inverted},
          {"scaled_jacobian_below_0_2", r.below_0_2},
          {"min_scaled_jacobian", r.min_scaled_jacobian},
          {"conforming", r.conforming},
          {"boundary_faces_inside", r.boundary_faces_inside}};
}

json fields(const MeshTryReport& r) {
  json j = {{"thickness_ratio", r.thickness_ratio}, {"eps", r.eps}, {"failed", r.failed}};
  if (r.failed) {
    j["failure"] = r.failure;
  } else {
    j["inverted"] = r.inverted;
    j["min_scaled_jacobian"] = r.min_scaled_jacobian;
    j["conforming"] = r.conforming;
    j["fold_repair_left"] = r.fold_repair_left;
  }
  return j;
}

json fields(const ThicknessRetryReport& r) {
  return {{"thin_wall_vertices", r.thin_wall_vertices},
          {"coarsening_vertices", r.coarsening_vertices},
          {"remeshed_input", r.remeshed_input},
          {"curvature_sized", fields(r.curvature)},
          {"thickness_sized", fields(r.thickness)},
          {"kept", r.kept_thickness ? "thickness" : "curvature"}};
}

json fields(const FinerRetryReport& r) {
  json tries = json::array();
  for (const MeshTryReport& t : r.tries) tries.push_back(fields(t));
  return {{"tries", tries}, {"kept", r.kept}};
}

}  // namespace

std::string describe(const StageReport& report) {
  return std::visit([](const auto& r) { return text(r); }, report);
}

std::string describe(const SurfaceRepairReport& r) {
  auto plural = [](size_t n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); };
  auto ids = [](const std::vector<int>& first, size_t count) {
    std::string list;
    for (size_t k = 0; k < first.size(); ++k) list += (k ? ", " : "") + std::to_string(first[k]);
    return list + (count > first.size() ? ", ..." : "");
  };
  std::ostringstream out;
  out.precision(10);
  const MergeCoincidentVerticesReport& m = r.merge;
  if (m.vertices_merged) {
    out << "  repaired: " << plural(m.vertices_merged, "coincident vertex", "coincident vertices")
        << " merged onto an earlier one (first: " << m.first_merged[0] << " onto " << m.first_kept[0] << " at ("
        << m.first_places[0].x() << ", " << m.first_places[0].y() << ", " << m.first_places[0].z() << "))\n";
  }
  const RemoveSmallIslandsReport& i = r.islands;
  if (i.islands_dropped) {
    out << "  repaired: " << plural(i.islands_dropped, "island", "islands") << " ("
        << plural(i.triangles_dropped, "triangle", "triangles") << ") dropped, below --min-island"
        << (i.dropped_by_volume ? " (" + std::to_string(i.dropped_by_volume) + " by volume)" : std::string())
        << " (first: triangle "
        << i.first_triangles[0] << " near (" << i.first_places[0].x() << ", " << i.first_places[0].y() << ", "
        << i.first_places[0].z() << "))\n";
  }
  const RemoveRedundantTrianglesReport& d = r.redundant;
  if (d.collapsed_removed + d.duplicates_removed) {
    out << "  repaired: ";
    if (d.collapsed_removed) out << plural(d.collapsed_removed, "collapsed triangle", "collapsed triangles");
    if (d.collapsed_removed && d.duplicates_removed) out << " and ";
    if (d.duplicates_removed) out << plural(d.duplicates_removed, "duplicate triangle", "duplicate triangles");
    out << " removed (first: " << ids(d.first_removed, d.collapsed_removed + d.duplicates_removed) << ")\n";
  }
  const RepairOrientationReport& o = r.orientation;
  if (o.triangles_turned)
    out << "  repaired: " << plural(o.triangles_turned, "triangle", "triangles") << " turned to match "
        << (o.triangles_turned == 1 ? "its" : "their") << " neighbours (first: " << ids(o.first_turned, o.triangles_turned)
        << ")\n";
  const FlipZeroAreaSliversReport& f = r.slivers;
  if (f.slivers_flipped)
    out << "  repaired: " << plural(f.slivers_flipped, "zero-area sliver", "zero-area slivers")
        << " flipped away with the neighbour across its longest edge, the shape unchanged (first: triangle "
        << f.first_flipped[0] << " at (" << f.first_places[0].x() << ", " << f.first_places[0].y() << ", "
        << f.first_places[0].z() << "))\n";
  return out.str();
}

std::string describe(const ThicknessRetryReport& r) {
  if (!r.ran) return "";
  const char* counted = r.remeshed_input ? " vertices of the remeshed input" : " input vertices";
  std::ostringstream out;
  out << r.thin_wall_vertices << " of " << r.coarsening_vertices << counted
      << " lie on walls thinner than their curvature size, so the input was meshed twice:\n"
      << "  sized by curvature (" << text(r.curvature) << ") and by wall thickness, --thickness-ratio 1 ("
      << text(r.thickness) << ");\n  kept the " << (r.kept_thickness ? "thickness" : "curvature") << "-sized mesh";
  return out.str();
}

std::string describe(const FinerRetryReport& r) {
  if (!r.ran || r.tries.empty()) return "";
  std::ostringstream out;
  // A sound mesh ends the tries, so a kept one that is sound before the last try is one
  // whose fold repair was left and made it sound afterwards (its report is the repaired mesh's).
  const MeshTryReport& kept = r.tries[r.kept];
  const bool sound_once_repaired = r.kept + 1 < r.tries.size() && kept.inverted == 0 && kept.conforming;
  out << "the mesh at eps " << std::setprecision(3) << r.tries.front().eps;
  if (sound_once_repaired && r.kept == 0)
    out << " had boundary faces folded into it (fold repair left for a finer try)";
  else
    out << " was unsound (" << text(r.tries.front()) << ")";
  out << ", so the input was meshed again at finer eps:";
  for (size_t k = 1; k < r.tries.size(); ++k) out << "\n  eps " << r.tries[k].eps << " (" << text(r.tries[k]) << ")";
  out << "\n  kept the mesh at eps " << kept.eps;
  if (sound_once_repaired) out << ", sound once its folds were repaired (" << text(kept) << ")";
  return out.str();
}

std::string summary_table(const PipelineResult& r, const PipelineOptions& o) {
  std::ostringstream out;
  out << "om_dthex " << DTHEX_VERSION << ": " << r.input_path;
  if (o.thex_only)
    out << " (THex only)";
  else
    out << " (eps " << r.eps << ", dice " << r.dice << (o.project ? "" : ", not projected") << ")";
  out << "\n";
  out << describe(r.repairs);
  out << "  stage                  seconds  result\n";
  for (const auto& s : r.stages) {
    // The detail is appended, not formatted into the buffer: a long one lost its end and
    // the line break with it.
    char line[96];
    std::snprintf(line, sizeof line, "  %-22s %7.3f  ", s.name.c_str(), s.seconds);
    out << line << describe(s.report) << "\n";
  }
  char total[96];
  std::snprintf(total, sizeof total, "  %-22s %7.3f\n", "total", r.total_seconds);
  out << total << "\n";
  out << "  quality (Verdict)     elements      avg      std      min      max\n";
  out << quality_row("input triangles", r.input_summary.triangles, r.input_summary.shape);
  if (!o.thex_only) out << quality_row("coarse triangles", r.coarse_summary.triangles, r.coarse_summary.shape);
  out << quality_row("tets", r.tets, r.tet_shape);
  out << quality_row("hex shape", r.hexes.hexes.size(), r.quality.shape_stats);
  out << quality_row("hex scaled Jac.", r.hexes.hexes.size(), r.quality.scaled_jacobian_stats);
  out << "\n";
  const double diag = r.input_summary.bbox_diagonal > 0 ? r.input_summary.bbox_diagonal : 1.0;
  char tail[512];
  std::snprintf(tail, sizeof tail,
                "  nodes %zu, hexes %zu, inverted %zu, scaled Jacobian < 0.2: %zu, conforming: %s\n"
                "  distance to input: Hausdorff %.4g (%.3f%% of the bbox diagonal), mean %.4g\n"
                "  volume: hexes %.6g, input %.6g (%+.3f%%)\n",
                r.hexes.nodes.size(), r.hexes.hexes.size(), r.quality.inverted, r.quality.below_0_2,
                r.conforming ? "yes" : "NO", r.hausdorff, 100.0 * r.hausdorff / diag, r.mean_distance, r.hex_volume,
                r.input_summary.volume,
                r.input_summary.volume != 0 ? 100.0 * (r.hex_volume - r.input_summary.volume) / r.input_summary.volume
                                            : 0.0);
  out << tail;
  std::snprintf(tail, sizeof tail, "  at the 2x2x2 Gauss points: min scaled Jacobian %.4f, det J <= 0 in %zu hexes\n",
                r.quality.gauss_scaled_jacobian_min, r.quality.gauss_inverted);
  out << tail;
  if (r.quality.inverted > 0) {
    out << "  WARNING: " << r.quality.inverted << " inverted hexes remain; worst:";
    for (size_t i = 0; i < r.worst_hexes.size() && i < 5; ++i)
      out << " " << r.worst_hexes[i] << " (SJ " << r.quality.scaled_jacobian[r.worst_hexes[i]] << ")";
    out << "\n";
  }
  for (size_t i = 0; i < r.regions.size(); ++i)
    if (!r.regions[i].conforming)
      out << "  WARNING: material region " << i + 1 << " alone is not conforming (" << r.regions[i].boundary_faces_inside
          << " of its boundary faces, interfaces included, lie inside it)\n";
  if (r.boundary_faces_inside > 0) {
    char where[160];
    std::snprintf(where, sizeof where, "(%.6g, %.6g, %.6g)", r.first_inside_point.x(), r.first_inside_point.y(),
                  r.first_inside_point.z());
    out << "  WARNING: " << r.boundary_faces_inside
        << " boundary faces lie inside the mesh (its boundary folds into its own volume), the first near " << where << "\n";
  }
  // Thin walls sized by curvature alone are the commonest cause of poor hexes left over.
  const bool poor = r.quality.inverted > 0 || r.quality.below_0_2 > 0;
  if (r.finer_retry.ran) out << "  finer eps: " << describe(r.finer_retry) << "\n";
  if (r.thickness_retry.ran)
    out << "  thin walls: " << describe(r.thickness_retry) << "\n";
  else if (const auto* predicted = r.stage_report<ThinWallPredictionReport>("predict thin walls");
           predicted && predicted->thickness_ratio > 0)
    out << "  thin walls: " << text(*predicted) << "\n";
  else if (poor && !o.thex_only && o.thickness_ratio <= 0 && r.thickness_ratio_used <= 0 &&
           r.thin_wall_vertices * 20 >= r.coarsening_input().points.size())
    out << "  hint: " << r.thin_wall_vertices << " of " << r.coarsening_input().points.size()
        << " input vertices lie on walls thinner than their coarse size; --thickness-ratio 1 sizes such walls by their\n"
           "  thickness (more nodes, better hexes: the shared pelvis went from min scaled Jacobian 0.04 to 0.21)\n";
  return out.str();
}

std::string report_json(const PipelineResult& r, const PipelineOptions& o, const PipelineResult* thex_baseline) {
  nlohmann::json j;
  j["tool"] = "om_dthex";
  j["version"] = DTHEX_VERSION;
  j["input"] = {{"path", r.input_path}, {"surface", surface_json(r.input_summary)}};
  // What the safe repairs did (PipelineOptions::repair): counts, and the first ids.
  j["input"]["repairs"] = {{"ran", r.repairs.ran},
                           {"vertices_merged", r.repairs.merge.vertices_merged},
                           {"first_merged_vertices", r.repairs.merge.first_merged},
                           {"islands_dropped", r.repairs.islands.islands_dropped},
                           {"island_triangles_dropped", r.repairs.islands.triangles_dropped},
                           {"first_island_triangles", r.repairs.islands.first_triangles},
                           {"collapsed_triangles_removed", r.repairs.redundant.collapsed_removed},
                           {"duplicate_triangles_removed", r.repairs.redundant.duplicates_removed},
                           {"first_removed_triangles", r.repairs.redundant.first_removed},
                           {"redundant_triangles_left", r.repairs.redundant.left_in_place},
                           {"triangles_turned", r.repairs.orientation.triangles_turned},
                           {"components_with_turned_triangles", r.repairs.orientation.components_repaired},
                           {"first_turned_triangles", r.repairs.orientation.first_turned},
                           {"islands_dropped_by_volume", r.repairs.islands.dropped_by_volume},
                           {"slivers_flipped", r.repairs.slivers.slivers_flipped},
                           {"first_flipped_slivers", r.repairs.slivers.first_flipped}};
  // The surface the coarsening started from, when the input was remeshed first.
  if (!r.remeshed.triangles.empty())
    j["input"]["remeshed"] = {{"vertices", r.remeshed.points.size()}, {"triangles", r.remeshed.triangles.size()}};
  j["options"] = {{"repair", o.repair == PipelineOptions::Repair::none ? "none" : "safe"},
                  {"min_island", o.min_island_triangles},
                  {"min_island_volume_fraction", o.min_island_volume_fraction},
                  {"eps", r.eps},
                  {"target_nodes", o.target_nodes},
                  {"dice", r.dice},
                  {"h_min", o.h_min},
                  {"h_max", o.h_max},
                  {"max_edge_ratio", o.max_edge_ratio},
                  {"thickness_ratio", o.thickness_ratio},
                  {"thickness_retry", o.thickness_retry},
                  {"finer_retry", o.finer_retry},
                  {"predict_thin_walls", o.predict_thin_walls},
                  {"thex_only", o.thex_only},
                  {"project", o.project},
                  {"strict", o.strict},
                  {"knife_edge_slide", o.knife_edge_slide},
                  {"boundary_slack", o.boundary_slack},
                  {"min_dihedral", o.min_dihedral_deg},
                  {"nested", o.nested == PipelineOptions::Nested::material ? "material" : "cavity"},
                  {"remesh", o.remesh == PipelineOptions::Remesh::always  ? "on"
                             : o.remesh == PipelineOptions::Remesh::never ? "off"
                                                                          : "auto"},
                  {"tetgen", tetgen_switches_for(o)},
                  {"time_limit_seconds", o.time_limit_seconds}};
  if (!o.thex_only) {
    j["coarse"] = surface_json(r.coarse_summary);
    j["coarse"]["thin_wall_input_vertices"] = r.thin_wall_vertices;
    j["coarse"]["thickness_ratio_used"] = r.thickness_ratio_used;
    // What the automatic retry did (null when it did not run).
    j["coarse"]["thickness_retry"] = r.thickness_retry.ran ? fields(r.thickness_retry) : nlohmann::json();
    // What the retry at a finer eps did (null when it did not run).
    j["coarse"]["finer_retry"] = r.finer_retry.ran ? fields(r.finer_retry) : nlohmann::json();
  }
  j["tets"] = {{"count", r.tets}, {"shape", stats_json(r.tet_shape)}};
  j["hex"] = {{"nodes", r.hexes.nodes.size()},
              {"hexes", r.hexes.hexes.size()},
              {"shape", stats_json(r.quality.shape_stats)},
              {"scaled_jacobian", stats_json(r.quality.scaled_jacobian_stats)},
              {"inverted", r.quality.inverted},
              {"inverted_before_untangle", r.inverted_before_untangle},
              {"scaled_jacobian_below_0_2", r.quality.below_0_2},
              {"gauss_points", {{"scaled_jacobian_min", r.quality.gauss_scaled_jacobian_min},
                                {"inverted", r.quality.gauss_inverted}}},
              {"conforming", r.conforming},
              {"boundary_faces_inside", r.boundary_faces_inside},
              {"volume", r.hex_volume},
              {"worst_hexes", r.worst_hexes},
              {"shape_histogram", {{"lo", 0.0}, {"hi", 1.0}, {"counts", histogram(r.quality.shape, 20, 0.0, 1.0)}}},
              {"scaled_jacobian_histogram",
               {{"lo", -1.0}, {"hi", 1.0}, {"counts", histogram(r.quality.scaled_jacobian, 40, -1.0, 1.0)}}}};
  if (!r.regions.empty()) {  // --nested material: each region judged alone
    nlohmann::json regions = nlohmann::json::array();
    for (const RegionMeasure& region : r.regions)
      regions.push_back({{"hexes", region.hexes},
                         {"inverted", region.inverted},
                         {"scaled_jacobian_min", region.min_scaled_jacobian},
                         {"conforming", region.conforming},
                         {"boundary_faces_inside", region.boundary_faces_inside}});
    j["hex"]["regions"] = regions;
  }
  j["distance"] = {{"hausdorff", r.hausdorff},
                   {"hausdorff_relative", r.input_summary.bbox_diagonal > 0 ? r.hausdorff / r.input_summary.bbox_diagonal : 0.0},
                   {"mean", r.mean_distance}};
  nlohmann::json stages = nlohmann::json::array();
  for (const auto& s : r.stages)
    stages.push_back({{"name", s.name},
                      {"seconds", s.seconds},
                      {"report", std::visit([](const auto& report) { return fields(report); }, s.report)},
                      {"summary", describe(s.report)}});
  j["stages"] = stages;
  j["total_seconds"] = r.total_seconds;
  if (thex_baseline) {
    PipelineOptions thex_options = o;
    thex_options.thex_only = true;
    j["thex_baseline"] = nlohmann::json::parse(report_json(*thex_baseline, thex_options));
  }
  return j.dump(2) + "\n";
}

}  // namespace dthex
