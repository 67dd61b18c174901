// SPDX-License-Identifier: MIT
#include <dthex/boundary/optimize_worst_regions.h>

#include <dthex/hexes/conformity.h>
#include <dthex/mesh/hex_topology.h>
#include <dthex/mesh/incidence.h>
#include <dthex/mesh/quality.h>
#include <dthex/numerics/lbfgs.h>
#include <dthex/surface/features.h>
#include <dthex/numerics/tangent_basis.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace dthex {
namespace {

using Clock = std::chrono::steady_clock;

// The scaled Jacobian s = det(a, b, c) / (|a| |b| |c|) of a frame and its gradient with respect
// to a, b and c (0 where an axis vanishes).
double frame_scaled_jacobian(const Vec3& a, const Vec3& b, const Vec3& c, Vec3& da, Vec3& db, Vec3& dc) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double lengths = la * lb * lc;
  if (!(lengths > 0)) {
    da = db = dc = Vec3::Zero();
    return 0;
  }
  const Vec3 bc = b.cross(c);
  const double s = a.dot(bc) / lengths;
  da = bc / lengths - s * a / (la * la);
  db = c.cross(a) / lengths - s * b / (lb * lb);
  dc = a.cross(b) / lengths - s * c / (lc * lc);
  return s;
}

class WorstRegionOptimizer {
 public:
  WorstRegionOptimizer(HexMesh& mesh, const OptimizeWorstRegionsOptions& options) : mesh_(mesh), options_(options) {
    node_hexes_ = NodeCellIncidence(mesh.nodes.size(), mesh.hexes);
    on_boundary_ = boundary_nodes(mesh, options.constraints ? &options.constraints->on_boundary : nullptr);
    hex_mark_.assign(mesh.hexes.size(), 0);
    node_mark_.assign(mesh.nodes.size(), 0);
    if (options.surface) {
      const TriangleBvh& surface = *options.surface;
      surface_normals_ = unit_triangle_normals(surface.points(), surface.triangles());
      min_normal_cos_ = std::cos(options.max_normal_turn_deg * M_PI / 180.0);
      flat_cos_ = std::cos(options.flat_turn_deg * M_PI / 180.0);
      if (options.knife_edge_zone > 0 && has_knife_edge(surface.triangles(), surface_normals_))
        knife_zone_ = options.knife_edge_zone * surface.bounds().diagonal().norm();
    }
    deadline_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(options.time_limit_seconds));
  }

  OptimizeWorstRegionsReport run() {
    OptimizeWorstRegionsReport report;
    std::vector<double> sj(mesh_.hexes.size());
    report.min_before = report.min_after = measure(sj);
    continuation(report, sj);
    report.min_on_surface = report.min_after;
    // The boundary nodes where the input curves allowed a little off it: only where the
    // continuation on it ended for want of a gain (not of steps, seeds or time), and from
    // there, so the minimum cannot end lower than without.
    if (options_.surface && options_.surface_slack > 0 && report.seeds_without_gain > 0 &&
        !report.time_limit_reached) {
      off_surface_phase_ = true;
      report.seeds_without_gain = 0;
      const int on_surface_steps = report.steps;
      continuation(report, sj);
      report.off_surface_steps = report.steps - on_surface_steps;
      for (size_t v : lifted_) {
        const double offset = std::sqrt(options_.surface->closest_point(mesh_.nodes[v]).distance_sq);
        if (!(offset > 1e-9 * node_scale(v))) continue;
        ++report.nodes_off_surface;
        report.largest_offset = std::max(report.largest_offset, offset);
      }
    }
    return report;
  }

 private:
  // What a region's solve moves: its interior nodes; with them its boundary nodes off creases,
  // sliding on the input; or those also along their normal, within the slack of the input.
  enum class Move { interior, on_surface, off_surface };

  // The smallest scaled Jacobian of the mesh, each hex's in sj.
  double measure(std::vector<double>& sj) const {
#pragma omp parallel for schedule(static) if (sj.size() > 50000)
    for (long h = 0; h < long(sj.size()); ++h) sj[size_t(h)] = hex_scaled_jacobian(hex_corners(mesh_, size_t(h)));
    return *std::min_element(sj.begin(), sj.end());
  }

  // Steps of the continuation (OptimizeWorstRegionsOptions::steps and steps_while_poor) from report.min_after;
  // sj holds each hex's scaled Jacobian, and is kept so.
  void continuation(OptimizeWorstRegionsReport& report, std::vector<double>& sj) {
    auto more_steps = [&](int step) {
      return step < options_.steps || (report.min_after < options_.poor_below && step < options_.steps_while_poor);
    };
    for (int step = 0; more_steps(step) && report.min_after < options_.target; ++step) {
      if (Clock::now() > deadline_) {
        report.time_limit_reached = true;
        break;
      }
      const double below = std::min(options_.target, report.min_after + options_.margin);
      std::vector<size_t> seeds;
      for (size_t h = 0; h < sj.size(); ++h)
        if (sj[h] < below) seeds.push_back(h);
      if (seeds.size() > options_.max_seeds * size_t(std::max(options_.max_batches, 1))) {
        report.too_many_seeds = true;
        break;
      }
      // The seeds in batches of max_seeds, worst first, each batch's region solved on its own.
      std::stable_sort(seeds.begin(), seeds.end(), [&](size_t a, size_t b) { return sj[a] < sj[b]; });
      size_t moved = 0;
      for (size_t first = 0; first < seeds.size(); first += options_.max_seeds) {
        const size_t last = std::min(seeds.size(), first + options_.max_seeds);
        const std::vector<size_t> batch(seeds.begin() + long(first), seeds.begin() + long(last));
        // The interior nodes first; where they gain nothing (the worst corners held by the
        // boundary), the boundary nodes sliding on the input with them, or in the second
        // phase allowed off it (a slide on it would put back the nodes already off).
        bool gained = false;
        for (const Move move : {Move::interior, Move::on_surface, Move::off_surface}) {
          if (move != Move::interior && !options_.surface) break;
          if ((move == Move::on_surface && off_surface_phase_) || (move == Move::off_surface && !off_surface_phase_))
            continue;
          select(batch, move);
          if (free_.empty()) continue;
          // A region that gains nothing at the usual sharpness may at the sharper one, where
          // the frames just above its minimum, many of them, outweighed the few worst.
          sharpness_ = options_.sharpness;
          gained = solve();
          if (!gained && options_.fallback_sharpness > options_.sharpness) {
            sharpness_ = options_.fallback_sharpness;
            gained = solve();
          }
          if (gained) {
            moved += free_.size();
            if (move == Move::off_surface)
              for (size_t i = 0; i < free_.size(); ++i)
                if (lifting_[i]) lifted_.insert(free_[i]);
            break;
          }
        }
        if (!gained && first == 0) break;  // the worst hex is in the first batch: it stays the minimum
      }
      const double min_before_step = report.min_after;
      report.min_after = measure(sj);
      if (!(report.min_after > min_before_step)) {  // the batch around the worst gained nothing
        report.seeds_without_gain = seeds.size();
        report.moved_nodes += moved;
        break;
      }
      report.seeds += seeds.size();
      report.moved_nodes += moved;
      ++report.steps;
    }
  }

  // Rounds of L-BFGS on the selected region, each kept only when it raises the region's
  // minimum; true if one was kept.
  bool solve() {
    bool kept_any = false;
    for (int round = 0; round < options_.rounds && Clock::now() <= deadline_; ++round) {
      Eigen::VectorXd z = start_variables();
      const double before = region_min();
      const std::vector<Vec3> kept = positions();
      floor_ = before;
      LbfgsOptions lbfgs;
      lbfgs.max_iterations = options_.iterations;
      lbfgs.deadline = deadline_;
      minimize_lbfgs(z, [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) { return energy(x, g); }, lbfgs);
      place(z);
      put_back_on_surface();
      // No gain, or an edge drawn below half its floor: put the round's start back.
      if (!(region_min() > before + 1e-6) ||
          !(shortest_edge_fraction() >= 0.5 * options_.min_edge_fraction)) {
        restore(kept);
        break;
      }
      kept_any = true;
    }
    return kept_any;
  }

  // The variables at the current positions: an interior node's coordinates, a sliding node's
  // two tangent offsets (0) and, lifting, its normal offset (0), each in units of the node's
  // scale. Sets the sliding nodes' origins and, in the off-surface phase, their distances to
  // the input.
  Eigen::VectorXd start_variables() {
    Eigen::VectorXd z(static_cast<Eigen::Index>(variable_count_));
    for (size_t i = 0; i < free_.size(); ++i) {
      const Vec3& x = mesh_.nodes[free_[i]];
      const Eigen::Index o = Eigen::Index(offset_[i]);
      if (!sliding_[i]) {
        for (int c = 0; c < 3; ++c) z[o + c] = x[c] / scale_[i];
        continue;
      }
      origin_[i] = x;
      z[o] = z[o + 1] = 0;
      if (lifting_[i]) z[o + 2] = 0;
      if (!off_surface_phase_) continue;
      const Vec3 off = x - options_.surface->closest_point(x).point;
      origin_offset_[i] = off.norm();
      origin_lift_[i] = off.dot(normal_[i]) / scale_[i];
    }
    return z;
  }

  // Each sliding node onto the input's closest point, or a lifting one within the slack of it;
  // one whose closest point is further than it moved plus where it started (on another sheet)
  // or on a part of the surface facing elsewhere (across a crease) goes back to where its
  // slide started.
  void put_back_on_surface() {
    if (!options_.surface) return;
    for (size_t i = 0; i < free_.size(); ++i) {
      if (!sliding_[i]) continue;
      Vec3& x = mesh_.nodes[free_[i]];
      const TriangleBvh::ClosestPoint cp = options_.surface->closest_point(x);
      const double reach = (x - origin_[i]).norm() + origin_offset_[i] + 1e-12 * scale_[i];
      const bool lands = cp.triangle >= 0 && std::sqrt(cp.distance_sq) <= reach &&
                         surface_normals_[size_t(cp.triangle)].dot(normal_[i]) >= min_normal_cos_;
      if (!lands) {
        x = origin_[i];
        continue;
      }
      const Vec3 offset = x - cp.point;
      const double limit = lifting_[i] ? lift_limit_[i] * scale_[i] : 0.0;
      const double length = offset.norm();
      x = length <= limit ? x : Vec3(cp.point + (limit / length) * offset);
    }
  }

  // A boundary node of the region that may slide on the input: off every crease and corner
  // (a slide would round them off) and off a knife edge's zone; with its surface normal.
  bool may_slide(size_t v, double scale, Vec3& normal) const {
    if (!options_.surface) return false;
    const Vec3& x = mesh_.nodes[v];
    const TriangleBvh::ClosestPoint cp = options_.surface->closest_point(x);
    if (cp.triangle < 0) return false;
    normal = surface_normals_[size_t(cp.triangle)];
    if (normal.squaredNorm() == 0) return false;
    if (on_surface_crease(*options_.surface, surface_normals_, x, normal, 1e-6 * scale, min_normal_cos_, false))
      return false;
    return !(knife_zone_ > 0 && near_knife_edge(*options_.surface, surface_normals_, x, knife_zone_));
  }

  // The region: hexes within region_rings rings of the seeds; its free nodes: nodes all of
  // whose hexes are in it, interior or (moving more than the interior) sliding on the
  // boundary, lifting too for Move::off_surface; the active hexes: those with a free node.
  void select(const std::vector<size_t>& seeds, Move move) {
    const bool slide = move != Move::interior;
    // The region's hexes, ring by ring; marks on the mesh's hexes and nodes, cleared after, so
    // a selection costs what its region holds, not what the mesh does.
    std::vector<size_t> region = seeds, frontier = seeds, seen_nodes;
    for (size_t h : seeds) hex_mark_[h] = 1;
    for (int ring = 0; ring < options_.region_rings; ++ring) {
      std::vector<size_t> next;
      for (size_t h : frontier)
        for (int v : mesh_.hexes[h]) {
          if (node_mark_[size_t(v)]) continue;
          node_mark_[size_t(v)] = 1, seen_nodes.push_back(size_t(v));
          for (int g : node_hexes_[size_t(v)])
            if (!hex_mark_[size_t(g)]) hex_mark_[size_t(g)] = 1, region.push_back(size_t(g)), next.push_back(size_t(g));
        }
      frontier.swap(next);
    }
    // The nodes of the region's hexes, in index order.
    std::vector<size_t> candidates;
    for (size_t h : region)
      for (int v : mesh_.hexes[h])
        if (node_mark_[size_t(v)] != 2) node_mark_[size_t(v)] = 2, candidates.push_back(size_t(v));
    std::sort(candidates.begin(), candidates.end());
    // Free: interior nodes all of whose hexes are in the region, and boundary ones that may slide.
    std::unordered_map<size_t, Vec3> slide_normal;
    std::unordered_set<size_t> lifts;  // sliding nodes that may leave the input: on a curved part of it
    free_.clear();
    active_.clear();
    for (size_t v : candidates) {
      bool inside = true;
      for (int g : node_hexes_[v]) inside = inside && hex_mark_[size_t(g)];
      if (!inside) continue;
      if (!on_boundary_[v]) {
        free_.push_back(v);
        continue;
      }
      if (!slide) continue;
      Vec3 normal;
      const double scale = node_scale(v);
      if (!may_slide(v, scale, normal)) continue;
      free_.push_back(v), slide_normal[v] = normal;
      if (move == Move::off_surface && !on_interface(v) &&
          surface_curves_near(*options_.surface, surface_normals_, mesh_.nodes[v], normal, scale, flat_cos_,
                              min_normal_cos_))
        lifts.insert(v);
    }
    for (size_t h : region) hex_mark_[h] = 0;
    for (size_t v : seen_nodes) node_mark_[v] = 0;
    for (size_t v : candidates) node_mark_[v] = 0;
    // The active hexes, in index order, and each one's slot.
    for (size_t v : free_)
      for (int g : node_hexes_[v])
        if (!hex_mark_[size_t(g)]) hex_mark_[size_t(g)] = 1, active_.push_back(size_t(g));
    std::sort(active_.begin(), active_.end());
    std::unordered_map<size_t, int> slot_of;
    for (size_t a = 0; a < active_.size(); ++a) hex_mark_[active_[a]] = 0, slot_of[active_[a]] = int(a);
    slots_of_.assign(free_.size(), {});
    for (size_t i = 0; i < free_.size(); ++i)
      for (int g : node_hexes_[free_[i]]) {
        const auto& hex = mesh_.hexes[size_t(g)];
        const int corner = int(std::find(hex.begin(), hex.end(), int(free_[i])) - hex.begin());
        slots_of_[i].push_back({slot_of.at(size_t(g)), corner});
      }
    // The active hexes' edge lengths when each first became active: the floor's reference.
    start_lengths_.resize(active_.size());
    for (size_t a = 0; a < active_.size(); ++a) {
      auto [it, added] = first_lengths_.try_emplace(active_[a]);
      if (added) it->second = edge_lengths(active_[a]);
      start_lengths_[a] = it->second;
    }
    // Each node's variables in units of its mean hex edge, so one step means the same anywhere:
    // an interior node's three coordinates, a sliding node's two offsets in its tangent plane.
    scale_.assign(free_.size(), 0);
    sliding_.assign(free_.size(), 0);
    lifting_.assign(free_.size(), 0);
    origin_offset_.assign(free_.size(), 0);
    origin_lift_.assign(free_.size(), 0);
    lift_limit_.assign(free_.size(), 0);
    normal_.assign(free_.size(), Vec3::Zero());
    tangent_.assign(free_.size(), {Vec3::Zero(), Vec3::Zero()});
    origin_.assign(free_.size(), Vec3::Zero());
    offset_.assign(free_.size(), 0);
    variable_count_ = 0;
    for (size_t i = 0; i < free_.size(); ++i) {
      scale_[i] = node_scale(free_[i]);
      offset_[i] = variable_count_;
      const auto found = slide_normal.find(free_[i]);
      if (found == slide_normal.end()) {
        variable_count_ += 3;
        continue;
      }
      const Vec3& normal = found->second;
      sliding_[i] = 1;
      lifting_[i] = lifts.count(free_[i]) > 0;
      if (lifting_[i])
        lift_limit_[i] = options_.max_surface_offset > 0 ? std::min(options_.surface_slack, options_.max_surface_offset / scale_[i])
                                                         : options_.surface_slack;
      normal_[i] = normal;
      tangent_[i] = tangent_basis(normal);
      variable_count_ += lifting_[i] ? 3 : 2;
    }
  }

  // Whether node v has hexes of two materials (HexMesh::region): on an interface, which stays
  // on the input where the materials meet.
  bool on_interface(size_t v) const {
    if (mesh_.region.empty()) return false;
    for (int g : node_hexes_[v])
      if (mesh_.region[size_t(g)] != mesh_.region[size_t(node_hexes_[v][0])]) return true;
    return false;
  }

  // The mean distance from node v to the nodes of its hexes (1 for a node without hexes).
  double node_scale(size_t v) const {
    double sum = 0;
    int count = 0;
    for (int g : node_hexes_[v])
      for (int u : mesh_.hexes[size_t(g)]) sum += (mesh_.nodes[size_t(u)] - mesh_.nodes[v]).norm(), ++count;
    return count ? std::max(sum / count, 1e-300) : 1.0;
  }

  std::vector<Vec3> positions() const {
    std::vector<Vec3> out;
    for (size_t v : free_) out.push_back(mesh_.nodes[v]);
    return out;
  }
  void restore(const std::vector<Vec3>& kept) {
    for (size_t i = 0; i < free_.size(); ++i) mesh_.nodes[free_[i]] = kept[i];
  }
  void place(const Eigen::VectorXd& z) {
    for (size_t i = 0; i < free_.size(); ++i) {
      const Eigen::Index o = Eigen::Index(offset_[i]);
      if (!sliding_[i]) {
        mesh_.nodes[free_[i]] = scale_[i] * Vec3(z[o], z[o + 1], z[o + 2]);
        continue;
      }
      Vec3 step = z[o] * tangent_[i][0] + z[o + 1] * tangent_[i][1];
      if (lifting_[i]) step += z[o + 2] * normal_[i];
      mesh_.nodes[free_[i]] = origin_[i] + scale_[i] * step;
    }
  }
  double region_min() const {
    double lowest = std::numeric_limits<double>::infinity();
    for (size_t h : active_) lowest = std::min(lowest, hex_scaled_jacobian(hex_corners(mesh_, h)));
    return lowest;
  }

  std::array<double, 12> edge_lengths(size_t h) const {
    std::array<double, 12> lengths;
    const auto& hex = mesh_.hexes[h];
    for (size_t e = 0; e < 12; ++e)
      lengths[e] = (mesh_.nodes[size_t(hex[size_t(kHexEdges[e][0])])] - mesh_.nodes[size_t(hex[size_t(kHexEdges[e][1])])]).norm();
    return lengths;
  }
  // The smallest ratio of an active hex's edge to its length when the stage first moved it.
  double shortest_edge_fraction() const {
    double lowest = std::numeric_limits<double>::infinity();
    for (size_t a = 0; a < active_.size(); ++a) {
      const std::array<double, 12> lengths = edge_lengths(active_[a]);
      for (size_t e = 0; e < 12; ++e)
        if (start_lengths_[a][e] > 0) lowest = std::min(lowest, lengths[e] / start_lengths_[a][e]);
    }
    return lowest;
  }

  // sum over the active hexes' frames of exp(-sharpness (s - floor)), plus over their edges of
  // exp(-sharpness (l / l_start - min_edge_fraction)), and its gradient in z. Each hex's
  // gradient goes to its own slots, then each node sums its hexes'.
  double energy(const Eigen::VectorXd& z, Eigen::VectorXd& gradient) {
    place(z);
    const double k = sharpness_;
    hex_gradient_.resize(8 * active_.size());
    hex_energy_.resize(active_.size());
    // Every hex on its own over the cores; the sum then in order, so a run repeats exactly.
#pragma omp parallel for schedule(static) if (active_.size() > 2000)
    for (long a = 0; a < long(active_.size()); ++a) {
      double total = 0;
      const auto& hex = mesh_.hexes[active_[size_t(a)]];
      std::array<Vec3, 8> x;
      for (size_t i = 0; i < 8; ++i) x[i] = mesh_.nodes[size_t(hex[i])];
      Vec3* dx = &hex_gradient_[8 * size_t(a)];
      for (size_t i = 0; i < 8; ++i) dx[i] = Vec3::Zero();
      Vec3 da, db, dc;
      for (const auto& f : kHexCornerFrames) {
        const double s = frame_scaled_jacobian(x[size_t(f[1])] - x[size_t(f[0])], x[size_t(f[2])] - x[size_t(f[0])],
                                               x[size_t(f[3])] - x[size_t(f[0])], da, db, dc);
        const double e = std::exp(-k * (s - floor_));
        total += e;
        const double w = -k * e;
        dx[f[1]] += w * da, dx[f[2]] += w * db, dx[f[3]] += w * dc;
        dx[f[0]] -= w * (da + db + dc);
      }
      std::array<Vec3, 3> axis;
      for (size_t a3 = 0; a3 < 3; ++a3) {
        axis[a3] = Vec3::Zero();
        for (size_t i = 0; i < 8; ++i) axis[a3] += kHexCentreAxes[a3][i] * x[i];
      }
      const double s = frame_scaled_jacobian(axis[0], axis[1], axis[2], da, db, dc);
      const double e = std::exp(-k * (s - floor_));
      total += e;
      const double w = -k * e;
      for (size_t i = 0; i < 8; ++i)
        dx[i] += w * (kHexCentreAxes[0][i] * da + kHexCentreAxes[1][i] * db + kHexCentreAxes[2][i] * dc);
      for (size_t e = 0; e < 12; ++e) {
        const double start = start_lengths_[size_t(a)][e];
        if (!(start > 0)) continue;
        const size_t i = size_t(kHexEdges[e][0]), j = size_t(kHexEdges[e][1]);
        const Vec3 d = x[i] - x[j];
        const double length = d.norm();
        const double edge_energy = std::exp(-k * (length / start - options_.min_edge_fraction));
        total += edge_energy;
        if (length > 0) {
          const Vec3 g = (-k * edge_energy / (start * length)) * d;
          dx[i] += g, dx[j] -= g;
        }
      }
      hex_energy_[size_t(a)] = total;
    }
    double total = 0;
    for (double e : hex_energy_) total += e;
#pragma omp parallel for schedule(static) if (free_.size() > 2000)
    for (long i = 0; i < long(free_.size()); ++i) {
      Vec3 g = Vec3::Zero();
      for (const auto& [slot, corner] : slots_of_[size_t(i)]) g += hex_gradient_[8 * size_t(slot) + size_t(corner)];
      const Eigen::Index o = Eigen::Index(offset_[size_t(i)]);
      if (sliding_[size_t(i)]) {
        gradient[o] = g.dot(tangent_[size_t(i)][0]) * scale_[size_t(i)];
        gradient[o + 1] = g.dot(tangent_[size_t(i)][1]) * scale_[size_t(i)];
        if (lifting_[size_t(i)]) gradient[o + 2] = g.dot(normal_[size_t(i)]) * scale_[size_t(i)];
      } else {
        for (int c = 0; c < 3; ++c) gradient[o + c] = g[c] * scale_[size_t(i)];
      }
    }
    // A lifting node's offset from the input held within its limit: exp(-sharpness (1 - (t /
    // limit)^2)) of its offset t along its normal (in units of its scale), as steep beyond the
    // limit as the frames are below the floor.
    if (off_surface_phase_) {
      for (size_t i = 0; i < free_.size(); ++i) {
        if (!lifting_[i]) continue;
        const double slack = lift_limit_[i];
        const Eigen::Index o = Eigen::Index(offset_[i]);
        const double t = origin_lift_[i] + z[o + 2];
        const double e = std::exp(-k * (1 - (t / slack) * (t / slack)));
        total += e;
        gradient[o + 2] += e * k * 2 * t / (slack * slack);
      }
    }
    return total;
  }

  HexMesh& mesh_;
  const OptimizeWorstRegionsOptions& options_;
  NodeCellIncidence node_hexes_;
  std::vector<char> on_boundary_;
  std::vector<char> hex_mark_, node_mark_;  //!< all 0 between selections
  std::vector<size_t> free_, active_;
  std::vector<double> scale_;
  std::vector<char> sliding_;                     //!< per free node: a boundary node sliding on the input
  std::vector<char> lifting_;                     //!< per free node: sliding, and along its normal too
  std::vector<double> origin_offset_;             //!< per free node: its slide's start's distance to the input
  std::vector<double> origin_lift_;               //!< per lifting node: that start's offset along its normal / scale
  std::vector<double> lift_limit_;                //!< per lifting node: how far off the input it may end / scale
  std::vector<Vec3> normal_, origin_;             //!< per free node: its surface normal, where its slide starts
  std::vector<std::array<Vec3, 2>> tangent_;      //!< per free node: its tangent plane's axes
  std::vector<size_t> offset_;                    //!< per free node: its first variable
  size_t variable_count_ = 0;
  std::vector<Vec3> surface_normals_;             //!< of options.surface's triangles
  double min_normal_cos_ = 0, flat_cos_ = 1, knife_zone_ = 0;
  std::vector<std::vector<std::pair<int, int>>> slots_of_;  //!< per free node: (active hex slot, corner)
  std::vector<Vec3> hex_gradient_;                          //!< 8 per active hex
  std::vector<double> hex_energy_;                          //!< per active hex
  std::unordered_map<size_t, std::array<double, 12>> first_lengths_;  //!< per hex ever active
  std::vector<std::array<double, 12>> start_lengths_;                 //!< per active hex
  bool off_surface_phase_ = false;  //!< the continuation with surface_slack under way
  std::unordered_set<size_t> lifted_;  //!< nodes a kept off-surface solve moved
  double floor_ = 0;
  double sharpness_ = 0;  //!< of the solve under way: options.sharpness or its fallback
  Clock::time_point deadline_;
};

}  // namespace

OptimizeWorstRegionsReport optimize_worst_regions(HexMesh& mesh, const OptimizeWorstRegionsOptions& options) {
  if (mesh.hexes.empty()) return {};
  WorstRegionOptimizer optimizer(mesh, options);
  return optimizer.run();
}

}  // namespace dthex
