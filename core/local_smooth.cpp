// SPDX-License-Identifier: MIT
#include "core/local_smooth.h"

#include "core/conformity.h"
#include "core/quality.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace dthex {
namespace {

using Clock = std::chrono::steady_clock;

class NodeSmoother {
 public:
  NodeSmoother(HexMesh& mesh, const TriangleBvh& surface, const LocalSmoothOptions& options)
      : mesh_(mesh), surface_(surface), options_(options) {
    const size_t n = mesh.nodes.size();
    node_hexes_.resize(n);
    for (size_t h = 0; h < mesh.hexes.size(); ++h)
      for (int v : mesh.hexes[h]) node_hexes_[size_t(v)].push_back(int(h));
    is_boundary_.assign(n, 0);
    for (const auto& q : boundary_quads(mesh))
      for (int v : q) is_boundary_[size_t(v)] = 1;
    for (size_t v = 0; v < n; ++v)
      if (mesh.is_boundary_node(int(v))) is_boundary_[v] = 1;
    sj_.resize(mesh.hexes.size());
    shape_.resize(mesh.hexes.size());
    for (size_t h = 0; h < mesh.hexes.size(); ++h) {
      const auto x = hex_corners(mesh, h);
      sj_[h] = hex_scaled_jacobian(x);
      shape_[h] = hex_shape(x);
    }
    surface_normals_.resize(surface.triangles().size());
    for (size_t t = 0; t < surface_normals_.size(); ++t) {
      const auto& f = surface.triangles()[t];
      const auto& p = surface.points();
      const Vec3 c = (p[size_t(f[1])] - p[size_t(f[0])]).cross(p[size_t(f[2])] - p[size_t(f[0])]);
      surface_normals_[t] = c.norm() > 0 ? Vec3(c.normalized()) : Vec3::Zero();
    }
  }

  LocalSmoothReport run() {
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(options_.time_limit_seconds));
    LocalSmoothReport report;
    report.min_scaled_jacobian_before = min_sj();
    report.avg_shape_before = avg_shape();
    const double target = options_.target_scaled_jacobian;
    size_t last_below = sj_.size() + 1;
    double last_min = -2;
    for (int sweep = 0; sweep < options_.max_sweeps + options_.shape_sweeps; ++sweep) {
      const bool shape_pass = sweep >= options_.max_sweeps;
      std::vector<char> candidate(mesh_.nodes.size(), 0);
      for (size_t h = 0; h < mesh_.hexes.size(); ++h)
        if (shape_pass ? shape_[h] < options_.shape_threshold : sj_[h] < target)
          for (int v : mesh_.hexes[h]) candidate[size_t(v)] = 1;
      std::vector<int> order;
      for (size_t v = 0; v < candidate.size(); ++v)
        if (candidate[v] && (options_.move_boundary || !is_boundary_[v])) order.push_back(int(v));
      if (order.empty()) {
        if (shape_pass) break;
        sweep = options_.max_sweeps - 1;  // nothing below target: on to the shape sweeps
        continue;
      }
      // Worst first: their moves free their neighbours.
      std::vector<double> worst(order.size());
      for (size_t i = 0; i < order.size(); ++i) worst[i] = local_min_sj(order[i]);
      std::vector<size_t> idx(order.size());
      std::iota(idx.begin(), idx.end(), size_t(0));
      std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return worst[a] < worst[b]; });
      size_t moved = 0;
      for (size_t i : idx) {
        if (Clock::now() > deadline) {
          report.time_limit_reached = true;
          break;
        }
        if (improve_node(order[i], shape_pass)) ++moved;
      }
      report.moves += moved;
      ++report.sweeps;
      if (report.time_limit_reached) break;
      // A scaled-Jacobian sweep that neither lifted the minimum nor cleared a hex is the last.
      const size_t below = size_t(std::count_if(sj_.begin(), sj_.end(), [&](double q) { return q < target; }));
      const double minimum = min_sj();
      const bool stalled = !shape_pass && below >= last_below && minimum < last_min + 1e-3;
      last_below = below;
      last_min = minimum;
      if (moved == 0 || stalled) {
        if (shape_pass) break;
        sweep = options_.max_sweeps - 1;
      }
    }
    report.min_scaled_jacobian_after = min_sj();
    report.avg_shape_after = avg_shape();
    return report;
  }

 private:
  double min_sj() const { return sj_.empty() ? 0 : *std::min_element(sj_.begin(), sj_.end()); }
  double avg_shape() const {
    return shape_.empty() ? 0 : std::accumulate(shape_.begin(), shape_.end(), 0.0) / double(shape_.size());
  }
  double local_min_sj(int v) const {
    double m = 1;
    for (int h : node_hexes_[size_t(v)]) m = std::min(m, sj_[size_t(h)]);
    return m;
  }

  struct Score {
    double min_sj = 0, shape_sum = 0, min_shape = 0;
    double clipped_sj_sum = 0;  //!< sum over the hexes of min(scaled Jacobian, target)
  };
  // The hexes around v with v at x.
  Score score_at(int v, const Vec3& x, std::vector<double>* sj, std::vector<double>* shape) {
    Vec3& node = mesh_.nodes[size_t(v)];
    const Vec3 saved = node;
    node = x;
    Score s;
    s.min_sj = 1;
    s.min_shape = 1;
    const auto& hexes = node_hexes_[size_t(v)];
    for (size_t k = 0; k < hexes.size(); ++k) {
      const auto corners = hex_corners(mesh_, size_t(hexes[k]));
      const double q = hex_scaled_jacobian(corners);
      const double sh = need_shape_ ? hex_shape(corners) : 0.0;
      s.min_sj = std::min(s.min_sj, q);
      s.clipped_sj_sum += std::min(q, options_.target_scaled_jacobian);
      s.shape_sum += sh;
      s.min_shape = std::min(s.min_shape, sh);
      if (sj) (*sj)[k] = q;
      if (shape) (*shape)[k] = sh;
    }
    node = saved;
    return s;
  }

  // Scaled-Jacobian pass: raise the local minimum while it is below the target. Shape pass:
  // raise the shape sum while the local minimum stays at least min(current, target).
  bool better(const Score& candidate, const Score& current, bool shape_pass) const {
    const double target = options_.target_scaled_jacobian;
    // Raising a hex that is not the worst, without lowering the worst, counts too: it frees
    // the neighbours, where a pure max-min search stalls between two equally bad hexes.
    if (!shape_pass)
      return current.min_sj < target && (candidate.min_sj > current.min_sj + 1e-9 ||
                                         (candidate.min_sj >= current.min_sj &&
                                          candidate.clipped_sj_sum > current.clipped_sj_sum + 1e-9));
    if (candidate.min_sj < std::min(current.min_sj, target)) return false;
    // The worst shape counts as much as the mean: the minimum is what a solver feels.
    const double n = double(std::max<size_t>(1, node_hexes_count_));
    return candidate.min_shape + candidate.shape_sum / n > current.min_shape + current.shape_sum / n + 1e-9;
  }

  // Where a step from x along d lands: x + d for an interior node; for a boundary node the
  // closest surface point, refused (false) if it jumps further than the step (another sheet)
  // or onto a part of the surface facing elsewhere (across a feature).
  bool landing(int v, const Vec3& x, const Vec3& d, const Vec3& normal, Vec3& out) const {
    if (!is_boundary_[size_t(v)]) {
      out = x + d;
      return true;
    }
    const Vec3 moved = x + d;
    const TriangleBvh::ClosestPoint cp = surface_.closest_point(moved);
    if (cp.triangle < 0) return false;
    if (std::sqrt(cp.distance_sq) > d.norm()) return false;
    if (surface_normals_[size_t(cp.triangle)].dot(normal) < std::cos(options_.max_normal_turn_deg * M_PI / 180.0))
      return false;
    out = cp.point;
    return true;
  }

  // True if a surface triangle within `radius` of x faces more than the allowed turn away
  // from `normal`: x is on a feature edge or corner, which a slide would round off.
  bool on_feature(const Vec3& x, const Vec3& normal, double radius) const {
    const double min_cos = std::cos(options_.max_normal_turn_deg * M_PI / 180.0);
    const Eigen::AlignedBox3d box(x - Vec3::Constant(radius), x + Vec3::Constant(radius));
    bool feature = false;
    const auto& p = surface_.points();
    surface_.for_each_in_box(box, [&](int t) {
      if (feature || surface_normals_[size_t(t)].dot(normal) >= min_cos) return;
      const auto& f = surface_.triangles()[size_t(t)];
      const Vec3 c = closest_point_on_triangle(x, p[size_t(f[0])], p[size_t(f[1])], p[size_t(f[2])]);
      if ((c - x).squaredNorm() <= radius * radius) feature = true;
    });
    return feature;
  }

  bool improve_node(int v, bool shape_pass) {
    const auto& hexes = node_hexes_[size_t(v)];
    if (hexes.empty()) return false;
    Vec3 x = mesh_.nodes[size_t(v)];
    double scale = 0;
    int edges = 0;
    for (int h : hexes)
      for (int u : mesh_.hexes[size_t(h)])
        if (u != v) scale += (mesh_.nodes[size_t(u)] - x).norm(), ++edges;
    scale = edges ? scale / edges : 1.0;
    if (!(scale > 0)) return false;

    // Search directions: the axes, or for a boundary node the tangent plane of the surface.
    std::vector<Vec3> directions;
    Vec3 normal = Vec3::Zero();
    if (is_boundary_[size_t(v)]) {
      const TriangleBvh::ClosestPoint cp = surface_.closest_point(x);
      if (cp.triangle < 0) return false;
      normal = surface_normals_[size_t(cp.triangle)];
      if (normal.squaredNorm() == 0 || on_feature(x, normal, 1e-6 * scale)) return false;
      const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
      const Vec3 t1 = normal.cross(helper).normalized(), t2 = normal.cross(t1);
      for (double a = 0; a < 2 * M_PI - 1e-9; a += M_PI / 4) directions.push_back(std::cos(a) * t1 + std::sin(a) * t2);
    } else {
      for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) directions.push_back(sign * Vec3::Unit(axis));
      const double r = 1 / std::sqrt(3.0);
      for (double sx : {-r, r})
        for (double sy : {-r, r})
          for (double sz : {-r, r}) directions.push_back(Vec3(sx, sy, sz));
    }

    node_hexes_count_ = hexes.size();
    need_shape_ = shape_pass;
    Score current = score_at(v, x, nullptr, nullptr);
    if (!shape_pass && current.min_sj >= options_.target_scaled_jacobian) return false;
    bool moved = false;
    int last_good = -1;
    int trials = 0;
    for (double step = options_.initial_step * scale; step >= options_.min_step * scale && trials < (shape_pass ? 40 : 80);) {
      bool improved = false;
      // Try the direction that worked last time first.
      for (size_t k = 0; k < directions.size() && !improved; ++k) {
        const size_t dir = last_good >= 0 ? (size_t(last_good) + k) % directions.size() : k;
        Vec3 y;
        ++trials;
        if (!landing(v, x, step * directions[dir], normal, y)) continue;
        const Score s = score_at(v, y, nullptr, nullptr);
        if (better(s, current, shape_pass)) {
          x = y;
          current = s;
          improved = moved = true;
          last_good = int(dir);
        }
      }
      if (!improved) step *= 0.5;
      if (!shape_pass && current.min_sj >= options_.target_scaled_jacobian) break;
    }
    if (!moved) return false;
    std::vector<double> sj(hexes.size()), shape(hexes.size());
    need_shape_ = true;
    score_at(v, x, &sj, &shape);
    mesh_.nodes[size_t(v)] = x;
    for (size_t k = 0; k < hexes.size(); ++k) sj_[size_t(hexes[k])] = sj[k], shape_[size_t(hexes[k])] = shape[k];
    return true;
  }

  HexMesh& mesh_;
  const TriangleBvh& surface_;
  LocalSmoothOptions options_;
  std::vector<std::vector<int>> node_hexes_;
  std::vector<char> is_boundary_;
  std::vector<double> sj_, shape_;
  std::vector<Vec3> surface_normals_;
  size_t node_hexes_count_ = 1;  //!< hexes around the node being moved
  bool need_shape_ = true;       //!< scoring computes shapes (shape pass, final update)
};

}  // namespace

LocalSmoothReport smooth_worst_hexes(HexMesh& mesh, const TriangleBvh& surface, const LocalSmoothOptions& options) {
  if (mesh.hexes.empty()) return {};
  NodeSmoother smoother(mesh, surface, options);
  return smoother.run();
}

}  // namespace dthex
