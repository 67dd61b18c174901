// SPDX-License-Identifier: MIT
#include <dthex/numerics/lbfgs.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

using namespace dthex;

namespace {

double rosenbrock(const Eigen::VectorXd& z, Eigen::VectorXd& g) {
  const double a = 1 - z[0], b = z[1] - z[0] * z[0];
  g[0] = -2 * a - 400 * z[0] * b;
  g[1] = 200 * b;
  return a * a + 100 * b * b;
}

//! sum of w_i (z_i - c_i)^2, weights spread over four orders of magnitude.
struct Quadratic {
  Eigen::VectorXd w, c;
  explicit Quadratic(int n) : w(n), c(n) {
    for (int i = 0; i < n; ++i) w[i] = std::pow(10.0, 4.0 * i / (n - 1)), c[i] = std::sin(i + 1.0);
  }
  double operator()(const Eigen::VectorXd& z, Eigen::VectorXd& g) const {
    g = 2 * w.cwiseProduct(z - c);
    return w.dot((z - c).cwiseAbs2());
  }
};

}  // namespace

// From Rosenbrock's classic start (-1.2, 1) down the curved valley to its minimum (1, 1).
TEST(Lbfgs, MinimizesRosenbrock) {
  Eigen::VectorXd z(2);
  z << -1.2, 1.0;
  LbfgsOptions options;
  options.max_iterations = 500;
  options.max_steepest_step = 1.0;
  options.relative_decrease = 0;
  options.gradient_tolerance = 1e-10;
  const LbfgsReport r = minimize_lbfgs(z, rosenbrock, options);
  EXPECT_NEAR(z[0], 1.0, 1e-6);
  EXPECT_NEAR(z[1], 1.0, 1e-6);
  EXPECT_DOUBLE_EQ(r.start_energy, 24.2);
  EXPECT_LT(r.energy, 1e-12);
  EXPECT_GT(r.iterations, 10);  // the valley takes many steps
  EXPECT_LT(r.iterations, 500);
  EXPECT_FALSE(r.timed_out);
}

// A badly scaled convex quadratic in 20 variables: the minimum is its centre.
TEST(Lbfgs, MinimizesConvexQuadratic) {
  const Quadratic f(20);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(20);
  LbfgsOptions options;
  options.max_iterations = 1000;
  options.relative_decrease = 0;
  options.gradient_tolerance = 1e-9;
  const LbfgsReport r = minimize_lbfgs(z, f, options);
  EXPECT_LT((z - f.c).lpNorm<Eigen::Infinity>(), 1e-8);
  EXPECT_LT(r.energy, 1e-12);
}

// max_iterations bounds the iterations (and so the progress); a later call from where it
// stopped goes on.
TEST(Lbfgs, RespectsMaxIterations) {
  Eigen::VectorXd z(2);
  z << -1.2, 1.0;
  LbfgsOptions options;
  options.max_iterations = 3;
  const LbfgsReport r = minimize_lbfgs(z, rosenbrock, options);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_LT(r.energy, r.start_energy);
  EXPECT_GT((z - Eigen::Vector2d(1, 1)).norm(), 0.1);
  Eigen::VectorXd g(2);
  EXPECT_DOUBLE_EQ(rosenbrock(z, g), r.energy);
}

// A deadline already past: no iteration, z unchanged, timed_out.
TEST(Lbfgs, StopsAtDeadline) {
  Eigen::VectorXd z(2);
  z << -1.2, 1.0;
  LbfgsOptions options;
  options.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  const LbfgsReport r = minimize_lbfgs(z, rosenbrock, options);
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(z[0], -1.2);
  EXPECT_EQ(z[1], 1.0);
}

// An energy that refuses z0 >= 0.5 (+inf) with its unconstrained minimum at z0 = 1: the
// minimizer backtracks from refused points and ends inside, close to the wall.
TEST(Lbfgs, NeverEntersRefusedPoints) {
  auto barrier = [](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
    if (z[0] >= 0.5) return std::numeric_limits<double>::infinity();
    g[0] = 2 * (z[0] - 1) + 1e-6 / (0.5 - z[0]);
    g[1] = 2 * z[1];
    return (z[0] - 1) * (z[0] - 1) + z[1] * z[1] - 1e-6 * std::log(0.5 - z[0]);
  };
  Eigen::VectorXd z(2);
  z << -3.0, 2.0;
  LbfgsOptions options;
  options.max_iterations = 200;
  options.max_steepest_step = 10;  // the first step would jump far past the wall
  const LbfgsReport r = minimize_lbfgs(z, barrier, options);
  EXPECT_LT(z[0], 0.5);
  EXPECT_GT(z[0], 0.49);
  EXPECT_NEAR(z[1], 0.0, 1e-4);
  EXPECT_TRUE(std::isfinite(r.energy));
}

// A refused start: no iteration, z unchanged, the start energy reported as it is.
TEST(Lbfgs, RefusedStartLeavesZ) {
  auto refuse = [](const Eigen::VectorXd&, Eigen::VectorXd&) { return std::numeric_limits<double>::infinity(); };
  Eigen::VectorXd z = Eigen::VectorXd::Constant(3, 2.0);
  const LbfgsReport r = minimize_lbfgs(z, refuse, LbfgsOptions());
  EXPECT_EQ(r.iterations, 0);
  EXPECT_FALSE(std::isfinite(r.start_energy));
  EXPECT_EQ(z, Eigen::VectorXd::Constant(3, 2.0));
}

// Given the energy and gradient at the start, the minimizer does not evaluate them again
// and takes the same path as when it evaluates them itself.
TEST(Lbfgs, KnownStartSavesOneEvaluation) {
  int calls = 0;
  auto counted = [&](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
    ++calls;
    return rosenbrock(z, g);
  };
  LbfgsOptions options;
  options.max_iterations = 20;
  Eigen::VectorXd z1(2), z2(2), g(2);
  z1 << -1.2, 1.0;
  z2 = z1;
  const LbfgsReport a = minimize_lbfgs(z1, counted, options);
  const int calls_a = calls;
  calls = 0;
  const double e = rosenbrock(z2, g);
  const LbfgsReport b = minimize_lbfgs(z2, counted, options, e, g);
  EXPECT_EQ(calls, calls_a - 1);
  EXPECT_EQ(z1, z2);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.energy, b.energy);
}
