// SPDX-License-Identifier: MIT
// A try's report (MeshTryReport) in one line, for tests of how tries are ordered and described.
#pragma once

#include <dthex/pipeline/stage_reports.h>

#include <cstddef>

namespace dthex::testing {

//! The report of a try at `eps` that did not fail.
inline MeshTryReport mesh_try(double eps, size_t inverted, double min_scaled_jacobian, bool conforming,
                              bool fold_repair_left) {
  MeshTryReport t;
  t.eps = eps;
  t.inverted = inverted;
  t.min_scaled_jacobian = min_scaled_jacobian;
  t.conforming = conforming;
  t.fold_repair_left = fold_repair_left;
  return t;
}

}  // namespace dthex::testing
