// SPDX-License-Identifier: MIT
// Axis-aligned bounding-box tree over a triangle surface: closest-point queries
// (projection onto the input surface) and overlap queries (self-intersection checks).
#pragma once

#include <dthex/mesh/types.h>

#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <limits>
#include <vector>

namespace dthex {

class TriangleBvh {
 public:
  struct ClosestPoint {
    int triangle = -1;     //!< -1 when no triangle was accepted
    Vec3 point = Vec3::Zero();
    double distance_sq = 0;
  };

  //! Builds the tree; the point and triangle arrays are copied.
  TriangleBvh(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles);
  explicit TriangleBvh(const TriSurface& surface) : TriangleBvh(surface.points, surface.triangles) {}

  //! Closest point of the whole surface to q.
  ClosestPoint closest_point(const Vec3& q) const;
  //! Closest point among the triangles for which accept(triangle) is true
  //! (e.g. only triangles whose normal faces the same way as a coarse facet).
  ClosestPoint closest_point(const Vec3& q, const std::function<bool(int)>& accept) const;
  //! Per tree node, the box of its triangles' unit normals ((b - a) x (c - a) normalized, zero
  //! for a degenerate triangle), rounded outward to single precision (24 bytes a node).
  //! Made on demand, for searches that take only triangles facing one way (Facing).
  using NormalBounds = std::vector<std::array<float, 6>>;
  NormalBounds normal_bounds() const;
  //! A promise about `accept` that lets a search skip every subtree whose triangles all face
  //! the wrong way without asking it: accept(t) is false whenever unit_normal(t) . direction
  //! >= max_cos. The answer is the same as without it (only time is saved).
  struct Facing {
    const NormalBounds* bounds = nullptr;  //!< normal_bounds() of this tree
    Vec3 direction = Vec3::Zero();
    double max_cos = 0;
  };

  //! Closest accepted point no further than `max_distance` from q (triangle -1 if there is
  //! none): the search never leaves that ball, however far the nearest accepted triangle is.
  ClosestPoint closest_point_within(const Vec3& q, double max_distance, const std::function<bool(int)>& accept,
                                    const Facing* facing = nullptr) const;
  //! Closest point of the whole surface to q, starting from triangle `hint` (e.g. the
  //! answer for a nearby point): its distance bounds the search, so coherent query
  //! sequences visit far fewer boxes. The distance found does not depend on the hint.
  ClosestPoint closest_point_near(const Vec3& q, int hint) const;

  //! Calls visit(t) for every triangle whose box overlaps box.
  void for_each_in_box(const Eigen::AlignedBox3d& box, const std::function<void(int)>& visit) const;
  //! Calls visit(a, b) once for every pair a < b of triangles whose boxes overlap.
  void for_each_overlapping_pair(const std::function<void(int, int)>& visit) const;
  //! The work of for_each_overlapping_pair cut into about `pieces` independent parts (fewer
  //! for a small tree): for_each_overlapping_pair_in(part, visit) over every part visits
  //! each pair exactly once, so the parts can go to different threads.
  std::vector<std::array<int, 2>> overlapping_pair_parts(size_t pieces) const;
  void for_each_overlapping_pair_in(const std::array<int, 2>& part, const std::function<void(int, int)>& visit) const;

  size_t size() const { return triangles_.size(); }
  //! The surface the tree was built on (the untangler reads triangle normals from it).
  const std::vector<Vec3>& points() const { return points_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const Eigen::AlignedBox3d& bounds() const;

 private:
  ClosestPoint search(const Vec3& q, const std::function<bool(int)>* accept, int hint,
                      double max_distance_sq = std::numeric_limits<double>::infinity(),
                      const Facing* facing = nullptr) const;
  //! One step of the simultaneous descent of for_each_overlapping_pair: the parts that
  //! (ia, ib) splits into go to `out`; false if it is a pair of leaves (or a leaf with
  //! itself), whose triangle pairs are visited directly.
  bool split_pair_part(const std::array<int, 2>& part, std::vector<std::array<int, 2>>& out) const;

  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  //!< children, -1 for a leaf
    int first = 0, count = 0;   //!< leaf range in order_
  };
  std::vector<Vec3> points_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  std::vector<Eigen::AlignedBox3d> boxes_;  //!< per triangle (indexed by triangle id)
};

//! Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace dthex
