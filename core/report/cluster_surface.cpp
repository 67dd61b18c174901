// SPDX-License-Identifier: MIT
#include <dthex/report/cluster_surface.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace dthex {
namespace {

constexpr uint64_t kSingleton = uint64_t(1) << 63;  // cluster key of a vertex that is not merged
constexpr size_t kMaxCells = (size_t(1) << 20) - 1;  // three 20-bit cell coordinates fit a key

// The surface as triangles, each with the index of the input face it was cut from.
struct Triangles {
  std::vector<std::array<int, 3>> corners;
  std::vector<size_t> face;
};

template <size_t N>
Triangles triangulate(const std::vector<std::array<int, N>>& faces) {
  Triangles t;
  t.corners.reserve(faces.size() * (N - 2));
  t.face.reserve(faces.size() * (N - 2));
  for (size_t f = 0; f < faces.size(); ++f)
    for (size_t k = 1; k + 1 < N; ++k) {  // a fan: (a,b,c) and (a,c,d) for a quad
      t.corners.push_back({faces[f][0], faces[f][k], faces[f][k + 1]});
      t.face.push_back(f);
    }
  return t;
}

// Unit area-weighted vertex normals (zero for a vertex no triangle uses).
std::vector<Vec3> vertex_normals(const std::vector<Vec3>& points, const Triangles& t) {
  std::vector<Vec3> normal(points.size(), Vec3::Zero());
  for (const auto& c : t.corners) {
    const Vec3 n = (points[size_t(c[1])] - points[size_t(c[0])]).cross(points[size_t(c[2])] - points[size_t(c[0])]);
    for (int v : c) normal[size_t(v)] += n;
  }
  for (Vec3& n : normal) {
    const double length = n.norm();
    if (length > 0) n /= length;
  }
  return normal;
}

struct Grid {
  Vec3 lo = Vec3::Zero();
  double longest = 0;
};

class Clusterer {
 public:
  Clusterer(const std::vector<Vec3>& points, const Triangles& t) : points_(points), t_(t) {
    used_.assign(points.size(), 0);
    for (const auto& c : t.corners)
      for (int v : c) used_[size_t(v)] = 1;
    bool first = true;
    Vec3 hi = Vec3::Zero();
    for (size_t v = 0; v < points.size(); ++v) {
      if (!used_[v]) continue;
      grid_.lo = first ? points[v] : grid_.lo.cwiseMin(points[v]);
      hi = first ? points[v] : hi.cwiseMax(points[v]);
      first = false;
    }
    grid_.longest = std::max((hi - grid_.lo).maxCoeff(), 1e-300);
    normal_ = vertex_normals(points, t);
  }

  // Cluster of every used vertex for `cells` cells along the longest side; vertices
  // flagged in `singleton` get a cluster of their own. A cell's vertices split in two by
  // the side their normal lies on of the cell's principal normal direction: the two
  // sides of a sheet (or a fold) thinner than the cell stay apart, while a smooth patch,
  // whose normals all lie on one side, stays one cluster. Returns the cluster count.
  size_t assign(size_t cells, const std::vector<char>& singleton, std::vector<int>& cluster) const {
    const double h = grid_.longest / double(cells);
    std::unordered_map<uint64_t, int> cell_ids, ids;
    cell_ids.reserve(std::min(points_.size(), 4 * cells * cells + 1024));
    ids.reserve(std::min(points_.size(), 8 * cells * cells + 1024));
    std::vector<int> cell_of(points_.size(), -1);
    std::vector<uint64_t> cell_key;
    std::vector<Eigen::Matrix3d> scatter;
    for (size_t v = 0; v < points_.size(); ++v) {
      if (!used_[v] || singleton[v]) continue;
      const Vec3 cell = (points_[v] - grid_.lo) / h;
      uint64_t ijk[3];
      for (int k = 0; k < 3; ++k) ijk[k] = uint64_t(std::clamp<double>(std::floor(cell[k]), 0.0, double(cells - 1)));
      const uint64_t key = (ijk[0] << 20 | ijk[1]) << 20 | ijk[2];
      const auto [it, inserted] = cell_ids.emplace(key, int(cell_key.size()));
      if (inserted) {
        cell_key.push_back(key);
        scatter.push_back(Eigen::Matrix3d::Zero());
      }
      cell_of[v] = it->second;
      scatter[size_t(it->second)] += normal_[v] * normal_[v].transpose();
    }
    std::vector<Vec3> principal(scatter.size());
    for (size_t c = 0; c < scatter.size(); ++c) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(scatter[c]);
      principal[c] = solver.eigenvectors().col(2);  // eigenvalues ascend: the largest is last
    }
    cluster.assign(points_.size(), -1);
    for (size_t v = 0; v < points_.size(); ++v) {
      if (!used_[v]) continue;
      uint64_t key;
      if (singleton[v]) {
        key = kSingleton | v;
      } else {
        const size_t c = size_t(cell_of[v]);
        key = cell_key[c] << 1 | (normal_[v].dot(principal[c]) < 0 ? 1 : 0);
      }
      cluster[v] = ids.emplace(key, int(ids.size())).first->second;
    }
    return ids.size();
  }

  // Triangles that keep three distinct clusters: an upper bound of the result's size
  // (cancelling pairs only remove more), cheap enough to search the grid size with.
  size_t surviving(const std::vector<int>& cluster) const {
    size_t count = 0;
    for (const auto& c : t_.corners) {
      const int a = cluster[size_t(c[0])], b = cluster[size_t(c[1])], d = cluster[size_t(c[2])];
      count += a != b && b != d && a != d;
    }
    return count;
  }

 private:
  const std::vector<Vec3>& points_;
  const Triangles& t_;
  std::vector<char> used_;
  std::vector<Vec3> normal_;
  Grid grid_;
};

struct TriangleKey {
  std::array<int, 3> sorted;
  bool operator==(const TriangleKey& o) const { return sorted == o.sorted; }
};
struct TriangleKeyHash {
  size_t operator()(const TriangleKey& k) const {
    uint64_t h = 1469598103934665603ull;
    for (int v : k.sorted) h = (h ^ uint64_t(uint32_t(v))) * 1099511628211ull;
    return size_t(h ^ (h >> 29));
  }
};

// The image triangles summed as an oriented chain, in first-appearance order.
ClusteredSurface build(const std::vector<Vec3>& points, const Triangles& t, const std::vector<int>& cluster,
                       size_t clusters, const std::vector<double>& priority) {
  struct Term {
    std::array<int, 3> sorted;
    int coefficient = 0;
    size_t source = 0;
  };
  std::vector<Term> terms;
  std::unordered_map<TriangleKey, size_t, TriangleKeyHash> index;
  index.reserve(t.corners.size() / 2 + 16);
  auto worse = [&](size_t a, size_t b) { return !priority.empty() && priority[a] < priority[b]; };
  for (size_t i = 0; i < t.corners.size(); ++i) {
    std::array<int, 3> c{cluster[size_t(t.corners[i][0])], cluster[size_t(t.corners[i][1])],
                         cluster[size_t(t.corners[i][2])]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;  // collapsed
    // Sort with a parity count: an odd number of swaps means the opposite orientation.
    int sign = 1;
    if (c[0] > c[1]) std::swap(c[0], c[1]), sign = -sign;
    if (c[1] > c[2]) std::swap(c[1], c[2]), sign = -sign;
    if (c[0] > c[1]) std::swap(c[0], c[1]), sign = -sign;
    const auto [it, inserted] = index.emplace(TriangleKey{c}, terms.size());
    if (inserted) terms.push_back({c, 0, t.face[i]});
    Term& term = terms[it->second];
    term.coefficient += sign;
    if (worse(t.face[i], term.source)) term.source = t.face[i];
  }

  ClusteredSurface out;
  std::vector<Vec3> sum(clusters, Vec3::Zero());
  std::vector<size_t> members(clusters, 0);
  for (size_t v = 0; v < points.size(); ++v)
    if (cluster[v] >= 0) {
      sum[size_t(cluster[v])] += points[v];
      ++members[size_t(cluster[v])];
    }
  std::vector<int> compact(clusters, -1);
  for (const Term& term : terms) {
    if (term.coefficient == 0) continue;  // opposite copies: a sheet collapsed onto itself
    std::array<int, 3> tri = term.sorted;
    if (term.coefficient < 0) std::swap(tri[1], tri[2]);
    for (int& c : tri) {
      if (compact[size_t(c)] < 0) {
        compact[size_t(c)] = int(out.points.size());
        out.points.push_back(sum[size_t(c)] / double(members[size_t(c)]));
      }
      c = compact[size_t(c)];
    }
    out.triangles.push_back(tri);
    out.source_face.push_back(term.source);
  }
  return out;
}

template <size_t N>
ClusteredSurface cluster_faces(const std::vector<Vec3>& points, const std::vector<std::array<int, N>>& faces,
                               const std::vector<double>& priority, const std::vector<char>& keep,
                               const ClusterSurfaceOptions& options) {
  const Triangles t = triangulate(faces);
  const size_t budget = std::max<size_t>(options.max_triangles, 1);
  if (t.corners.size() <= budget) {
    ClusteredSurface out;
    out.points = points;
    out.triangles = t.corners;
    out.source_face = t.face;
    return out;
  }
  const Clusterer clusterer(points, t);

  // Flagged faces, worst first, up to the share of the budget.
  std::vector<size_t> flagged;
  for (size_t f = 0; f < keep.size() && f < faces.size(); ++f)
    if (keep[f]) flagged.push_back(f);
  std::stable_sort(flagged.begin(), flagged.end(), [&](size_t a, size_t b) {
    return !priority.empty() && priority[a] < priority[b];
  });
  size_t kept = std::min(flagged.size(), size_t(options.max_kept_share * double(budget)) / (N - 2));

  std::vector<int> cluster;
  for (;;) {
    std::vector<char> singleton(points.size(), 0);
    for (size_t i = 0; i < kept; ++i)
      for (int v : faces[flagged[i]]) singleton[size_t(v)] = 1;
    // Face count grows about as cells^2 on a surface: rescale toward 95% of the budget,
    // remembering the finest grid that fits.
    size_t cells = std::clamp<size_t>(size_t(std::sqrt(double(budget))), 1, kMaxCells), best = 0;
    for (int attempt = 0; attempt < 12; ++attempt) {
      clusterer.assign(cells, singleton, cluster);
      const size_t count = clusterer.surviving(cluster);
      if (count <= budget && cells > best) best = cells;
      if (count <= budget && count >= budget * 9 / 10) break;
      const double scale = count == 0 ? 2.0 : std::sqrt(0.95 * double(budget) / double(count));
      size_t next = std::clamp<size_t>(size_t(std::lround(double(cells) * scale)), 1, kMaxCells);
      if (next == cells) next = count > budget ? cells - 1 : cells + 1;
      if (next == 0 || next > kMaxCells || (count <= budget && next <= best)) break;
      cells = next;
    }
    // Rare: the count does not fall smoothly with the grid. Halve down to one cell.
    for (size_t c = cells; best == 0 && c >= 1; c /= 2) {
      clusterer.assign(c, singleton, cluster);
      if (clusterer.surviving(cluster) <= budget) best = c;
    }
    if (best > 0) {
      const size_t clusters = clusterer.assign(best, singleton, cluster);
      ClusteredSurface out = build(points, t, cluster, clusters, priority);
      out.grid_cells = best;
      out.kept_faces = kept;
      return out;
    }
    // Even one cell is too much: the kept faces alone overflow. With none kept, one cell
    // leaves at most two clusters, so no triangle at all.
    if (kept == 0) {
      const size_t clusters = clusterer.assign(1, singleton, cluster);
      ClusteredSurface out = build(points, t, cluster, clusters, priority);
      out.grid_cells = 1;
      return out;
    }
    kept /= 2;
  }
}

}  // namespace

ClusteredSurface cluster_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces,
                                 const std::vector<double>& priority, const std::vector<char>& keep,
                                 const ClusterSurfaceOptions& options) {
  return cluster_faces(points, faces, priority, keep, options);
}

ClusteredSurface cluster_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 4>>& faces,
                                 const std::vector<double>& priority, const std::vector<char>& keep,
                                 const ClusterSurfaceOptions& options) {
  return cluster_faces(points, faces, priority, keep, options);
}

}  // namespace dthex
