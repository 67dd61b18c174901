// SPDX-License-Identifier: MIT
// Plain formulas the DTHex Decimater modules share: sizing factor, osculating radius,
// normalized edge length, triangle shape. Header-only, OpenMesh-free apart from the
// point type being any vector with operator-, |, % and norm() (OpenMesh::VectorT).
#pragma once

#include <cmath>
#include <limits>
#include <string>

namespace dthex {

//! Name of the per-vertex double property holding the sizing field h (target edge length).
//! ModCurvatureSizingT writes it in initialize(); ModNormalizedLengthT, ModEdgeSwapT and
//! ModLocalSmoothingT read it; apps may read or overwrite it before decimating.
inline const char* size_property_name() { return "v:dthex_size"; }
//! Name of the mesh property (std::vector<VertexHandle>) in which post-collapse modules list
//! the vertices they moved or whose edges they flipped, so a decimater can re-queue them.
inline const char* touched_property_name() { return "m:dthex_touched"; }

//! Degrees to radians.
inline double deg_to_rad(double deg) { return deg * 3.14159265358979323846 / 180.0; }

//! Chord-to-radius factor: a chord of length alpha * rho of a circle of radius rho has
//! sagitta eps * rho. alpha = 2 sqrt(eps (2 - eps)); eps is clamped to (0, 1].
inline double sizing_alpha(double eps) {
  eps = std::fmin(std::fmax(eps, 1e-12), 1.0);
  return 2.0 * std::sqrt(eps * (2.0 - eps));
}

//! Radius of the circle through P and Q tangent at P to the plane with unit normal n:
//! rho = |PQ| / (2 |cos theta|), cos theta = (PQ . n) / |PQ|. Infinite for a tangent edge.
template <class Point>
double osculating_radius(const Point& p, const Point& n, const Point& q) {
  const Point d = q - p;
  const double len = d.norm();
  const double c = std::fabs(double(d | n));  // = |PQ| |cos theta|
  if (len <= 0 || c <= 1e-300) return std::numeric_limits<double>::infinity();
  return len * len / (2.0 * c);
}

//! Length of an edge of Euclidean length d measured in the sizing field, h varying linearly
//! from hA to hB along it: the integral of 1/h = d ln(hB/hA) / (hB - hA); d/hA when equal
//! (a series in x = (hB-hA)/hA avoids the 0/0 near there).
inline double normalized_length(double d, double hA, double hB) {
  const double x = (hB - hA) / hA;
  if (std::fabs(x) < 1e-4) return d / hA * (1.0 - x / 2.0 + x * x / 3.0 - x * x * x / 4.0);
  return d * std::log(hB / hA) / (hB - hA);
}

//! Verdict triangle shape (1/condition number): 4 sqrt(3) area / (sum of squared edge
//! lengths); 1 equilateral, 0 degenerate. Same formula as dthex::triangle_shape in core/.
template <class Point>
double triangle_shape(const Point& a, const Point& b, const Point& c) {
  const Point e0 = b - a, e1 = c - b, e2 = a - c;
  const double denom = double(e0.sqrnorm() + e1.sqrnorm() + e2.sqrnorm());
  if (denom <= 0) return 0.0;
  return 2.0 * std::sqrt(3.0) * double((e0 % (c - a)).norm()) / denom;
}

//! Unnormalized normal (twice the area) of triangle a, b, c.
template <class Point>
Point triangle_normal(const Point& a, const Point& b, const Point& c) {
  return (b - a) % (c - a);
}

}  // namespace dthex
