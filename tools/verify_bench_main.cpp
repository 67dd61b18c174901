// SPDX-License-Identifier: MIT
// Times reading and verifying surfaces: verify_bench FILE... (prints one line per file).
// verify_bench --bvh N times building a TriangleBvh over a sphere of about N triangles.
#include <dthex/io/read_surface.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/surface/verify_surface.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

int bvh_bench(long triangles) {
  using clock = std::chrono::steady_clock;
  const int rings = std::max(2, int(std::sqrt(double(triangles) / 4)));
  const int segments = std::max(3, int(triangles / (2 * rings)));
  dthex::TriSurface s;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = M_PI * (i + 0.5) / (rings + 1), phi = 2 * M_PI * j / segments;
      s.points.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * segments + j, b = i * segments + (j + 1) % segments;
      s.triangles.push_back({a, a + segments, b + segments});
      s.triangles.push_back({a, b + segments, b});
    }
  const auto t0 = clock::now();
  const dthex::TriangleBvh bvh(s);
  const auto t1 = clock::now();
  double sum = 0;
  for (int k = 0; k < 100000; ++k) {
    const double u = 2 * M_PI * k / 100000.0, v = std::acos(1 - 2 * ((k * 0.618034) - std::floor(k * 0.618034)));
    const dthex::Vec3 q = (1.0 + 0.01 * std::sin(7.0 * k)) *
                          dthex::Vec3(std::sin(v) * std::cos(u), std::sin(v) * std::sin(u), std::cos(v));
    sum += bvh.closest_point(q).distance_sq;
  }
  const auto t2 = clock::now();
  std::printf("bvh: %zu triangles, build %.3f s, 100000 near-surface closest points %.3f s (checksum %.6g)\n",
              s.triangles.size(), std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count(), sum);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using clock = std::chrono::steady_clock;
  if (argc == 3 && std::string(argv[1]) == "--bvh") return bvh_bench(std::atol(argv[2]));
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
