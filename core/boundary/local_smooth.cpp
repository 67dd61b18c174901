// SPDX-License-Identifier: MIT
#include <dthex/boundary/local_smooth.h>

#include <dthex/hexes/conformity.h>
#include <dthex/mesh/graph_colouring.h>
#include <dthex/mesh/incidence.h>
#include <dthex/mesh/quality.h>
#include <dthex/numerics/tangent_basis.h>

#include <algorithm>
#include <cstdint>
#include <chrono>
#include <cmath>
#include <numeric>
#include <queue>

namespace dthex {
namespace {

using Clock = std::chrono::steady_clock;

class NodeSmoother {
 public:
  NodeSmoother(HexMesh& mesh, const TriangleBvh& surface, const LocalSmoothOptions& options)
      : mesh_(mesh), surface_(surface), options_(options) {
    const size_t n = mesh.nodes.size();
    node_hexes_ = NodeCellIncidence(n, mesh.hexes, true);
    is_boundary_ = boundary_nodes(mesh, options.constraints ? &options.constraints->on_boundary : nullptr);
    sj_.resize(mesh.hexes.size());
    shape_.resize(mesh.hexes.size());
    edge_ratio_floor_ = options_.min_edge_ratio * options_.min_edge_ratio;
    if (edge_ratio_floor_ > 0) edge_ratio_.resize(mesh.hexes.size());
#pragma omp parallel for schedule(static) if (mesh.hexes.size() > 50000)
    for (long h = 0; h < long(mesh.hexes.size()); ++h) {
      const std::array<Vec3, 8> corners = hex_corners(mesh, size_t(h));
      const HexScaledJacobianAndShape q = hex_scaled_jacobian_and_shape(corners);
      sj_[size_t(h)] = q.scaled_jacobian;
      shape_[size_t(h)] = q.shape;
      if (edge_ratio_floor_ > 0) edge_ratio_[size_t(h)] = hex_edge_ratio_squared(corners);
    }
    surface_normals_ = unit_triangle_normals(surface.points(), surface.triangles());
    min_normal_cos_ = std::cos(options_.max_normal_turn_deg * M_PI / 180.0);
    // The knife-edge zone, only where the surface has a knife edge: the nodes that start in
    // it (they stay in it), and the zone's width.
    near_knife_.assign(n, 0);
    if (options_.knife_edge_slide > 0 && has_knife_edge(surface.triangles(), surface_normals_)) {
      knife_zone_ = options_.knife_edge_slide * surface.bounds().diagonal().norm();
#pragma omp parallel for schedule(dynamic, 256)
      for (long v = 0; v < long(n); ++v)
        if (is_boundary_[size_t(v)])
          near_knife_[size_t(v)] = near_knife_edge(surface_, surface_normals_, mesh.nodes[size_t(v)], knife_zone_);
    }
  }

  LocalSmoothReport run() {
    deadline_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(options_.time_limit_seconds));
    LocalSmoothReport report;
    report.min_scaled_jacobian_before = min_sj();
    report.avg_shape_before = avg_shape();
    raise_worst(report);
    if (!report.time_limit_reached) lift_worst(report);
    if (!report.time_limit_reached) improve_shapes(report);
    // The shape sweeps changed the neighbourhoods of the hexes still below the target:
    // some of them can now move further.
    if (!report.time_limit_reached && options_.shape_sweeps > 0) raise_worst(report);
    report.min_scaled_jacobian_after = min_sj();
    report.avg_shape_after = avg_shape();
    return report;
  }

 private:
  bool out_of_time(LocalSmoothReport& report) {
    if (Clock::now() <= deadline_) return false;
    report.time_limit_reached = true;
    return true;
  }
  double min_sj() const { return sj_.empty() ? 0 : *std::min_element(sj_.begin(), sj_.end()); }
  double avg_shape() const {
    return shape_.empty() ? 0 : std::accumulate(shape_.begin(), shape_.end(), 0.0) / double(shape_.size());
  }

  // Worst hex first: each hex below the target has the nodes moved that raise the
  // smallest scaled Jacobian around them; the hexes whose value changes go back in the
  // queue. A hex is taken at most `max_attempts_per_hex` times, which bounds the work
  // where the target cannot be reached. With `until_worst_is_stuck` (a lift step) the pass
  // ends as soon as the worst hex has had its attempts and is still below the target: the
  // minimum cannot reach the target then, and raising the others would cost shape and time
  // for nothing the step is for.
  void raise_worst(LocalSmoothReport& report, bool until_worst_is_stuck = false) {
    const double target = options_.target_scaled_jacobian;
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (size_t h = 0; h < sj_.size(); ++h)
      if (sj_[h] < target) queue.push({sj_[h], int(h)});
    const double budget =
        double(options_.max_attempts_per_hex) *
        std::max(options_.attempt_budget_fraction * double(sj_.size()), double(options_.attempt_budget_hexes));
    std::vector<unsigned char> attempts(sj_.size(), 0);
    // A node's search depends only on the nodes of its own hexes: one that failed is not
    // searched again until one of those moves (it would fail the same way). Hexes below the
    // target share nodes, so where they cannot be raised most searches are such repeats.
    std::vector<uint32_t> changed(mesh_.nodes.size(), 0), failed_at(mesh_.nodes.size(), 0);
    uint32_t move_count = 0;
    size_t popped = 0;
    while (!queue.empty()) {
      const auto [value, h] = queue.top();
      queue.pop();
      if (value != sj_[size_t(h)] || value >= target) continue;
      if (attempts[size_t(h)] >= options_.max_attempts_per_hex) {
        if (until_worst_is_stuck) return;  // the worst (the heap's top, its value current) is stuck
        continue;
      }
      ++attempts[size_t(h)];
      if (double(++popped) > budget) return;
      if (popped % 64 == 0 && out_of_time(report)) return;
      ++report.sweeps;
      // Only the nodes of the frame where the hex is worst can raise it.
      const auto& hex = mesh_.hexes[size_t(h)];
      const int frame = hex_worst_scaled_jacobian_frame(hex_corners(mesh_, size_t(h)));
      std::array<int, 8> nodes = hex;
      size_t count = 8;
      if (frame < 8) {
        const auto local = hex_corner_frame_nodes(frame);
        for (size_t i = 0; i < 4; ++i) nodes[i] = hex[size_t(local[i])];
        count = 4;
      }
      for (size_t n = 0; n < count; ++n) {
        const int v = nodes[n];
        if (failed_at[size_t(v)] == changed[size_t(v)] + 1) continue;
        if (!improve_node(v, false, scratch_)) {
          failed_at[size_t(v)] = changed[size_t(v)] + 1;
          continue;
        }
        ++report.moves;
        ++move_count;
        for (int g : node_hexes_[size_t(v)]) {
          for (int w : mesh_.hexes[size_t(g)]) changed[size_t(w)] = move_count;
          if (sj_[size_t(g)] < target) queue.push({sj_[size_t(g)], g});
        }
      }
    }
  }

  // The target raised a step at a time (LocalSmoothOptions::lift_to_scaled_jacobian), each
  // step a pass over the hexes below it, until a step raises the minimum no further. The target
  // stays at the last step: the shape sweeps then keep every hex at or above min(its value,
  // that step), so they do not undo what was lifted.
  void lift_worst(LocalSmoothReport& report) {
    const double step = options_.lift_step;
    if (!(step > 0)) return;
    // Where the pass to the target fell short, a higher one would not be reached either.
    if (min_sj() < options_.target_scaled_jacobian - 0.5 * step) return;
    const double start = options_.target_scaled_jacobian;
    for (int k = 1; start + k * step <= options_.lift_to_scaled_jacobian + 1e-12 && !report.time_limit_reached; ++k) {
      const double level = start + k * step;
      if (min_sj() >= level) continue;  // already there
      const double before = min_sj();
      options_.target_scaled_jacobian = level;
      raise_worst(report, true);
      report.lifted_to = level;
      if (min_sj() < before + 1e-4) return;
    }
  }

  // Colours such that two nodes of one colour never share a hex: their moves are then
  // independent (each reads only its own hexes' nodes and writes only its own hexes'
  // values), so a colour can be swept by several threads with the same result as by one.
  std::vector<std::vector<int>> colour_classes(const std::vector<char>& wanted) const {
    GreedyCellColouring colouring(mesh_.hexes.size());
    std::vector<std::vector<int>> classes;
    for (size_t v = 0; v < wanted.size(); ++v) {
      if (!wanted[v]) continue;
      const NodeCellIncidence::Range hexes = node_hexes_[v];
      const size_t c = colouring.add(hexes.begin(), hexes.end());
      if (c == classes.size()) classes.emplace_back();
      classes[c].push_back(int(v));
    }
    return classes;
  }

  // Sweeps over the nodes of the hexes below the shape threshold, one colour class at a
  // time (in parallel within a class); a later sweep only revisits the nodes next to one
  // that moved (the others would find what they found before).
  void improve_shapes(LocalSmoothReport& report) {
    std::vector<char> active(mesh_.nodes.size(), 0);
    for (size_t h = 0; h < shape_.size(); ++h)
      if (shape_[h] < options_.shape_threshold)
        for (int v : mesh_.hexes[h]) active[size_t(v)] = 1;
    if (!options_.move_boundary)
      for (size_t v = 0; v < active.size(); ++v)
        if (is_boundary_[v]) active[v] = 0;
    std::vector<char> moved(mesh_.nodes.size(), 0);
    for (int sweep = 0; sweep < options_.shape_sweeps; ++sweep) {
      const std::vector<std::vector<int>> classes = colour_classes(active);
      if (classes.empty()) break;
      std::fill(active.begin(), active.end(), 0);
      ++report.sweeps;
      for (const std::vector<int>& nodes : classes) {
        if (out_of_time(report)) return;
        const long count = long(nodes.size());
#pragma omp parallel if (count > 32)
        {
          Scratch scratch;
#pragma omp for schedule(dynamic, 64)
          for (long n = 0; n < count; ++n) moved[size_t(nodes[size_t(n)])] = improve_node(nodes[size_t(n)], true, scratch);
        }
        for (int v : nodes) {
          if (!moved[size_t(v)]) continue;
          moved[size_t(v)] = 0;
          ++report.moves;
          for (int g : node_hexes_[size_t(v)])
            if (shape_[size_t(g)] < options_.shape_threshold)
              for (int u : mesh_.hexes[size_t(g)])
                if (options_.move_boundary || !is_boundary_[size_t(u)]) active[size_t(u)] = 1;
        }
      }
    }
  }

  struct Score {
    bool valid = false;  //!< false: a hex fell below the floor, the position is refused
    double min_sj = 0, shape_sum = 0, min_shape = 0;
    double clipped_sj_sum = 0;  //!< sum over the hexes of min(scaled Jacobian, target)
  };
  //! Per-thread work space of improve_node.
  struct Scratch {
    std::vector<HexWithMovingCorner> around;  //!< the hexes of the node, when searched incrementally
    std::vector<double> trial_sj, trial_shape;  //!< per hex, at the last scored position
    std::vector<double> best_sj, best_shape;    //!< per hex, at the best position so far
    std::vector<double> edge_ratio_now;         //!< per hex: hex_edge_ratio_squared, node where it stands
    bool best_has_shape = false;
  };

  // The hexes around v with v at x, into scratch.trial_*; stops early (invalid) when a
  // hex's scaled Jacobian is below `floor`, which no accepted position may do.
  //! The hexes around v with v at x. Invalid (not evaluated further) if a hex falls below
  //! `floor`, or, with `keep_valid`, if a hex valid now falls below min(its value, target), or
  //! if a hex's edge ratio falls below min(its value now, min_edge_ratio).
  Score score_at(int v, const Vec3& x, bool need_shape, double floor, bool keep_valid, Scratch& scratch) const {
    Score s;
    s.min_sj = 1;
    s.min_shape = 1;
    const NodeCellIncidence::Entries hexes = node_hexes_.entries(size_t(v));
    const bool incremental = !scratch.around.empty();
    for (size_t k = 0; k < hexes.size(); ++k) {
      HexScaledJacobianAndShape q;
      double edge_ratio = 1;
      if (incremental) {
        q = scratch.around[k].at(x, need_shape);
        if (edge_ratio_floor_ > 0) edge_ratio = scratch.around[k].edge_ratio_squared_at(x);
      } else {
        auto corners = hex_corners(mesh_, size_t(hexes[k].cell));
        corners[size_t(hexes[k].corner)] = x;
        q = need_shape ? hex_scaled_jacobian_and_shape(corners) : HexScaledJacobianAndShape{hex_scaled_jacobian(corners), 0};
        if (edge_ratio_floor_ > 0) edge_ratio = hex_edge_ratio_squared(corners);
      }
      if (q.scaled_jacobian < floor) return s;
      if (edge_ratio < std::min(scratch.edge_ratio_now[k], edge_ratio_floor_)) return s;
      // Around an inverted hex the floor is negative, and a move that keeps the worst hex and
      // raises the clipped sum could otherwise trade a valid hex for an inverted one: move
      // after move, nodes of a tangled region walked across the mesh.
      if (keep_valid) {
        const double now = sj_[size_t(hexes[k].cell)];
        if (now > 0 && q.scaled_jacobian < std::min(now, options_.target_scaled_jacobian)) return s;
      }
      s.min_sj = std::min(s.min_sj, q.scaled_jacobian);
      s.clipped_sj_sum += std::min(q.scaled_jacobian, options_.target_scaled_jacobian);
      s.shape_sum += q.shape;
      s.min_shape = std::min(s.min_shape, q.shape);
      scratch.trial_sj[k] = q.scaled_jacobian;
      scratch.trial_shape[k] = q.shape;
    }
    s.valid = true;
    return s;
  }

  // Scaled-Jacobian pass: raise the local minimum while it is below the target. Shape pass:
  // raise the shape sum while the local minimum stays at least min(current, target).
  bool better(const Score& candidate, const Score& current, bool shape_pass, size_t hexes) const {
    if (!candidate.valid) return false;
    const double target = options_.target_scaled_jacobian;
    // Raising a hex that is not the worst, without lowering the worst, counts too: it frees
    // the neighbours, where a pure max-min search stalls between two equally bad hexes.
    if (!shape_pass)
      return current.min_sj < target && (candidate.min_sj > current.min_sj + 1e-9 ||
                                         (candidate.min_sj >= current.min_sj &&
                                          candidate.clipped_sj_sum > current.clipped_sj_sum + 1e-9));
    if (candidate.min_sj < std::min(current.min_sj, target)) return false;
    // The worst shape counts as much as the mean: the minimum is what a solver feels.
    const double n = double(std::max<size_t>(1, hexes));
    return candidate.min_shape + candidate.shape_sum / n > current.min_shape + current.shape_sum / n + 1e-9;
  }
  // No accepted position may have a hex below this.
  double floor_for(const Score& current, bool shape_pass) const {
    return shape_pass ? std::min(current.min_sj, options_.target_scaled_jacobian) : current.min_sj;
  }

  // Where a step from x along d lands: x + d for an interior node; for a boundary node the
  // closest surface point, refused (false) if it jumps further than the step (another sheet)
  // or onto a part of the surface facing elsewhere (across a feature).
  // A node held on a crease line, moving along it: the line's kind and unit direction where
  // the node stands, and the radius within which the crease tests look.
  struct CreaseLine {
    CreaseKind kind = CreaseKind::none;
    Vec3 direction = Vec3::Zero();
    double radius = 0;
  };

  bool landing(int v, const Vec3& x, const Vec3& d, const Vec3& normal, Vec3& out,
               const CreaseLine* line = nullptr) const {
    if (!is_boundary_[size_t(v)]) {
      out = x + d;
      return true;
    }
    const Vec3 moved = x + d;
    const TriangleBvh::ClosestPoint cp = surface_.closest_point(moved);
    if (cp.triangle < 0) return false;
    if (std::sqrt(cp.distance_sq) > d.norm()) return false;
    if (line) {
      // Still on a crease line of the same kind and about the same direction: the node has
      // moved along the crease, not off it.
      Vec3 there = Vec3::Zero();
      const CreaseKind kind = crease_at(surface_, surface_normals_, cp.point, surface_normals_[size_t(cp.triangle)],
                                        line->radius, min_normal_cos_, there);
      if (kind != line->kind || std::abs(there.dot(line->direction)) < min_normal_cos_) return false;
    } else if (surface_normals_[size_t(cp.triangle)].dot(normal) < min_normal_cos_) {
      return false;
    }
    if (near_knife_[size_t(v)] && !near_knife_edge(surface_, surface_normals_, cp.point, knife_zone_)) return false;
    out = cp.point;
    return true;
  }

  //! On a knife edge's line (not at a corner where it meets another crease).
  bool on_knife_edge(const Vec3& x, const Vec3& normal, double radius) const {
    Vec3 line;
    double faces_cos = 1;
    return crease_at(surface_, surface_normals_, x, normal, radius, min_normal_cos_, line, &faces_cos) ==
               CreaseKind::convex_line &&
           faces_cos < -std::cos(kKnifeEdgeAngleDeg * M_PI / 180.0);
  }

  // The mean of v's edge neighbours (each counted once per hex that holds the edge): the
  // Laplacian guess, which on a hex mesh evens out edge lengths and angles together. Also
  // the mean length of those edges, the node's length scale.
  Vec3 edge_neighbour_mean(int v, double& mean_length) const {
    Vec3 sum = Vec3::Zero();
    double length = 0;
    int n = 0;
    const Vec3& x = mesh_.nodes[size_t(v)];
    for (const NodeCellIncidence::Entry i : node_hexes_.entries(size_t(v))) {
      const auto& hex = mesh_.hexes[size_t(i.cell)];
      const auto frame = hex_corner_frame_nodes(i.corner);  // the corner and its 3 edge neighbours
      for (int k = 1; k < 4; ++k) {
        const Vec3& u = mesh_.nodes[size_t(hex[size_t(frame[size_t(k)])])];
        sum += u;
        length += (u - x).norm();
        ++n;
      }
    }
    mean_length = length / double(n);
    return sum / double(n);
  }

  bool improve_node(int v, bool shape_pass, Scratch& scratch) {
    const NodeCellIncidence::Entries hexes = node_hexes_.entries(size_t(v));
    if (hexes.empty()) return false;
    Vec3 x = mesh_.nodes[size_t(v)];
    const bool need_shape = shape_pass;
    // The current values are the cached ones (computed by the same functions).
    scratch.around.clear();
    scratch.trial_sj.resize(hexes.size());
    scratch.trial_shape.resize(hexes.size());
    Score current;
    current.valid = true;
    current.min_sj = current.min_shape = 1;
    for (const NodeCellIncidence::Entry i : hexes) {
      const double q = sj_[size_t(i.cell)], sh = need_shape ? shape_[size_t(i.cell)] : 0.0;
      current.min_sj = std::min(current.min_sj, q);
      current.clipped_sj_sum += std::min(q, options_.target_scaled_jacobian);
      current.shape_sum += sh;
      current.min_shape = std::min(current.min_shape, sh);
    }
    if (!shape_pass && current.min_sj >= options_.target_scaled_jacobian) return false;
    scratch.edge_ratio_now.assign(hexes.size(), 1.0);
    if (edge_ratio_floor_ > 0)
      for (size_t k = 0; k < hexes.size(); ++k) scratch.edge_ratio_now[k] = edge_ratio_[size_t(hexes[k].cell)];

    double scale = 0;
    const Vec3 laplacian = edge_neighbour_mean(v, scale);
    if (!(scale > 0)) return false;

    // Search directions: the axes, or for a boundary node the tangent plane of the surface,
    // or for one held on a crease line that line.
    Vec3 normal = Vec3::Zero();
    CreaseLine crease;
    const CreaseLine* along_crease = nullptr;
    if (is_boundary_[size_t(v)]) {
      const TriangleBvh::ClosestPoint cp = surface_.closest_point(x);
      if (cp.triangle < 0) return false;
      normal = surface_normals_[size_t(cp.triangle)];
      if (normal.squaredNorm() == 0) return false;
      // A node of the coarse surface's feature lines stays on any crease it sits on; another
      // one stays only on a convex crease (projection piles nodes of both neighbouring
      // facets onto a convex edge, and they trace it; on a concave one they are a mistake).
      const bool held = !options_.constraints || options_.constraints->on_feature.empty() ||
                        options_.constraints->is_feature(size_t(v));
      if (on_surface_crease(surface_, surface_normals_, x, normal, 1e-6 * scale, min_normal_cos_, !held) &&
          !(near_knife_[size_t(v)] && on_knife_edge(x, normal, 1e-6 * scale))) {
        // Held on the crease: along its line at most.
        if (!options_.slide_along_creases) return false;
        crease.radius = 1e-6 * scale;
        crease.kind = crease_at(surface_, surface_normals_, x, normal, crease.radius, min_normal_cos_, crease.direction);
        if (crease.kind != CreaseKind::convex_line && crease.kind != CreaseKind::concave_line) return false;
        along_crease = &crease;
      }
    }
    auto tangential = [&](Vec3 d) {
      if (along_crease) return Vec3(d.dot(along_crease->direction) * along_crease->direction);
      return is_boundary_[size_t(v)] ? Vec3(d - d.dot(normal) * normal) : d;
    };

    bool moved = false;
    auto accept = [&](const Vec3& y, const Score& s) {
      x = y;
      current = s;
      moved = true;
      std::swap(scratch.trial_sj, scratch.best_sj);
      std::swap(scratch.trial_shape, scratch.best_shape);
      scratch.trial_sj.resize(hexes.size());
      scratch.trial_shape.resize(hexes.size());
      scratch.best_has_shape = need_shape;
    };
    if (shape_pass) {
      // The cheap guess first (and half of it); the compass search only where it fails
      // around a badly shaped hex.
      const Vec3 d = tangential(laplacian - x);
      for (double t : {1.0, 0.5}) {
        Vec3 y;
        if (!landing(v, x, t * d, normal, y, along_crease)) continue;
        const Score s = score_at(v, y, need_shape, floor_for(current, true), current.min_sj <= 0, scratch);
        if (better(s, current, true, hexes.size())) {
          accept(y, s);
          break;
        }
      }
    }
    if (!moved && (!shape_pass || current.min_shape < options_.compass_below_shape)) {
      // Many trials around one position: evaluate the hexes incrementally.
      for (const NodeCellIncidence::Entry i : hexes)
        scratch.around.emplace_back(hex_corners(mesh_, size_t(i.cell)), i.corner);
      std::array<Vec3, 14> directions;
      size_t direction_count = 0;
      if (along_crease) {
        directions[direction_count++] = along_crease->direction;
        directions[direction_count++] = -along_crease->direction;
      } else if (is_boundary_[size_t(v)]) {
        const auto [t1, t2] = tangent_basis(normal);
        for (int k = 0; k < 8; ++k) {
          const double a = k * M_PI / 4;
          directions[direction_count++] = std::cos(a) * t1 + std::sin(a) * t2;
        }
      } else {
        for (int axis = 0; axis < 3; ++axis)
          for (double sign : {-1.0, 1.0}) directions[direction_count++] = sign * Vec3::Unit(axis);
        const double r = 1 / std::sqrt(3.0);
        for (double sx : {-r, r})
          for (double sy : {-r, r})
            for (double sz : {-r, r}) directions[direction_count++] = Vec3(sx, sy, sz);
      }
      int last_good = -1;
      int trials = 0;
      const int max_trials = shape_pass ? options_.shape_compass_trials : options_.compass_trials;
      for (double step = options_.initial_step * scale; step >= options_.min_step * scale && trials < max_trials;) {
        bool improved = false;
        // Try the direction that worked last time first.
        for (size_t k = 0; k < direction_count && !improved; ++k) {
          const size_t dir = last_good >= 0 ? (size_t(last_good) + k) % direction_count : k;
          Vec3 y;
          ++trials;
          if (!landing(v, x, step * directions[dir], normal, y, along_crease)) continue;
          const Score s = score_at(v, y, need_shape, floor_for(current, shape_pass), current.min_sj <= 0, scratch);
          if (better(s, current, shape_pass, hexes.size())) {
            accept(y, s);
            improved = true;
            last_good = int(dir);
          }
        }
        if (!improved) step *= 0.5;
        if (!shape_pass && current.min_sj >= options_.target_scaled_jacobian) break;
      }
    }
    if (!moved) return false;
    if (!scratch.best_has_shape) {
      score_at(v, x, true, -2, false, scratch);
      std::swap(scratch.trial_sj, scratch.best_sj);
      std::swap(scratch.trial_shape, scratch.best_shape);
    }
    return commit_move(v, x, scratch);
  }

  // Writes the node and its hexes' values (every hex of one node at a time, so nodes that
  // share no hex can be committed concurrently).
  bool commit_move(int v, const Vec3& x, const Scratch& scratch) {
    const NodeCellIncidence::Entries hexes = node_hexes_.entries(size_t(v));
    mesh_.nodes[size_t(v)] = x;
    for (size_t k = 0; k < hexes.size(); ++k) {
      const size_t h = size_t(hexes[k].cell);
      sj_[h] = scratch.best_sj[k], shape_[h] = scratch.best_shape[k];
      if (edge_ratio_floor_ > 0) edge_ratio_[h] = hex_edge_ratio_squared(hex_corners(mesh_, h));
    }
    return true;
  }

  HexMesh& mesh_;
  const TriangleBvh& surface_;
  LocalSmoothOptions options_;
  NodeCellIncidence node_hexes_;  //!< with corners
  std::vector<char> is_boundary_;
  std::vector<double> sj_, shape_;
  std::vector<double> edge_ratio_;  //!< per hex: hex_edge_ratio_squared (only with a floor)
  std::vector<Vec3> surface_normals_;
  double min_normal_cos_ = 0;
  double edge_ratio_floor_ = 0;  //!< options_.min_edge_ratio squared (hex_edge_ratio_squared's unit)
  std::vector<char> near_knife_;  //!< per node: started within knife_zone_ of a knife edge
  double knife_zone_ = 0;
  Clock::time_point deadline_;
  Scratch scratch_;  //!< for the serial passes
};

}  // namespace

LocalSmoothReport smooth_worst_hexes(HexMesh& mesh, const TriangleBvh& surface, const LocalSmoothOptions& options) {
  if (mesh.hexes.empty()) return {};
  NodeSmoother smoother(mesh, surface, options);
  return smoother.run();
}

}  // namespace dthex
