// SPDX-License-Identifier: MIT
// Element quality as VTK's Verdict defines it, so our numbers agree with the Verdict-based
// referee script (hexeval) and with ParaView: the same formulas, the hex metrics within a few
// ulps (a frame's edge lengths come from one root of their squares' product, the shape's
// cube root from inverse_cube_root.h; both were the smoother's bottleneck).
#pragma once

#include <dthex/mesh/types.h>

#include <limits>

namespace dthex {

//! Verdict triangle shape: 4 sqrt(3) area / (sum of squared edge lengths); 1 equilateral.
double triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c);
//! Verdict tet shape: 1 regular, 0 degenerate or inverted.
double tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
//! Verdict tet scaled Jacobian: sqrt 2 det(b - a, c - a, d - a) over the largest product of
//! the three edge lengths at a corner; 1 regular, 0 flat, negative inverted. THex gives each
//! tet corner a hex corner with the same three edges, so it bounds those hexes as they start.
double tet_scaled_jacobian(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
//! Verdict hex shape: min over the 8 corners of 3 det(A)^(2/3) / |A|_F^2; 0 if any corner is inverted.
double hex_shape(const std::array<Vec3, 8>& corners);
//! Verdict hex scaled Jacobian: min over the 8 corners and the centre of
//! det(A) / (|a1| |a2| |a3|), in [-1, 1]. Verdict returns 1e30 when an edge has zero
//! length; we return 0 there (the element is degenerate).
double hex_scaled_jacobian(const std::array<Vec3, 8>& corners);

//! The scaled Jacobian at the 2x2x2 Gauss points of the trilinear map (xi, eta, zeta = +-1/sqrt 3):
//! min over the eight of det(J) / (|J1| |J2| |J3|), J's columns the map's derivatives, in
//! [-1, 1]; 0 when a column vanishes. A solver integrates there, and FEBio refuses a model with
//! det(J) <= 0 at any of them, which a hex valid at its corners never has but a warped one can.
double hex_gauss_scaled_jacobian(const std::array<Vec3, 8>& corners);

//! Both of the above from one pass over the nine Jacobians (the smoother's inner loop
//! needs both for every trial position); bit-identical to calling them separately.
struct HexScaledJacobianAndShape {
  double scaled_jacobian = 0, shape = 0;
};
HexScaledJacobianAndShape hex_scaled_jacobian_and_shape(const std::array<Vec3, 8>& corners);

//! The square of a hex's shortest edge over its longest (0 if every edge has zero length):
//! what the scaled Jacobian is blind to. Verdict's shape sees it (a box of edges 1, 1, r has
//! shape about 2r), the scaled Jacobian does not (1 at any r).
double hex_edge_ratio_squared(const std::array<Vec3, 8>& corners);

//! Where a hex's scaled Jacobian is taken: the corner (0-7) whose frame is the smallest,
//! or 8 for the centre frame. Only the nodes of that frame can raise it.
int hex_worst_scaled_jacobian_frame(const std::array<Vec3, 8>& corners);
//! The nodes (local indices) of corner frame `corner` (0-7): the corner and its three
//! edge neighbours.
std::array<int, 4> hex_corner_frame_nodes(int corner);

//! A hex one of whose corners moves while the other seven stay: the four corner frames
//! that do not touch the moving corner are evaluated once, so each trial position costs
//! four frames and the centre instead of nine. at(x) equals
//! hex_scaled_jacobian_and_shape(corners with [moving] = x) exactly (the shape is 0 when
//! need_shape is false).
class HexWithMovingCorner {
 public:
  HexWithMovingCorner(const std::array<Vec3, 8>& corners, int moving);
  HexScaledJacobianAndShape at(const Vec3& position, bool need_shape = true);
  //! hex_edge_ratio_squared of the hex with the moving corner at `position`.
  double edge_ratio_squared_at(const Vec3& position) const;

 private:
  std::array<Vec3, 8> corners_;
  int moving_ = 0;
  std::array<int, 4> moving_frames_{};
  int moving_frame_count_ = 0;
  double fixed_sj_ = std::numeric_limits<double>::max();
  double fixed_t_ = std::numeric_limits<double>::max();
  bool fixed_shape_zero_ = false;
  //! The nine edges away from the moving corner: their shortest and longest (squared), and
  //! the three others (their indices in the hex's edge list).
  double fixed_shortest_sq_ = std::numeric_limits<double>::infinity(), fixed_longest_sq_ = 0;
  std::array<int, 3> moving_edges_{};
};

std::array<Vec3, 8> hex_corners(const HexMesh& mesh, size_t hex);

//! avg / population std dev / min / max, as in the paper's tables (and numpy.std).
struct QualityStats {
  size_t count = 0;
  double avg = 0, std_dev = 0, min = 0, max = 0;
};
QualityStats summarize(const std::vector<double>& values);

struct HexQuality {
  std::vector<double> shape;            //!< per hex
  std::vector<double> scaled_jacobian;  //!< per hex
  QualityStats shape_stats, scaled_jacobian_stats;
  size_t inverted = 0;      //!< scaled Jacobian <= 0
  size_t below_0_2 = 0;     //!< scaled Jacobian < 0.2
  double gauss_scaled_jacobian_min = 0;  //!< min over hexes of hex_gauss_scaled_jacobian
  size_t gauss_inverted = 0;             //!< hexes with det(J) <= 0 at a Gauss point
};
HexQuality measure_hex_quality(const HexMesh& mesh);

//! The smallest scaled Jacobian of `mesh`'s hexes (0 without hexes), how many lie below
//! `threshold` and how many are inverted (<= 0): one pass, on both cores for large meshes,
//! for the stages that only need these (no per-hex values kept).
struct ScaledJacobianTally {
  double min = 0;
  size_t below = 0, inverted = 0;
};
ScaledJacobianTally tally_scaled_jacobians(const HexMesh& mesh, double threshold);

std::vector<double> triangle_shapes(const TriSurface& surface);
std::vector<double> tet_shapes(const TetMesh& mesh);

//! Counts of values in `bins` equal-width bins over [lo, hi]; values outside are clamped.
std::vector<size_t> histogram(const std::vector<double>& values, size_t bins, double lo = 0.0, double hi = 1.0);

}  // namespace dthex
