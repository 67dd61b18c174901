// SPDX-License-Identifier: MIT
// Binned-SAH bounding-box tree over triangles. The tree is built top-down with an explicit
// work list (no recursion, so a degenerate input cannot overflow the stack) and traversed
// iteratively; leaves hold at most kLeafSize triangles.
#include <dthex/mesh/triangle_bvh.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dthex {

namespace {

constexpr int kLeafSize = 4;
constexpr int kBins = 16;

double half_area(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return 0.0;
  const Vec3 d = box.sizes();
  return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
}

//! Boxes that only touch count as overlapping: triangles sharing a vertex must be reported.
bool boxes_overlap(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  return (a.min().array() <= b.max().array()).all() && (b.min().array() <= a.max().array()).all();
}

//! Whether every unit normal n in node `index`'s box has n . direction >= max_cos (with a
//! margin far above the rounding of either side), so that no triangle there is accepted.
bool faces_away(const TriangleBvh::Facing* facing, int index) {
  const std::array<float, 6>& b = (*facing->bounds)[size_t(index)];
  double smallest = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = facing->direction[k];
    smallest += std::min(double(b[size_t(k)]) * d, double(b[size_t(k) + 3]) * d);
  }
  return smallest > facing->max_cos + 1e-6;
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;  // vertex region a

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;  // vertex region b

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge region ab
    const double denom = d1 - d3;
    return denom > 0 ? Vec3(a + (d1 / denom) * ab) : a;
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;  // vertex region c

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge region ac
    const double denom = d2 - d6;
    return denom > 0 ? Vec3(a + (d2 / denom) * ac) : a;
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge region bc
    const double denom = (d4 - d3) + (d5 - d6);
    return denom > 0 ? Vec3(b + ((d4 - d3) / denom) * (c - b)) : b;
  }

  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // Degenerate (zero-area) triangle that fell through: take the best of its three edges.
    auto on_segment = [&](const Vec3& s, const Vec3& e) -> Vec3 {
      const Vec3 d = e - s;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
      return s + t * d;
    };
    Vec3 best = on_segment(a, b);
    for (const Vec3& q : {on_segment(b, c), on_segment(c, a)})
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
  }
  const double v = vb / sum, w = vc / sum;  // interior
  return a + v * ab + w * ac;
}

TriangleBvh::TriangleBvh(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles)
    : points_(points), triangles_(triangles) {
  const int n = int(triangles_.size());
  order_.resize(size_t(n));
  for (int i = 0; i < n; ++i) order_[size_t(i)] = i;
  if (n == 0) return;

  boxes_.resize(size_t(n));
  std::vector<Vec3> centroids(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto& t = triangles_[size_t(i)];
    Eigen::AlignedBox3d box(points_[size_t(t[0])]);
    box.extend(points_[size_t(t[1])]);
    box.extend(points_[size_t(t[2])]);
    boxes_[size_t(i)] = box;
    centroids[size_t(i)] = box.center();
  }

  nodes_.reserve(size_t(2 * (n / kLeafSize + 1)));
  nodes_.emplace_back();
  nodes_[0].first = 0;
  nodes_[0].count = n;
  std::vector<int> work{0};

  struct Bin {
    Eigen::AlignedBox3d box;
    int count = 0;
  };

  while (!work.empty()) {
    const int index = work.back();
    work.pop_back();
    const int first = nodes_[size_t(index)].first, count = nodes_[size_t(index)].count;

    Eigen::AlignedBox3d box, centroid_box;
    for (int k = first; k < first + count; ++k) {
      box.extend(boxes_[size_t(order_[size_t(k)])]);
      centroid_box.extend(centroids[size_t(order_[size_t(k)])]);
    }
    nodes_[size_t(index)].box = box;
    if (count <= kLeafSize) continue;

    int axis;
    const Vec3 extent = centroid_box.sizes();
    const double max_extent = extent.maxCoeff(&axis);
    int* begin = order_.data() + first;
    int* end = begin + count;
    int* middle = nullptr;

    if (max_extent > 0) {
      // Binned surface-area heuristic along the widest centroid axis.
      Bin bins[kBins];
      const double lo = centroid_box.min()[axis];
      const double scale = kBins / max_extent;
      auto bin_of = [&](int t) {
        return std::min(kBins - 1, int((centroids[size_t(t)][axis] - lo) * scale));
      };
      for (int* it = begin; it != end; ++it) {
        Bin& bin = bins[bin_of(*it)];
        bin.box.extend(boxes_[size_t(*it)]);
        ++bin.count;
      }
      double right_cost[kBins];
      Eigen::AlignedBox3d acc;
      int acc_count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bins[b].box);
        acc_count += bins[b].count;
        right_cost[b] = acc_count ? half_area(acc) * acc_count : 0.0;
      }
      acc.setEmpty();
      acc_count = 0;
      double best_cost = std::numeric_limits<double>::infinity();
      int best_split = -1;
      for (int b = 1; b < kBins; ++b) {
        acc.extend(bins[b - 1].box);
        acc_count += bins[b - 1].count;
        if (acc_count == 0 || acc_count == count) continue;
        const double cost = half_area(acc) * acc_count + right_cost[b];
        if (cost < best_cost) {
          best_cost = cost;
          best_split = b;
        }
      }
      if (best_split > 0)
        middle = std::partition(begin, end, [&](int t) { return bin_of(t) < best_split; });
    }
    if (middle == nullptr || middle == begin || middle == end) {
      // All centroids coincide (or binning failed): split at the median to keep leaves small.
      middle = begin + count / 2;
      std::nth_element(begin, middle, end, [&](int a, int b) {
        return centroids[size_t(a)][axis] < centroids[size_t(b)][axis];
      });
    }

    const int left_count = int(middle - begin);
    const int left = int(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[size_t(left)].first = first;
    nodes_[size_t(left)].count = left_count;
    nodes_[size_t(left) + 1].first = first + left_count;
    nodes_[size_t(left) + 1].count = count - left_count;
    nodes_[size_t(index)].left = left;
    nodes_[size_t(index)].right = left + 1;
    work.push_back(left);
    work.push_back(left + 1);
  }
}

const Eigen::AlignedBox3d& TriangleBvh::bounds() const {
  static const Eigen::AlignedBox3d empty;
  return nodes_.empty() ? empty : nodes_[0].box;
}

TriangleBvh::ClosestPoint TriangleBvh::closest_point(const Vec3& q) const { return search(q, nullptr, -1); }

TriangleBvh::ClosestPoint TriangleBvh::closest_point(const Vec3& q,
                                                     const std::function<bool(int)>& accept) const {
  return search(q, accept ? &accept : nullptr, -1);
}

TriangleBvh::ClosestPoint TriangleBvh::closest_point_within(const Vec3& q, double max_distance,
                                                            const std::function<bool(int)>& accept,
                                                            const Facing* facing) const {
  return search(q, accept ? &accept : nullptr, -1, max_distance * max_distance, facing);
}

TriangleBvh::NormalBounds TriangleBvh::normal_bounds() const {
  NormalBounds bounds(nodes_.size());
  // Children come after their parent in nodes_: from the back, each node's children are done.
  for (size_t i = nodes_.size(); i-- > 0;) {
    const Node& node = nodes_[i];
    std::array<float, 6>& b = bounds[i];
    if (node.left >= 0) {
      const auto &l = bounds[size_t(node.left)], &r = bounds[size_t(node.right)];
      for (int k = 0; k < 3; ++k) {
        b[size_t(k)] = std::min(l[size_t(k)], r[size_t(k)]);
        b[size_t(k) + 3] = std::max(l[size_t(k) + 3], r[size_t(k) + 3]);
      }
      continue;
    }
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int k = node.first; k < node.first + node.count; ++k) {
      const auto& t = triangles_[size_t(order_[size_t(k)])];
      const Vec3 cross = (points_[size_t(t[1])] - points_[size_t(t[0])]).cross(points_[size_t(t[2])] - points_[size_t(t[0])]);
      const double length = cross.norm();
      const Vec3 normal = length > 0 ? Vec3(cross / length) : Vec3::Zero();
      lo = lo.cwiseMin(normal);
      hi = hi.cwiseMax(normal);
    }
    for (int k = 0; k < 3; ++k) {
      b[size_t(k)] = std::nextafter(float(lo[k]), -2.0f);
      b[size_t(k) + 3] = std::nextafter(float(hi[k]), 2.0f);
    }
  }
  return bounds;
}

TriangleBvh::ClosestPoint TriangleBvh::closest_point_near(const Vec3& q, int hint) const {
  return search(q, nullptr, hint);
}

TriangleBvh::ClosestPoint TriangleBvh::search(const Vec3& q, const std::function<bool(int)>* accept, int hint,
                                              double max_distance_sq, const Facing* facing) const {
  ClosestPoint best;
  best.distance_sq = max_distance_sq;
  if (nodes_.empty()) {
    best.distance_sq = 0;
    return best;
  }
  auto try_triangle = [&](int t) {
    const auto& tri = triangles_[size_t(t)];
    const Vec3 p = closest_point_on_triangle(q, points_[size_t(tri[0])], points_[size_t(tri[1])],
                                             points_[size_t(tri[2])]);
    const double d = (p - q).squaredNorm();
    if (d < best.distance_sq) {
      best.distance_sq = d;
      best.point = p;
      best.triangle = t;
    }
  };
  if (hint >= 0 && size_t(hint) < triangles_.size()) try_triangle(hint);
  // Stack of (node, squared box distance); the nearer child is pushed last so it is visited
  // first. Reused per thread: a heap allocation per query cost more than the search.
  thread_local std::vector<std::pair<int, double>> stack;
  stack.clear();
  stack.emplace_back(0, nodes_[0].box.squaredExteriorDistance(q));
  while (!stack.empty()) {
    const auto [index, box_distance_sq] = stack.back();
    stack.pop_back();
    if (box_distance_sq > best.distance_sq) continue;
    if (facing && faces_away(facing, index)) continue;
    const Node& node = nodes_[size_t(index)];
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k) {
        const int t = order_[size_t(k)];
        if (accept && !(*accept)(t)) continue;
        try_triangle(t);
      }
      continue;
    }
    const double dl = nodes_[size_t(node.left)].box.squaredExteriorDistance(q);
    const double dr = nodes_[size_t(node.right)].box.squaredExteriorDistance(q);
    if (dl <= dr) {
      if (dr <= best.distance_sq) stack.emplace_back(node.right, dr);
      if (dl <= best.distance_sq) stack.emplace_back(node.left, dl);
    } else {
      if (dl <= best.distance_sq) stack.emplace_back(node.left, dl);
      if (dr <= best.distance_sq) stack.emplace_back(node.right, dr);
    }
  }
  if (best.triangle < 0) best.distance_sq = 0;
  return best;
}

void TriangleBvh::for_each_in_box(const Eigen::AlignedBox3d& box, const std::function<void(int)>& visit) const {
  if (nodes_.empty() || box.isEmpty()) return;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& node = nodes_[size_t(stack.back())];
    stack.pop_back();
    if (!boxes_overlap(node.box, box)) continue;
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k) {
        const int t = order_[size_t(k)];
        if (boxes_overlap(boxes_[size_t(t)], box)) visit(t);
      }
    } else {
      stack.push_back(node.left);
      stack.push_back(node.right);
    }
  }
}

bool TriangleBvh::split_pair_part(const std::array<int, 2>& part, std::vector<std::array<int, 2>>& out) const {
  const auto [ia, ib] = part;
  const Node& a = nodes_[size_t(ia)];
  const Node& b = nodes_[size_t(ib)];
  if (ia == ib) {
    if (a.left < 0) return false;
    out.push_back({a.left, a.left});
    out.push_back({a.right, a.right});
    out.push_back({a.left, a.right});
    return true;
  }
  if (!boxes_overlap(a.box, b.box)) return true;  // no pair in it
  const bool a_leaf = a.left < 0, b_leaf = b.left < 0;
  if (a_leaf && b_leaf) return false;
  if (b_leaf || (!a_leaf && half_area(a.box) >= half_area(b.box))) {
    out.push_back({a.left, ib});
    out.push_back({a.right, ib});
  } else {
    out.push_back({ia, b.left});
    out.push_back({ia, b.right});
  }
  return true;
}

void TriangleBvh::for_each_overlapping_pair(const std::function<void(int, int)>& visit) const {
  if (nodes_.empty()) return;
  for_each_overlapping_pair_in({0, 0}, visit);
}

std::vector<std::array<int, 2>> TriangleBvh::overlapping_pair_parts(size_t pieces) const {
  std::vector<std::array<int, 2>> parts;
  if (nodes_.empty()) return parts;
  parts.push_back({0, 0});
  // Breadth first, so the parts are of about equal depth; a split that finds no overlap
  // drops its part.
  for (bool split = true; split && parts.size() < pieces;) {
    split = false;
    std::vector<std::array<int, 2>> next;
    for (const auto& part : parts)
      if (split_pair_part(part, next)) split = true;
      else next.push_back(part);
    parts.swap(next);
  }
  return parts;
}

void TriangleBvh::for_each_overlapping_pair_in(const std::array<int, 2>& part,
                                               const std::function<void(int, int)>& visit) const {
  auto report = [&](int a, int b) {
    if (boxes_overlap(boxes_[size_t(a)], boxes_[size_t(b)])) visit(std::min(a, b), std::max(a, b));
  };
  // Simultaneous descent: (n, n) covers pairs inside one subtree, (a, b) with a != b pairs
  // across two disjoint subtrees, so every unordered triangle pair is considered exactly once.
  std::vector<std::array<int, 2>> stack{part};
  while (!stack.empty()) {
    const std::array<int, 2> item = stack.back();
    stack.pop_back();
    if (split_pair_part(item, stack)) continue;
    const Node& a = nodes_[size_t(item[0])];
    const Node& b = nodes_[size_t(item[1])];
    if (item[0] == item[1]) {
      for (int i = a.first; i < a.first + a.count; ++i)
        for (int j = i + 1; j < a.first + a.count; ++j) report(order_[size_t(i)], order_[size_t(j)]);
    } else {
      for (int i = a.first; i < a.first + a.count; ++i)
        for (int j = b.first; j < b.first + b.count; ++j) report(order_[size_t(i)], order_[size_t(j)]);
    }
  }
}

}  // namespace dthex
