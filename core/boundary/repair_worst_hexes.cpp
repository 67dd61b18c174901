// SPDX-License-Identifier: MIT
#include <dthex/boundary/repair_worst_hexes.h>

#include <dthex/boundary/local_smooth.h>
#include <dthex/boundary/untangle.h>
#include <dthex/hexes/conformity.h>
#include <dthex/mesh/quality.h>
#include <dthex/surface/features.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace dthex {
RepairWorstHexesReport repair_worst_hexes(HexMesh& mesh, const TriangleBvh& surface,
                                          const RepairWorstHexesOptions& options) {
  RepairWorstHexesReport report;
  const ScaledJacobianTally before = tally_scaled_jacobians(mesh, options.threshold);
  report.below_before = report.below_after = before.below;
  report.min_scaled_jacobian_before = report.min_scaled_jacobian_after = report.min_after_region_solve = before.min;
  if (before.below == 0) return report;
  if (before.below > options.always_repaired &&
      double(before.below) > options.max_below_fraction * double(mesh.hexes.size())) {
    report.too_many = true;
    return report;
  }

  const auto start = std::chrono::steady_clock::now();
  // The boundary nodes, found once for every round's region solve and smoothing, and the
  // feature nodes.
  NodeConstraints constraints;
  if (options.constraints) constraints.on_feature = options.constraints->on_feature;
  constraints.on_boundary = boundary_nodes(mesh, options.constraints ? &options.constraints->on_boundary : nullptr);
  UntangleOptions region;
  region.constraints = &constraints;
  region.target_scaled_jacobian = options.threshold;
  region.region_rings = options.region_rings;
  region.max_boundary_phases = options.sliding_passes;
  region.slide_boundary = options.sliding_passes > 0;
  region.smoothing_iterations = 0;  // no shape pass over the whole mesh: only the region moves
  region.time_limit_seconds = options.time_limit_seconds;
  // The slides hold the creases: a node on a convex crease line or a corner of the surface
  // stays, and on a concave line a node of the coarse surface's feature lines (another one
  // got there by accident of projection, as in the local smoother). Free, the nodes of a
  // sharp knife edge slide down its faces and cut it off; made to slide along the crease
  // line instead, they end with a lower minimum.
  const std::vector<Vec3> normals = unit_triangle_normals(surface.points(), surface.triangles());
  const double min_cos = std::cos(options.max_normal_turn_deg * M_PI / 180.0);
  const double radius = 1e-7 * surface.bounds().diagonal().norm();
  // Knife edges (see LocalSmoothOptions::knife_edge_slide): their lines' nodes slide, and a
  // node that starts a round within the zone lands in it.
  const bool knives = options.knife_edge_slide > 0 && has_knife_edge(surface.triangles(), normals);
  const double knife_zone = options.knife_edge_slide * surface.bounds().diagonal().norm();
  const double knife_cos = -std::cos(kKnifeEdgeAngleDeg * M_PI / 180.0);
  if (knives)
    region.may_land = [&](size_t, const Vec3& from, const Vec3& to) {
      return !near_knife_edge(surface, normals, from, knife_zone) || near_knife_edge(surface, normals, to, knife_zone);
    };
  region.held = [&](size_t v, const Vec3& at) {
    const TriangleBvh::ClosestPoint cp = surface.closest_point(at);
    if (cp.triangle < 0 || normals[size_t(cp.triangle)].squaredNorm() == 0) return true;
    Vec3 line;
    double faces_cos = 1;
    switch (crease_at(surface, normals, at, normals[size_t(cp.triangle)], radius, min_cos, line, &faces_cos)) {
      case CreaseKind::none:
        return false;
      case CreaseKind::concave_line:  // projection may have put it there by mistake
        return constraints.is_feature(v);
      case CreaseKind::convex_line:
        if (knives && faces_cos < knife_cos) return false;
        break;
      case CreaseKind::corner:
        break;
    }
    return true;
  };
  LocalSmoothOptions raise;
  raise.constraints = &constraints;
  raise.target_scaled_jacobian = options.target_scaled_jacobian;
  raise.shape_sweeps = options.shape_sweeps;
  raise.knife_edge_slide = options.knife_edge_slide;
  // Not bounded by edge length here: these hexes are below the floor, where a shorter edge is
  // a fair price for a sound corner (a thin shell's rim hexes: 0.018 with the bound lifted,
  // nothing gained with it).
  raise.min_edge_ratio = 0;
  auto seconds_left = [&] {
    return std::max(0.0, options.time_limit_seconds -
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  };
  // Round after round while each leaves fewer hexes below the threshold or a higher minimum,
  // and neither a lower minimum nor more inverted hexes; the first that does not is undone
  // and ends the repair.
  ScaledJacobianTally now = before;
  for (int round = 0; round < options.rounds && now.below > 0; ++round) {
    const std::vector<Vec3> kept = mesh.nodes;
    region.time_limit_seconds = seconds_left();
    const UntangleReport solved = untangle_and_smooth(mesh, surface, region);
    if (round == 0) report.min_after_region_solve = solved.min_scaled_jacobian;
    raise.time_limit_seconds = seconds_left();
    const LocalSmoothReport raised = smooth_worst_hexes(mesh, surface, raise);
    report.time_limit_reached = solved.time_limit_reached || raised.time_limit_reached;
    const ScaledJacobianTally after = tally_scaled_jacobians(mesh, options.threshold);
    const bool gained = after.below < now.below || after.min > now.min;
    if (!gained || after.inverted > now.inverted || after.min < now.min) {
      mesh.nodes = kept;
      if (round == 0) report.undone = true;
      break;
    }
    now = after;
    ++report.rounds;
    if (report.time_limit_reached) break;
  }
  report.below_after = now.below;
  report.min_scaled_jacobian_after = now.min;
  return report;
}

}  // namespace dthex
