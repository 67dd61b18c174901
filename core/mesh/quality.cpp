// SPDX-License-Identifier: MIT
#include <dthex/mesh/quality.h>

#include <dthex/mesh/hex_topology.h>

#include <dthex/numerics/inverse_cube_root.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dthex {
namespace {

constexpr double kVerdictDblMin = 2.2250738585072014e-308;  // DBL_MIN, as Verdict compares


double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return a.dot(b.cross(c)); }

}  // namespace

double triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double area2 = (b - a).cross(c - a).norm();  // twice the area
  const double sum_sq = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  if (sum_sq <= 0) return 0.0;
  return 2.0 * std::sqrt(3.0) * area2 / sum_sq;
}

double tet_shape(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  const Vec3 a = p1 - p0, b = p2 - p0, c = p3 - p0;
  const double jacobian = a.cross(b).dot(c);
  if (jacobian < kVerdictDblMin) return 0.0;
  const double num = 3.0 * std::pow(std::sqrt(2.0) * jacobian, 2.0 / 3.0);
  const double den = 1.5 * (a.squaredNorm() + b.squaredNorm() + c.squaredNorm()) - (a.dot(b) + b.dot(c) + c.dot(a));
  if (den < kVerdictDblMin) return 0.0;
  return num / den;
}

double tet_scaled_jacobian(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  const Vec3 e01 = p1 - p0, e02 = p2 - p0, e03 = p3 - p0, e12 = p2 - p1, e13 = p3 - p1, e23 = p3 - p2;
  const double jacobian = e01.cross(e02).dot(e03);
  const double l01 = e01.squaredNorm(), l02 = e02.squaredNorm(), l03 = e03.squaredNorm(), l12 = e12.squaredNorm(),
               l13 = e13.squaredNorm(), l23 = e23.squaredNorm();
  // The largest product of the squared lengths of the three edges at a corner.
  const double largest = std::max({l01 * l02 * l03, l01 * l12 * l13, l02 * l12 * l23, l03 * l13 * l23});
  double product = std::sqrt(largest);
  if (product < std::abs(jacobian)) product = std::abs(jacobian);
  if (product < kVerdictDblMin) return 0.0;
  return std::sqrt(2.0) * jacobian / product;
}

namespace {

// The frames of a hex (its 8 corners, or some of them, and the centre), their determinants
// and squared edge lengths gathered first and their roots and quotients taken after: each
// frame's value is a chain of roots and a division, and independent chains side by side
// run several at once. Verdict's expressions, to a few ulps (the lengths' product is one
// root, see scaled_jacobians()).
struct Frames {
  int count = 0;
  //! Frames past `count` hold 1s: the fixed-length loops below run over all nine.
  double alpha[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1}, sq1[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1},
         sq2[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1}, sq3[9] = {1, 1, 1, 1, 1, 1, 1, 1, 1};

  void add(const Vec3& e1, const Vec3& e2, const Vec3& e3) {
    alpha[count] = det3(e1, e2, e3);
    sq1[count] = e1.squaredNorm(), sq2[count] = e2.squaredNorm(), sq3[count] = e3.squaredNorm();
    ++count;
  }
  void add_corner(const std::array<Vec3, 8>& x, int corner) {
    const auto& k = kHexCornerFrames[corner];
    add(x[size_t(k[1])] - x[size_t(k[0])], x[size_t(k[2])] - x[size_t(k[0])], x[size_t(k[3])] - x[size_t(k[0])]);
  }
  void add_centre(const std::array<Vec3, 8>& x) {
    add((x[1] - x[0]) + (x[2] - x[3]) + (x[5] - x[4]) + (x[6] - x[7]),
        (x[3] - x[0]) + (x[2] - x[1]) + (x[7] - x[4]) + (x[6] - x[5]),
        (x[4] - x[0]) + (x[5] - x[1]) + (x[6] - x[2]) + (x[7] - x[3]));
  }
  //! det / (|e1| |e2| |e3|) of frames [0, count); 0 for a zero-length edge. The lengths'
  //! product is the root of the squared lengths' product, one root instead of three (the
  //! roots were the smoother's bottleneck), in loops without branches that the compiler
  //! runs several frames at a time; where that product is below 1e-150 or above 1e150 (its
  //! square leaves the range of doubles) the lengths are taken one by one.
  void scaled_jacobians(double* sj) const {
    double lengths[9];
    for (int f = 0; f < 9; ++f) lengths[f] = std::sqrt(sq1[f] * sq2[f] * sq3[f]);
    for (int f = 0; f < 9; ++f) sj[f] = alpha[f] / lengths[f];
    for (int f = 0; f < count; ++f) {
      if (lengths[f] > 1e-150 && lengths[f] < 1e150) continue;
      const double separate = std::sqrt(sq1[f]) * std::sqrt(sq2[f]) * std::sqrt(sq3[f]);
      sj[f] = separate <= kVerdictDblMin ? 0.0 : alpha[f] / separate;
    }
  }
  //! Smallest scaled Jacobian over frames [0, count).
  double worst_scaled_jacobian() const {
    double sj[9];
    scaled_jacobians(sj);
    double worst = std::numeric_limits<double>::max();
    for (int f = 0; f < count; ++f) worst = std::min(worst, sj[f]);
    return worst;
  }
  //! Smallest alpha / |J|_F^3 over frames [0, last), or -1 if one of them is inverted
  //! (shape 0). The shape is 3 t^(2/3), monotone in t, so the minimum is taken over t and
  //! the cube root once.
  double worst_t(int last) const {
    for (int f = 0; f < last; ++f)
      if (alpha[f] <= kVerdictDblMin) return -1;
    double t[9];
    for (int f = 0; f < 9; ++f) {
      const double frob_sq = sq1[f] + sq2[f] + sq3[f];
      t[f] = alpha[f] / (frob_sq * std::sqrt(frob_sq));
    }
    double worst = std::numeric_limits<double>::max();
    for (int f = 0; f < last; ++f) worst = std::min(worst, t[f]);
    return worst;
  }
};

}  // namespace

// The hex metrics are the smoother's inner loop: on a processor with AVX2 they run a version
// compiled for it (four frames' roots in one instruction instead of two), chosen once at
// start-up; the same operations on each value, so the same results.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define DTHEX_HEX_METRIC __attribute__((target_clones("avx2", "default")))
#else
#define DTHEX_HEX_METRIC
#endif

namespace {

//! Verdict's shape 3 t^(2/3) = 3 t / t^(1/3); 0 for an inverted frame (t < 0).
double shape_from_t(double worst_t) { return worst_t < 0 ? 0.0 : 3.0 * worst_t * inverse_cube_root(worst_t); }

}  // namespace

DTHEX_HEX_METRIC double hex_shape(const std::array<Vec3, 8>& x) {
  Frames frames;
  for (int k = 0; k < 8; ++k) frames.add_corner(x, k);
  return shape_from_t(frames.worst_t(8));
}

DTHEX_HEX_METRIC double hex_scaled_jacobian(const std::array<Vec3, 8>& x) {
  Frames frames;
  for (int k = 0; k < 8; ++k) frames.add_corner(x, k);
  frames.add_centre(x);
  return std::clamp(frames.worst_scaled_jacobian(), -1.0, 1.0);
}

DTHEX_HEX_METRIC HexScaledJacobianAndShape hex_scaled_jacobian_and_shape(const std::array<Vec3, 8>& x) {
  Frames frames;
  for (int k = 0; k < 8; ++k) frames.add_corner(x, k);
  frames.add_centre(x);
  HexScaledJacobianAndShape q;
  q.scaled_jacobian = std::clamp(frames.worst_scaled_jacobian(), -1.0, 1.0);
  q.shape = shape_from_t(frames.worst_t(8));
  return q;
}

int hex_worst_scaled_jacobian_frame(const std::array<Vec3, 8>& x) {
  Frames frames;
  frames.add_centre(x);
  for (int k = 0; k < 8; ++k) frames.add_corner(x, k);
  double sj[9];
  frames.scaled_jacobians(sj);
  int worst = 8;
  double value = sj[0];
  for (int k = 0; k < 8; ++k)
    if (sj[k + 1] < value) value = sj[k + 1], worst = k;
  return worst;
}

std::array<int, 4> hex_corner_frame_nodes(int corner) {
  const auto& k = kHexCornerFrames[corner];
  return {k[0], k[1], k[2], k[3]};
}

namespace {
// Does corner frame `frame` use node `node` (its own corner or one of its three edges)?
bool frame_uses(int frame, int node) {
  for (int i = 0; i < 4; ++i)
    if (kHexCornerFrames[frame][i] == node) return true;
  return false;
}
}  // namespace

HexWithMovingCorner::HexWithMovingCorner(const std::array<Vec3, 8>& corners, int moving)
    : corners_(corners), moving_(moving) {
  Frames fixed;
  for (int k = 0; k < 8; ++k) {
    if (frame_uses(k, moving)) moving_frames_[size_t(moving_frame_count_++)] = k;
    else fixed.add_corner(corners_, k);
  }
  fixed_sj_ = std::min(fixed_sj_, fixed.worst_scaled_jacobian());
  const double t = fixed.worst_t(fixed.count);
  if (t < 0) fixed_shape_zero_ = true;
  else fixed_t_ = std::min(fixed_t_, t);
  int moving_edge_count = 0;
  for (int e = 0; e < 12; ++e) {
    const auto& edge = kHexEdges[size_t(e)];
    if (edge[0] == moving || edge[1] == moving) {
      moving_edges_[size_t(moving_edge_count++)] = e;
      continue;
    }
    const double l = (corners_[size_t(edge[0])] - corners_[size_t(edge[1])]).squaredNorm();
    fixed_shortest_sq_ = std::min(fixed_shortest_sq_, l);
    fixed_longest_sq_ = std::max(fixed_longest_sq_, l);
  }
}

DTHEX_HEX_METRIC HexScaledJacobianAndShape HexWithMovingCorner::at(const Vec3& position, bool need_shape) {
  corners_[size_t(moving_)] = position;
  Frames frames;
  for (int i = 0; i < moving_frame_count_; ++i) frames.add_corner(corners_, moving_frames_[size_t(i)]);
  frames.add_centre(corners_);
  HexScaledJacobianAndShape q;
  q.scaled_jacobian = std::clamp(std::min(fixed_sj_, frames.worst_scaled_jacobian()), -1.0, 1.0);
  if (need_shape) {
    const double t = fixed_shape_zero_ ? -1 : frames.worst_t(moving_frame_count_);
    q.shape = t < 0 ? 0.0 : shape_from_t(std::min(fixed_t_, t));
  }
  return q;
}

double HexWithMovingCorner::edge_ratio_squared_at(const Vec3& position) const {
  // The same lengths as hex_edge_ratio_squared, and min and max are exact: equal results.
  double shortest = fixed_shortest_sq_, longest = fixed_longest_sq_;
  for (const int e : moving_edges_) {
    const auto& edge = kHexEdges[size_t(e)];
    const Vec3& a = edge[0] == moving_ ? position : corners_[size_t(edge[0])];
    const Vec3& b = edge[1] == moving_ ? position : corners_[size_t(edge[1])];
    const double l = (a - b).squaredNorm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  return longest > 0 ? shortest / longest : 0.0;
}

double hex_edge_ratio_squared(const std::array<Vec3, 8>& corners) {
  double shortest = std::numeric_limits<double>::infinity(), longest = 0;
  for (const auto& e : kHexEdges) {
    const double l = (corners[size_t(e[0])] - corners[size_t(e[1])]).squaredNorm();
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
  }
  return longest > 0 ? shortest / longest : 0.0;
}

std::array<Vec3, 8> hex_corners(const HexMesh& mesh, size_t hex) {
  std::array<Vec3, 8> x;
  for (size_t i = 0; i < 8; ++i) x[i] = mesh.nodes[size_t(mesh.hexes[hex][i])];
  return x;
}

QualityStats summarize(const std::vector<double>& values) {
  QualityStats s;
  s.count = values.size();
  if (values.empty()) return s;
  double sum = 0;
  s.min = values.front();
  s.max = values.front();
  for (double v : values) {
    sum += v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.avg = sum / double(values.size());
  double var = 0;
  for (double v : values) var += (v - s.avg) * (v - s.avg);
  s.std_dev = std::sqrt(var / double(values.size()));
  return s;
}

double hex_gauss_scaled_jacobian(const std::array<Vec3, 8>& x) {
  // VTK's corner signs in (xi, eta, zeta).
  static constexpr int sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  double worst = 1.0;
  for (const auto& p : sign) {
    const double xi = g * p[0], eta = g * p[1], zeta = g * p[2];
    Vec3 d[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (int i = 0; i < 8; ++i) {
      const double a = 1 + xi * sign[i][0], b = 1 + eta * sign[i][1], c = 1 + zeta * sign[i][2];
      d[0] += (sign[i][0] * b * c / 8.0) * x[size_t(i)];
      d[1] += (sign[i][1] * a * c / 8.0) * x[size_t(i)];
      d[2] += (sign[i][2] * a * b / 8.0) * x[size_t(i)];
    }
    const double lengths = d[0].norm() * d[1].norm() * d[2].norm();
    if (!(lengths > 0)) return 0.0;
    worst = std::min(worst, d[0].dot(d[1].cross(d[2])) / lengths);
  }
  return worst;
}

ScaledJacobianTally tally_scaled_jacobians(const HexMesh& mesh, double threshold) {
  const long n = long(mesh.hexes.size());
  double min = std::numeric_limits<double>::infinity();
  size_t below = 0, inverted = 0;
#pragma omp parallel for schedule(static) reduction(min : min) reduction(+ : below, inverted) if (n > 50000)
  for (long h = 0; h < n; ++h) {
    const double sj = hex_scaled_jacobian(hex_corners(mesh, size_t(h)));
    min = std::min(min, sj);
    below += sj < threshold;
    inverted += sj <= 0;
  }
  return {n ? min : 0.0, below, inverted};
}

HexQuality measure_hex_quality(const HexMesh& mesh) {
  HexQuality q;
  const size_t n = mesh.hexes.size();
  q.shape.resize(n);
  q.scaled_jacobian.resize(n);
  size_t inverted = 0, below_0_2 = 0, gauss_inverted = 0;
  double gauss_min = n > 0 ? 1.0 : 0.0;
  // Every hex on its own: split over the cores once there are enough to pay for the threads.
#pragma omp parallel for schedule(static) reduction(+ : inverted, below_0_2, gauss_inverted) \
    reduction(min : gauss_min) if (n > 50000)
  for (long h = 0; h < long(n); ++h) {
    const auto x = hex_corners(mesh, size_t(h));
    q.shape[size_t(h)] = hex_shape(x);
    const double sj = hex_scaled_jacobian(x);
    q.scaled_jacobian[size_t(h)] = sj;
    if (sj <= 0) ++inverted;
    if (sj < 0.2) ++below_0_2;
    const double gauss = hex_gauss_scaled_jacobian(x);
    gauss_min = std::min(gauss_min, gauss);
    if (gauss <= 0) ++gauss_inverted;
  }
  q.inverted = inverted;
  q.below_0_2 = below_0_2;
  q.gauss_inverted = gauss_inverted;
  q.gauss_scaled_jacobian_min = gauss_min;
  q.shape_stats = summarize(q.shape);
  q.scaled_jacobian_stats = summarize(q.scaled_jacobian);
  return q;
}

std::vector<double> triangle_shapes(const TriSurface& s) {
  std::vector<double> out;
  out.reserve(s.triangles.size());
  for (const auto& t : s.triangles)
    out.push_back(triangle_shape(s.points[size_t(t[0])], s.points[size_t(t[1])], s.points[size_t(t[2])]));
  return out;
}

std::vector<double> tet_shapes(const TetMesh& m) {
  std::vector<double> out;
  out.reserve(m.tets.size());
  for (const auto& t : m.tets)
    out.push_back(tet_shape(m.points[size_t(t[0])], m.points[size_t(t[1])], m.points[size_t(t[2])],
                            m.points[size_t(t[3])]));
  return out;
}

std::vector<size_t> histogram(const std::vector<double>& values, size_t bins, double lo, double hi) {
  std::vector<size_t> counts(bins, 0);
  if (bins == 0 || hi <= lo) return counts;
  for (double v : values) {
    const double t = (v - lo) / (hi - lo);
    const long b = std::clamp(long(std::floor(t * double(bins))), 0L, long(bins) - 1);
    counts[size_t(b)]++;
  }
  return counts;
}

}  // namespace dthex
