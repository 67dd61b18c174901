// SPDX-License-Identifier: MIT
// Times reading and verifying surfaces: verify_bench FILE... (prints one line per file).
#include "core/read_surface.h"
#include "core/verify_surface.h"

#include <chrono>
#include <cstdio>

int main(int argc, char** argv) {
  using clock = std::chrono::steady_clock;
  int status = 0;
  for (int i = 1; i < argc; ++i) {
    try {
      const auto t0 = clock::now();
      dthex::TriSurface surface = dthex::read_surface(argv[i]);
      const auto t1 = clock::now();
      const dthex::SurfaceStats s = dthex::verify_surface(surface, argv[i]);
      const auto t2 = clock::now();
      std::printf("%s: V %zu E %zu F %zu components %zu cavities %zu genus %d flipped %zu volume %.6g area %.6g "
                  "diag %.6g | read %.3f s verify %.3f s\n",
                  argv[i], s.vertices, s.edges, s.triangles, s.components, s.cavities, s.genus, s.flipped_components,
                  s.volume, s.area, s.bbox_diagonal, std::chrono::duration<double>(t1 - t0).count(),
                  std::chrono::duration<double>(t2 - t1).count());
    } catch (const std::exception& e) {
      std::printf("%s\n", e.what());
      status = 2;
    }
  }
  return status;
}
