// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/split_crowded_vertices.h>

#include <dthex/mesh/quality.h>
#include <dthex/numerics/grid_directions.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace dthex {
namespace {

// A face of v's link: (a, b, c) with (v, a, b, c) an even permutation of the tet it came from,
// so positively oriented with v in place.
struct LinkFace {
  std::array<int, 3> corners;
  int tet;
};

std::array<int, 3> face_opposite(const std::array<int, 4>& t, int v) {
  // The even permutations that put each position first.
  static constexpr int kEven[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
  for (size_t i = 0; i < 4; ++i)
    if (t[i] == v) return {t[size_t(kEven[i][1])], t[size_t(kEven[i][2])], t[size_t(kEven[i][3])]};
  return {-1, -1, -1};
}

// A proposed split: the link faces that go to the new vertex, the cut's edges (directed as in a
// face that stays), the two positions and the worst tet of the new star.
struct Split {
  std::vector<char> to_new;
  std::vector<std::array<int, 2>> cut;
  Vec3 kept_at = Vec3::Zero(), new_at = Vec3::Zero();
  double worst = -2;
  size_t larger_side = 0;
};

// Whether the link faces with to_new == side form one disk: Euler characteristic 1, every
// vertex of its rim on exactly two rim edges, and connected.
bool faces_form_a_disk(const std::vector<LinkFace>& link, const std::vector<char>& to_new, char side) {
  std::map<std::pair<int, int>, int> edge_uses;
  std::map<int, int> vertex_index;
  size_t faces = 0;
  for (size_t i = 0; i < link.size(); ++i) {
    if (to_new[i] != side) continue;
    ++faces;
    const auto& c = link[i].corners;
    for (size_t k = 0; k < 3; ++k) {
      vertex_index.emplace(c[k], int(vertex_index.size()));
      const int a = c[k], b = c[(k + 1) % 3];
      ++edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  if (faces == 0) return false;
  if (long(vertex_index.size()) - long(edge_uses.size()) + long(faces) != 1) return false;
  std::map<int, int> rim_degree;
  for (const auto& [edge, uses] : edge_uses)
    if (uses == 1) ++rim_degree[edge.first], ++rim_degree[edge.second];
  for (const auto& [vertex, degree] : rim_degree)
    if (degree != 2) return false;
  std::vector<int> parent(vertex_index.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  };
  for (size_t i = 0; i < link.size(); ++i) {
    if (to_new[i] != side) continue;
    const auto& c = link[i].corners;
    for (size_t k = 1; k < 3; ++k) parent[size_t(root(vertex_index[c[k]]))] = root(vertex_index[c[0]]);
  }
  const int first = root(0);
  for (const auto& [vertex, index] : vertex_index)
    if (root(index) != first) return false;
  return true;
}

class CrowdedVertexSplitter {
 public:
  CrowdedVertexSplitter(TetMesh& mesh, const SplitCrowdedVerticesOptions& options) : mesh_(mesh), options_(options) {
    on_boundary_.assign(mesh.points.size(), 0);
    for (const auto& f : mesh.boundary_faces)
      for (int v : f) on_boundary_[size_t(v)] = 1;
    star_.assign(mesh.points.size(), {});
    for (size_t t = 0; t < mesh.tets.size(); ++t)
      for (int v : mesh.tets[t]) star_[size_t(v)].push_back(int(t));
  }

  //! Interior vertices in more than max_tets tets, and the largest tet count of one.
  size_t crowded(int& most) const {
    size_t count = 0;
    most = 0;
    for (size_t v = 0; v < star_.size(); ++v) {
      if (on_boundary_[v]) continue;
      most = std::max(most, int(star_[v].size()));
      count += int(star_[v].size()) > options_.max_tets;
    }
    return count;
  }

  //! One round over the crowded vertices, most crowded first; the number of splits made.
  size_t split_round() {
    std::vector<std::pair<size_t, int>> order;
    for (size_t v = 0; v < star_.size(); ++v)
      if (!on_boundary_[v] && int(star_[v].size()) > options_.max_tets) order.emplace_back(star_[v].size(), int(v));
    std::sort(order.rbegin(), order.rend());
    size_t made = 0;
    for (const auto& [tets, v] : order)
      if (int(star_[size_t(v)].size()) > options_.max_tets && try_split(v)) ++made;
    return made;
  }

 private:
  const Vec3& point(int v) const { return mesh_.points[size_t(v)]; }

  double worst_around(int v) const {
    double worst = 1;
    for (int t : star_[size_t(v)]) {
      const auto& q = mesh_.tets[size_t(t)];
      worst = std::min(worst, tet_scaled_jacobian(point(q[0]), point(q[1]), point(q[2]), point(q[3])));
    }
    return worst;
  }

  // The worst tet scaled Jacobian of the new star with the points at kept_at and new_at; stops
  // as soon as one tet is at or below `stop_below` (the caller only needs to know it loses).
  double worst_of(const std::vector<LinkFace>& link, const Split& s, const Vec3& kept_at, const Vec3& new_at,
                  double stop_below) const {
    double worst = 1;
    for (size_t i = 0; i < link.size() && worst > stop_below; ++i) {
      const auto& c = link[i].corners;
      const Vec3& moved = s.to_new[i] ? new_at : kept_at;
      worst = std::min(worst, tet_scaled_jacobian(moved, point(c[0]), point(c[1]), point(c[2])));
    }
    for (size_t i = 0; i < s.cut.size() && worst > stop_below; ++i)
      worst = std::min(worst, tet_scaled_jacobian(kept_at, point(s.cut[i][1]), point(s.cut[i][0]), new_at));
    return worst;
  }

  // Moves one of the two points by a pattern search that raises the new star's worst tet.
  void place(const std::vector<LinkFace>& link, Split& s, bool move_new, double length) const {
    Vec3& x = move_new ? s.new_at : s.kept_at;
    double step = 0.2 * length;
    for (int trial = 0; trial < options_.placement_trials && step > 1e-3 * length; ++trial) {
      Vec3 best_x = x;
      double best = s.worst;
      for (const Vec3& d : grid_directions()) {
        const Vec3 y = x + step * d;
        const double w = move_new ? worst_of(link, s, s.kept_at, y, best) : worst_of(link, s, y, s.new_at, best);
        if (w > best + 1e-12) best = w, best_x = y;
      }
      if (best_x == x) {
        step *= 0.5;
        continue;
      }
      x = best_x;
      s.worst = best;
    }
  }

  // The split of v's link by the plane through the median of its faces across `axis`, with
  // both points placed; worst = -2 when the plane does not cut the link into two disks.
  Split split_across(int v, const std::vector<LinkFace>& link, const std::vector<Vec3>& centre, const Vec3& axis,
                     double length) const {
    Split s;
    std::vector<double> along(link.size());
    for (size_t i = 0; i < link.size(); ++i) along[i] = centre[i].dot(axis);
    std::vector<double> sorted = along;
    std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    s.to_new.resize(link.size());
    for (size_t i = 0; i < link.size(); ++i) s.to_new[i] = along[i] > median ? 1 : 0;
    if (!faces_form_a_disk(link, s.to_new, 0) || !faces_form_a_disk(link, s.to_new, 1)) return s;
    std::map<std::pair<int, int>, size_t> face_of_edge;
    for (size_t i = 0; i < link.size(); ++i)
      for (size_t k = 0; k < 3; ++k) face_of_edge[{link[i].corners[k], link[i].corners[(k + 1) % 3]}] = i;
    size_t moved = 0;
    for (size_t i = 0; i < link.size(); ++i) {
      if (s.to_new[i]) {
        ++moved;
        continue;
      }
      for (size_t k = 0; k < 3; ++k) {
        const int a = link[i].corners[k], b = link[i].corners[(k + 1) % 3];
        const auto across = face_of_edge.find({b, a});
        if (across != face_of_edge.end() && s.to_new[across->second]) s.cut.push_back({a, b});
      }
    }
    s.larger_side = std::max(moved, link.size() - moved) + s.cut.size();
    // Each point starts a quarter of the way from v towards its cap's centre.
    Vec3 kept_centre = Vec3::Zero(), new_centre = Vec3::Zero();
    for (size_t i = 0; i < link.size(); ++i) (s.to_new[i] ? new_centre : kept_centre) += centre[i];
    s.kept_at = point(v) + 0.25 * kept_centre / double(link.size() - moved);
    s.new_at = point(v) + 0.25 * new_centre / double(moved);
    s.worst = worst_of(link, s, s.kept_at, s.new_at, -2);
    for (int round = 0; round < 2; ++round) {
      place(link, s, false, length);
      place(link, s, true, length);
    }
    return s;
  }

  bool try_split(int v) {
    std::vector<LinkFace> link;
    for (int t : star_[size_t(v)]) link.push_back({face_opposite(mesh_.tets[size_t(t)], v), t});
    const Vec3 p = point(v);
    double length = 0;
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    std::vector<Vec3> centre(link.size());
    for (size_t i = 0; i < link.size(); ++i) {
      centre[i] = Vec3::Zero();
      for (int y : link[i].corners) {
        const Vec3 d = point(y) - p;
        centre[i] += d / 3;
        length += d.norm() / 3;
        spread += d * d.transpose();
      }
    }
    length /= double(link.size());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(spread);
    Split best;
    for (const Vec3& axis : {Vec3(axes.eigenvectors().col(2)), Vec3(axes.eigenvectors().col(1)),
                             Vec3(axes.eigenvectors().col(0)), Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY()),
                             Vec3(Vec3::UnitZ())}) {
      Split s = split_across(v, link, centre, axis.normalized(), length);
      // The better worst tet; between equals, the more even split.
      if (s.worst > best.worst + 1e-12 || (s.worst > best.worst - 1e-12 && s.larger_side < best.larger_side))
        best = std::move(s);
    }
    const double ratio = int(link.size()) > options_.very_crowded_tets ? options_.very_crowded_quality_ratio
                                                                        : options_.min_quality_ratio;
    if (best.to_new.empty() || !(best.worst > 0) || best.worst < ratio * worst_around(v)) return false;
    apply(v, link, best);
    return true;
  }

  void apply(int v, const std::vector<LinkFace>& link, const Split& s) {
    const int w = int(mesh_.points.size());
    mesh_.points.push_back(s.new_at);
    mesh_.points[size_t(v)] = s.kept_at;
    on_boundary_.push_back(0);
    star_.emplace_back();
    std::vector<int> kept;
    for (size_t i = 0; i < link.size(); ++i) {
      const int t = link[i].tet;
      if (!s.to_new[i]) {
        kept.push_back(t);
        continue;
      }
      std::replace(mesh_.tets[size_t(t)].begin(), mesh_.tets[size_t(t)].end(), v, w);
      star_[size_t(w)].push_back(t);
    }
    star_[size_t(v)] = std::move(kept);
    const bool regions = !mesh_.tet_region.empty();
    const int region = regions ? mesh_.tet_region[size_t(link.front().tet)] : 0;
    for (const auto& e : s.cut) {
      // (v, b, a, w): the face (v, a, b) of the kept tet across the cut has its tet on the
      // other side, so this one is positive where the kept tet is.
      const int t = int(mesh_.tets.size());
      mesh_.tets.push_back({v, e[1], e[0], w});
      if (regions) mesh_.tet_region.push_back(region);
      for (int y : mesh_.tets.back()) star_[size_t(y)].push_back(t);
    }
  }

  TetMesh& mesh_;
  const SplitCrowdedVerticesOptions& options_;
  std::vector<char> on_boundary_;
  std::vector<std::vector<int>> star_;
};

}  // namespace

SplitCrowdedVerticesReport split_crowded_vertices(TetMesh& mesh, const SplitCrowdedVerticesOptions& options) {
  SplitCrowdedVerticesReport report;
  report.tets_before = mesh.tets.size();
  CrowdedVertexSplitter splitter(mesh, options);
  report.crowded_before = splitter.crowded(report.most_tets_before);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    const size_t made = splitter.split_round();
    report.split += made;
    if (made == 0) break;
  }
  report.crowded_after = splitter.crowded(report.most_tets_after);
  report.tets_after = mesh.tets.size();
  return report;
}

}  // namespace dthex
