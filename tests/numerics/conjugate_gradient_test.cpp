// SPDX-License-Identifier: MIT
#include <dthex/numerics/conjugate_gradient.h>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace dthex;

namespace {

//! The 1D Laplacian plus a diagonal shift, tridiagonal: SPD, diagonal 2 + shift[u], -1 off it.
struct Tridiagonal {
  std::vector<double> shift;
  size_t size() const { return shift.size(); }
  double diagonal(size_t u) const { return 2 + shift[u]; }
  template <size_t K>
  void multiply_row(size_t u, const double* p, std::array<double, K>& s) const {
    for (size_t c = 0; c < K; ++c) {
      s[c] = diagonal(u) * p[K * u + c];
      if (u > 0) s[c] -= p[K * (u - 1) + c];
      if (u + 1 < size()) s[c] -= p[K * (u + 1) + c];
    }
  }
  //! A x, one system.
  std::vector<double> times(const std::vector<double>& x) const {
    std::vector<double> y(size());
    std::array<double, 1> s;
    for (size_t u = 0; u < size(); ++u) multiply_row(u, x.data(), s), y[u] = s[0];
    return y;
  }
};

std::vector<double> known_solution(size_t n, double phase) {
  std::vector<double> x(n);
  for (size_t u = 0; u < n; ++u) x[u] = std::sin(0.1 * double(u) + phase) + 0.01 * double(u);
  return x;
}

}  // namespace

// b = A x* for a known x*: the solve returns x* to the tolerance and says it converged.
TEST(ConjugateGradient, SolvesSpdSystemWithKnownSolution) {
  Tridiagonal a{std::vector<double>(200, 0.01)};
  const std::vector<double> expected = known_solution(200, 0.3), b = a.times(expected);
  ConjugateGradientOptions options;
  options.tolerance = 1e-12;
  ConjugateGradientReport report;
  const std::vector<double> x =
      solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b[u]; }, options, &report);
  ASSERT_EQ(x.size(), 200u);
  EXPECT_TRUE(report.converged);
  EXPECT_GT(report.iterations, 10);
  for (size_t u = 0; u < 200; ++u) EXPECT_NEAR(x[u], expected[u], 1e-8) << u;
}

// Too few iterations: not converged, and the report says so.
TEST(ConjugateGradient, ReportsNonConvergence) {
  Tridiagonal a{std::vector<double>(200, 0.0)};
  const std::vector<double> b = a.times(known_solution(200, 0.0));
  ConjugateGradientOptions options;
  options.max_iterations = 5;
  ConjugateGradientReport report;
  solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b[u]; }, options, &report);
  EXPECT_EQ(report.iterations, 5);
  EXPECT_FALSE(report.converged);
}

// A diagonal spread over six orders of magnitude: Jacobi preconditioning makes the matrix
// the identity plus a small coupling and converges in a few iterations; plain CG needs many
// more. Both reach the tolerance.
TEST(ConjugateGradient, JacobiBeatsNoneOnBadlyScaledDiagonal) {
  std::vector<double> shift(100);
  for (size_t u = 0; u < shift.size(); ++u) shift[u] = std::pow(10.0, 6.0 * double(u) / 99.0);
  Tridiagonal a{shift};
  const std::vector<double> expected = known_solution(100, 1.0), b = a.times(expected);
  ConjugateGradientOptions options;
  options.tolerance = 1e-10;
  ConjugateGradientReport with, without;
  const auto x_with = solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b[u]; }, options, &with);
  options.jacobi = false;
  const auto x_without = solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b[u]; }, options, &without);
  EXPECT_TRUE(with.converged);
  EXPECT_TRUE(without.converged);
  EXPECT_LT(with.iterations * 3, without.iterations);
  // Both meet the contract: |b - A x| <= tolerance |b| (up to rounding).
  auto relative_residual = [&](const std::vector<double>& x) {
    const std::vector<double> ax = a.times(x);
    double r2 = 0, b2 = 0;
    for (size_t u = 0; u < 100; ++u) r2 += (b[u] - ax[u]) * (b[u] - ax[u]), b2 += b[u] * b[u];
    return std::sqrt(r2 / b2);
  };
  EXPECT_LT(relative_residual(x_with), 2e-10);
  EXPECT_LT(relative_residual(x_without), 2e-10);
}

// Two systems solved together give bit for bit what each gives alone (the recurrences are
// independent; a system that has converged stops changing while the other goes on).
TEST(ConjugateGradient, SystemsSolvedTogetherMatchAlone) {
  Tridiagonal a{std::vector<double>(150, 0.05)};
  const std::vector<double> b0 = a.times(known_solution(150, 0.0));
  std::vector<double> b1(150, 0.0);
  b1[75] = 1;  // a different spectrum content: converges at another iteration
  ConjugateGradientOptions options;
  options.tolerance = 1e-9;
  const auto both = solve_conjugate_gradient<2>(a, [&](size_t u, size_t c) { return c == 0 ? b0[u] : b1[u]; }, options);
  const auto x0 = solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b0[u]; }, options);
  const auto x1 = solve_conjugate_gradient<1>(a, [&](size_t u, size_t) { return b1[u]; }, options);
  for (size_t u = 0; u < 150; ++u) {
    EXPECT_EQ(both[2 * u], x0[u]);
    EXPECT_EQ(both[2 * u + 1], x1[u]);
  }
}

// A zero right-hand side gives zero without an iteration.
TEST(ConjugateGradient, ZeroRightHandSide) {
  Tridiagonal a{std::vector<double>(10, 0.0)};
  ConjugateGradientReport report;
  const auto x =
      solve_conjugate_gradient<1>(a, [](size_t, size_t) { return 0.0; }, ConjugateGradientOptions(), &report);
  EXPECT_EQ(report.iterations, 0);
  EXPECT_TRUE(report.converged);
  for (double v : x) EXPECT_EQ(v, 0.0);
}
