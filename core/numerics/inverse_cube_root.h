// SPDX-License-Identifier: MIT
// x^(-1/3) without std::cbrt, which was a large share of the untangler's and the smoother's
// time: a bit-level first guess (3.5% off) and four Newton steps reach full double
// precision (within three ulps of 1 / cbrt(x), 7e-16 relative).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace dthex {

inline double inverse_cube_root(double x) {
  if (!(x > 1e-290 && x < 1e290)) return 1.0 / std::cbrt(x);  // zero, huge, subnormal, inf, NaN
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = 0x553EF0FF289DD796ULL - bits / 3;
  double y;
  std::memcpy(&y, &bits, sizeof y);
  for (int i = 0; i < 4; ++i) y *= (4.0 - x * y * y * y) * (1.0 / 3.0);
  return y;
}

}  // namespace dthex
