// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/thin_crowded_boundary_stars.h>

#include <dthex/tet_edits/edge_removal.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace dthex {

double corner_scaled_jacobian_bound(double w) {
  if (!(w > 0)) return 0;
  if (w >= M_PI / 2) return 1;
  // Three unit edges at a common angle alpha (c = cos alpha, 0 <= c < 1): scaled Jacobian
  // sqrt(1 - 3c^2 + 2c^3), solid angle 2 atan2(that, 1 + 3c) (Van Oosterom and Strackee),
  // which falls as c rises; bisection on c.
  auto jacobian = [](double c) { return std::sqrt(std::max(0.0, 1 - 3 * c * c + 2 * c * c * c)); };
  auto solid_angle = [&](double c) { return 2 * std::atan2(jacobian(c), 1 + 3 * c); };
  double lo = 0, hi = 1;  // solid_angle(lo) = pi / 2 > w > 0 = solid_angle(hi)
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (solid_angle(mid) > w ? lo : hi) = mid;
  }
  return jacobian((lo + hi) / 2);
}

namespace {

// The solid angle whose corner bound is `bound` (the inverse of corner_scaled_jacobian_bound,
// which rises with it), by bisection.
double corner_solid_angle_for_bound(double bound) {
  if (!(bound > 0)) return 0;
  double lo = 0, hi = M_PI / 2;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (corner_scaled_jacobian_bound(mid) < bound ? lo : hi) = mid;
  }
  return hi;
}

// Solid angle at a of the tet (a, b, c, d).
double solid_angle_at(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 x = b - a, y = c - a, z = d - a;
  const double lx = x.norm(), ly = y.norm(), lz = z.norm();
  const double det = std::abs(x.dot(y.cross(z)));
  const double denom = lx * ly * lz + x.dot(y) * lz + x.dot(z) * ly + y.dot(z) * lx;
  return 2 * std::atan2(det, denom);
}

class StarThinner {
 public:
  StarThinner(TetMesh& mesh, const ThinCrowdedBoundaryStarsOptions& options)
      : m_(mesh),
        options_(options),
        on_boundary_(mesh.points.size(), 0),
        solid_angle_(mesh.points.size(), 0),
        gone_(mesh.points.size(), 0),
        target_solid_angle_(corner_solid_angle_for_bound(options.target_bound)) {
    for (const auto& f : mesh.boundary_faces)
      for (int v : f) on_boundary_[size_t(v)] = 1;
    for (const auto& t : mesh.tets)
      for (int i = 0; i < 4; ++i) {
        const int a = t[size_t(i)];
        if (!on_boundary_[size_t(a)]) continue;
        // The other three in an order that leaves the solid angle's sign out (abs above).
        std::array<int, 3> o{};
        for (int j = 0, n = 0; j < 4; ++j)
          if (j != i) o[size_t(n++)] = t[size_t(j)];
        solid_angle_[size_t(a)] += solid_angle_at(mesh.points[size_t(a)], mesh.points[size_t(o[0])],
                                                  mesh.points[size_t(o[1])], mesh.points[size_t(o[2])]);
      }
  }

  double bound(int v, int tets) const { return corner_scaled_jacobian_bound(solid_angle_[size_t(v)] / tets); }
  double bound(int v) { return bound(v, int(m_.tets_of(v).size())); }

  // The boundary vertices whose bound is below the target, the lowest first. Compared in solid
  // angle per tet (the bound rises with it), so the bound is reckoned only for them.
  std::vector<std::pair<double, int>> crowded() {
    std::vector<std::pair<double, int>> out;
    for (size_t v = 0; v < on_boundary_.size(); ++v)
      if (on_boundary_[v]) {
        const double w = solid_angle_[v] / double(m_.tets_of(int(v)).size());
        if (w < target_solid_angle_) out.emplace_back(w, int(v));
      }
    std::sort(out.begin(), out.end());
    for (auto& [w, v] : out) w = corner_scaled_jacobian_bound(w);
    return out;
  }

  double lowest_bound() {
    double narrowest = M_PI / 2;
    for (size_t v = 0; v < on_boundary_.size(); ++v)
      if (on_boundary_[v]) narrowest = std::min(narrowest, solid_angle_[v] / double(m_.tets_of(int(v)).size()));
    return corner_scaled_jacobian_bound(narrowest);
  }

  // Takes out the best interior edge at v, by an edge removal or by merging an interior
  // neighbour into another; false when neither is allowed anywhere around v.
  bool thin_once_at(int v) {
    const std::vector<int> neighbours = neighbours_of(v);
    Choice best;
    for (int u : neighbours) {
      const std::vector<int> around = m_.tets_with(v, u);
      auto removal = best_edge_removal(m_, v, u, around, options_.max_ring, on_boundary_);
      if (removal) consider(around, std::move(removal->new_tets), removal->worst, -1, best);
      if (options_.merge_interior_neighbours && !on_boundary_[size_t(u)]) consider_merges_of(u, best);
    }
    if (best.lowest_after < 0) return false;
    m_.replace(best.old_tets, best.new_tets);
    if (best.merged >= 0) gone_[size_t(best.merged)] = 1, ++merged_;
    else ++removed_;
    return true;
  }

  size_t edges_removed() const { return removed_; }
  size_t merged() const { return merged_; }

  // Drops the dead tets, then the merged points (the indices of the rest renumbered).
  void finish(TetMesh& mesh) {
    m_.compact();
    if (merged_) drop_points(mesh, gone_);
  }

 private:
  // A change of the mesh: these tets out, those in; merged is the point it takes out, if any.
  struct Choice {
    std::vector<int> old_tets;
    std::vector<std::array<int, 4>> new_tets;
    double lowest_after = -1, worst = -1;
    int merged = -1;
  };

  std::vector<int> neighbours_of(int v) {
    std::vector<int> out;
    for (int t : m_.tets_of(v))
      for (int u : m_.tet(t))
        if (u != v) out.push_back(u);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // Takes the change into `best` when its tets keep the shape the options ask for, the lowest
  // bound among the boundary vertices whose tet count it changes rises, and it rises further
  // than best's (or as far, with a better worst tet).
  void consider(const std::vector<int>& old_tets, std::vector<std::array<int, 4>> new_tets, double worst, int merged,
                Choice& best) {
    const double old_worst = worst_shape(m_, old_tets);
    if (worst < options_.min_shape_ratio * old_worst || worst < std::min(options_.min_shape, old_worst)) return;
    std::map<int, int> change;
    for (int t : old_tets)
      for (int x : m_.tet(t)) --change[x];
    for (const auto& t : new_tets)
      for (int x : t) ++change[x];
    double lowest_before = 1, lowest_after = 1;
    for (const auto& [x, d] : change) {
      if (!on_boundary_[size_t(x)] || d == 0) continue;
      const int k = int(m_.tets_of(x).size());
      lowest_before = std::min(lowest_before, bound(x, k));
      lowest_after = std::min(lowest_after, bound(x, k + d));
    }
    if (!(lowest_after > lowest_before + 1e-12)) return;
    if (lowest_after > best.lowest_after + 1e-12 || (lowest_after > best.lowest_after - 1e-12 && worst > best.worst)) {
      best.old_tets = old_tets;
      best.new_tets = std::move(new_tets);
      best.lowest_after = lowest_after;
      best.worst = worst;
      best.merged = merged;
    }
  }

  // The merges of interior vertex u into each of its interior neighbours w (an edge
  // contraction: the tets with both go, w replaces u in the others). w being interior, no new
  // edge or face joins only boundary vertices; every new tet must be positive, and w may not
  // end in more tets than the merge of interior points allows (collapse_interior_vertices.h).
  void consider_merges_of(int u, Choice& best) {
    const std::vector<int> star = m_.tets_of(u);
    for (int w : neighbours_of(u)) {
      if (on_boundary_[size_t(w)]) continue;
      EdgeContraction merge = contract_edge(m_, u, w, star);
      if (!(merge.worst > 0) || merge.tets_at_kept > size_t(options_.max_tets_at_merged_vertex)) continue;
      consider(star, std::move(merge.new_tets), merge.worst, u, best);
    }
  }

  EditableTets m_;
  const ThinCrowdedBoundaryStarsOptions& options_;
  std::vector<char> on_boundary_;
  std::vector<double> solid_angle_;  //!< per boundary vertex: the solid angle its tets fill
  std::vector<char> gone_;           //!< merged points
  double target_solid_angle_;        //!< the solid angle per tet whose bound is the target
  size_t removed_ = 0, merged_ = 0;
};

}  // namespace

ThinCrowdedBoundaryStarsReport thin_crowded_boundary_stars(TetMesh& mesh, const ThinCrowdedBoundaryStarsOptions& options) {
  ThinCrowdedBoundaryStarsReport report;
  report.tets_before = mesh.tets.size();
  StarThinner thinner(mesh, options);
  report.lowest_bound_before = thinner.lowest_bound();
  const auto crowded = thinner.crowded();
  report.crowded_before = crowded.size();
  for (const auto& [unused, v] : crowded)
    while (thinner.bound(v) < options.target_bound && thinner.thin_once_at(v)) {
    }
  report.edges_removed = thinner.edges_removed();
  report.merged = thinner.merged();
  report.crowded_after = thinner.crowded().size();
  report.lowest_bound_after = thinner.lowest_bound();
  thinner.finish(mesh);
  report.tets_after = mesh.tets.size();
  return report;
}

}  // namespace dthex
