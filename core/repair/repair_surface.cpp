// SPDX-License-Identifier: MIT
#include <dthex/repair/repair_surface.h>

namespace dthex {

SurfaceRepairReport repair_surface(TriSurface& surface, const SurfaceRepairOptions& options) {
  SurfaceRepairReport report;
  report.ran = true;
  report.merge = merge_coincident_vertices(surface, options.merge);
  report.islands = remove_small_islands(surface, options.islands);
  report.redundant = remove_redundant_triangles(surface, options.redundant);
  report.orientation = repair_orientation(surface, options.orientation);
  report.slivers = flip_zero_area_slivers(surface, options.slivers);
  return report;
}

}  // namespace dthex
