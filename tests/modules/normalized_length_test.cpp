// SPDX-License-Identifier: MIT
#include <dthex/mesh/quality.h>
#include <dthex/mesh/surface_mesh.h>

#include <dthex/modules/DTHexGeometry.hh>

#include <gtest/gtest.h>

#include <random>

using namespace dthex;

namespace {

//! Simpson's rule for the integral of 1/h along an edge of length d with h linear hA -> hB.
double integrate_inverse_size(double d, double hA, double hB, int n = 2000) {
  auto f = [&](double t) { return 1.0 / (hA + (hB - hA) * t / d); };
  const double step = d / n;
  double sum = f(0) + f(d);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * f(i * step);
  return sum * step / 3;
}

}  // namespace

TEST(NormalizedLength, EqualSizesGiveLengthOverSize) {
  EXPECT_DOUBLE_EQ(normalized_length(3.0, 1.5, 1.5), 2.0);
  EXPECT_DOUBLE_EQ(normalized_length(0.7, 0.35, 0.35), 2.0);
  // The series below |x| = 1e-4 agrees with the closed form (whose own rounding is ~1e-12 there)
  // and tends to the limit d / hA.
  EXPECT_NEAR(normalized_length(1.0, 1.0, 1.0 + 0.99e-4), std::log(1.0 + 0.99e-4) / 0.99e-4, 1e-11);
  EXPECT_NEAR(normalized_length(1.0, 1.0, 1.0 - 0.99e-4), std::log(1.0 - 0.99e-4) / -0.99e-4, 1e-11);
  EXPECT_NEAR(normalized_length(2.0, 4.0, 4.0 * (1 + 1e-9)), 0.5 * (1 - 0.5e-9), 1e-16);
}

TEST(NormalizedLength, MatchesNumericIntegrationOfInverseSize) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> size(0.05, 5.0), length(0.01, 10.0);
  for (int i = 0; i < 100; ++i) {
    const double d = length(rng), hA = size(rng), hB = size(rng);
    const double exact = integrate_inverse_size(d, hA, hB);
    EXPECT_NEAR(normalized_length(d, hA, hB), exact, 1e-7 * exact);
    EXPECT_NEAR(normalized_length(d, hA, hB), normalized_length(d, hB, hA), 1e-12 * exact);  // symmetric
  }
}

TEST(NormalizedLength, ModuleTriangleShapeIsVerdicts) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    EXPECT_NEAR(dthex::triangle_shape(to_openmesh(a), to_openmesh(b), to_openmesh(c)), dthex::triangle_shape(a, b, c),
                1e-12);
  }
  EXPECT_NEAR(dthex::triangle_shape(OpenMesh::Vec3d(0, 0, 0), OpenMesh::Vec3d(1, 0, 0), OpenMesh::Vec3d(0, 1, 0)),
              0.866025, 1e-6);
}
