// SPDX-License-Identifier: MIT
// Limited-memory BFGS with Armijo backtracking, for energies that may refuse a point: the
// untangler's (docs/METHOD.md, Untangling) is +inf where a step would invert a frame once
// every frame is valid, and a refused trial point is backtracked from like one that does not
// decrease the energy enough.
//
// `f(z, grad)` returns the energy at z and writes its gradient into grad (sized like z); it
// may return +inf (or NaN) for a point that must not be entered. It is a template parameter,
// so the energy is inlined into the loop (it is evaluated many times per iteration).
// minimize_lbfgs changes z to the last accepted point; z is never a refused point. It stops
// after max_iterations, at the deadline, when no step along the direction is accepted, or
// when an accepted step lowers the energy by no more than relative_decrease (relative to
// max(1, |f|)) or leaves the gradient's largest component below gradient_tolerance.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <vector>

namespace dthex {

struct LbfgsOptions {
  //! Most iterations (direction, line search, update).
  int max_iterations = 100;
  //! Checked before each iteration: past it, the minimizer stops with timed_out.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  //! Optional, checked before each iteration too: true stops the minimizer (stopped). Unlike
  //! the deadline, a stop that counts the caller's own work gives the same result every run.
  std::function<bool()> stop;
  //! Correction pairs kept: more follow the curvature better, each costs two dot products
  //! and two vector updates per iteration.
  int memory = 8;
  //! Armijo's sufficient decrease: a step t along d is taken if f drops by at least this
  //! times t times the slope.
  double sufficient_decrease = 1e-4;
  //! Halvings of the step before the line search gives up (and the minimizer stops).
  int max_halvings = 40;
  //! Where the direction is steepest descent (the first iteration, or when the quasi-Newton
  //! direction does not descend), its largest component is at most this: the variables'
  //! unit is the scale the caller chose for them.
  double max_steepest_step = 0.1;
  //! Stop when an iteration lowers f by no more than this times max(1, |f|).
  double relative_decrease = 1e-7;
  //! Stop when the gradient's largest component falls below this.
  double gradient_tolerance = 1e-9;
};

struct LbfgsReport {
  int iterations = 0;
  bool timed_out = false;  //!< stopped at the deadline
  bool stopped = false;    //!< stopped by LbfgsOptions::stop
  //! f at the given z (a refused start leaves z as it was and no iteration is made).
  double start_energy = std::numeric_limits<double>::infinity();
  double energy = std::numeric_limits<double>::infinity();  //!< f at the returned z
};

namespace detail {

template <class Energy>
LbfgsReport lbfgs_from(Eigen::VectorXd& z, Energy& f, const LbfgsOptions& options, double fz, Eigen::VectorXd& g) {
  LbfgsReport report;
  report.start_energy = report.energy = fz;
  if (!std::isfinite(fz)) return report;
  const Eigen::Index n = z.size();
  Eigen::VectorXd g_new(n), z_new(n), d(n);
  std::deque<Eigen::VectorXd> s_hist, y_hist;
  std::deque<double> rho_hist;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    if (std::chrono::steady_clock::now() > options.deadline) {
      report.timed_out = true;
      break;
    }
    if (options.stop && options.stop()) {
      report.stopped = true;
      break;
    }
    // Two-loop recursion.
    d = -g;
    std::vector<double> alpha(s_hist.size());
    for (int i = int(s_hist.size()) - 1; i >= 0; --i) {
      alpha[size_t(i)] = rho_hist[size_t(i)] * s_hist[size_t(i)].dot(d);
      d -= alpha[size_t(i)] * y_hist[size_t(i)];
    }
    if (!s_hist.empty()) d *= s_hist.back().dot(y_hist.back()) / y_hist.back().squaredNorm();
    for (size_t i = 0; i < s_hist.size(); ++i) {
      const double beta = rho_hist[i] * y_hist[i].dot(d);
      d += (alpha[i] - beta) * s_hist[i];
    }
    double slope = g.dot(d);
    if (s_hist.empty() || slope >= 0) {
      d = -g;
      const double biggest = d.lpNorm<Eigen::Infinity>();
      if (biggest <= 0) break;
      d *= std::min(1.0, options.max_steepest_step / biggest);
      slope = g.dot(d);
      s_hist.clear(), y_hist.clear(), rho_hist.clear();
    }
    double step = 1.0, f_new = std::numeric_limits<double>::infinity();
    bool accepted = false;
    for (int tries = 0; tries < options.max_halvings; ++tries, step *= 0.5) {
      z_new = z + step * d;
      f_new = f(z_new, g_new);
      if (std::isfinite(f_new) && f_new <= fz + options.sufficient_decrease * step * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) break;
    const Eigen::VectorXd s = z_new - z, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      s_hist.push_back(s), y_hist.push_back(y), rho_hist.push_back(1.0 / sy);
      if (int(s_hist.size()) > options.memory) s_hist.pop_front(), y_hist.pop_front(), rho_hist.pop_front();
    }
    const double decrease = fz - f_new;
    z.swap(z_new);
    g.swap(g_new);
    fz = f_new;
    if (decrease <= options.relative_decrease * std::max(1.0, std::abs(fz)) ||
        g.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) {
      ++it;
      break;
    }
  }
  report.iterations = it;
  report.energy = fz;
  return report;
}

}  // namespace detail

//! Minimizes f from z (see the file comment); f is evaluated at z first.
template <class Energy>
LbfgsReport minimize_lbfgs(Eigen::VectorXd& z, Energy&& f, const LbfgsOptions& options) {
  Eigen::VectorXd g(z.size());
  const double fz = f(z, g);
  return detail::lbfgs_from(z, f, options, fz, g);
}

//! The same from a z where the caller has evaluated f already: `energy` and `gradient` are
//! f's value and gradient at z (not evaluated again).
template <class Energy>
LbfgsReport minimize_lbfgs(Eigen::VectorXd& z, Energy&& f, const LbfgsOptions& options, double energy,
                           const Eigen::VectorXd& gradient) {
  Eigen::VectorXd g = gradient;
  return detail::lbfgs_from(z, f, options, energy, g);
}

}  // namespace dthex
