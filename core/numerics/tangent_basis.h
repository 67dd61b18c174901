// SPDX-License-Identifier: MIT
// Two unit tangents spanning the plane normal to a unit vector: the axes in which a boundary
// node slides on the surface (the smoothers' compass directions, the untangler's and the
// regions' two variables of a sliding node). The pair is fixed for a given normal, built
// from whichever of x and y is further from it.
#pragma once

#include <dthex/mesh/types.h>

#include <array>
#include <cmath>

namespace dthex {

//! t1, t2 with t1, t2 and `normal` orthonormal (normal must be a unit vector).
inline std::array<Vec3, 2> tangent_basis(const Vec3& normal) {
  const Vec3 helper = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 t1 = normal.cross(helper).normalized();
  return {t1, normal.cross(t1)};
}

}  // namespace dthex
