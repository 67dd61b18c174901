// SPDX-License-Identifier: MIT
// Conjugate gradients, Jacobi-preconditioned, for K systems that share one symmetric positive
// definite matrix: K independent recurrences, each pass over the matrix serving all K (the
// solve is memory bound, so K systems cost little more than one). Each iteration makes three
// passes over the unknowns (product with p and p.q; updates, preconditioned residual and its
// two dot products; new direction): seven separate passes cost twice as much.
//
// The matrix is a template parameter with
//   size_t size() const                        number of unknowns n
//   double diagonal(size_t u) const            A(u, u), > 0 (used by the preconditioner)
//   template <size_t K> void multiply_row(size_t u, const double* p, std::array<double, K>& s) const
//                                              s[c] = sum over w of A(u, w) p[K w + c]
// and `b(u, c)` gives the right-hand side of unknown u in system c. Returns the K solutions
// interleaved (K values per unknown), started from zero. System c stops changing once its
// residual norm is at most tolerance times |b_c| (a zero b_c gives zero at once).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace dthex {

struct ConjugateGradientOptions {
  int max_iterations = 1000;
  //! Relative residual |b - A x| / |b| at which a system is solved.
  double tolerance = 1e-8;
  //! Divide the residual by the matrix's diagonal (Jacobi): far fewer iterations where the
  //! diagonal varies a lot, the same where it is constant.
  bool jacobi = true;
};

struct ConjugateGradientReport {
  int iterations = 0;
  bool converged = false;  //!< every system reached the tolerance
};

template <size_t K, class Matrix, class Rhs>
std::vector<double> solve_conjugate_gradient(const Matrix& a, Rhs&& b, const ConjugateGradientOptions& options,
                                             ConjugateGradientReport* report = nullptr) {
  const size_t n = a.size(), m = K * n;
  const double tolerance = options.tolerance;
  std::vector<double> x(m, 0.0), r(m), z(m), p(m), q(m);
  using Values = std::array<double, K>;
  auto preconditioner = [&](size_t u) { return options.jacobi ? a.diagonal(u) : 1.0; };
  Values rhs_norm2{}, rz{};
  for (size_t u = 0; u < n; ++u) {
    const double d = preconditioner(u);
    for (size_t c = 0; c < K; ++c) {
      const size_t i = K * u + c;
      r[i] = b(u, c);
      z[i] = p[i] = r[i] / d;
      rhs_norm2[c] += r[i] * r[i];
      rz[c] += r[i] * z[i];
    }
  }
  Values r2 = rhs_norm2;
  auto converged = [&](size_t c) { return r2[c] <= tolerance * tolerance * rhs_norm2[c]; };
  auto all_converged = [&] {
    for (size_t c = 0; c < K; ++c)
      if (!converged(c)) return false;
    return true;
  };
  int it = 0;
  for (; it < options.max_iterations && !all_converged(); ++it) {
    Values pq{};
    for (size_t u = 0; u < n; ++u) {
      Values s;
      a.multiply_row(u, p.data(), s);
      for (size_t c = 0; c < K; ++c) {
        q[K * u + c] = s[c];
        pq[c] += p[K * u + c] * s[c];
      }
    }
    Values alpha;
    for (size_t c = 0; c < K; ++c) alpha[c] = converged(c) || !(pq[c] > 0) ? 0.0 : rz[c] / pq[c];
    Values rz_new{};
    r2 = Values{};
    for (size_t u = 0; u < n; ++u) {
      const double d = preconditioner(u);
      for (size_t c = 0; c < K; ++c) {
        const size_t i = K * u + c;
        x[i] += alpha[c] * p[i];
        r[i] -= alpha[c] * q[i];
        z[i] = r[i] / d;
        rz_new[c] += r[i] * z[i];
        r2[c] += r[i] * r[i];
      }
    }
    Values beta;
    for (size_t c = 0; c < K; ++c) beta[c] = rz[c] > 0 ? rz_new[c] / rz[c] : 0.0;
    for (size_t i = 0; i < m; i += K)
      for (size_t c = 0; c < K; ++c) p[i + c] = z[i + c] + beta[c] * p[i + c];
    rz = rz_new;
  }
  if (report) {
    report->iterations = it;
    report->converged = all_converged();
  }
  return x;
}

}  // namespace dthex
