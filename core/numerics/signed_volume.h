// SPDX-License-Identifier: MIT
// Six times the signed volume of the tet (a, b, c, d): positive when d lies on the side of
// triangle abc that its right-hand normal points to. The orientation test of the surface
// checks, the tet set-up and the coarsening's intersection test; one expression everywhere,
// so that they agree to the bit on the same four points.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dthex {

inline double signed_volume6(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d) {
  return (b - a).cross(c - a).dot(d - a);
}

}  // namespace dthex
