// SPDX-License-Identifier: MIT
// Times the refinement core on one surface: TetGen vs THex vs dicing.
// Usage: refine_bench SURFACE.off [tetgen switches, default pq1.2Y] [dice n, default 2]
#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/tets/tetrahedralize.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <sys/resource.h>

namespace {

dthex::TriSurface read_off(const std::string& path) { return dthex::read_surface(path); }

//! CPU seconds of this process and its waited-for children (TetGen runs in a child):
//! on a shared machine these are steadier than wall time.
double cpu_seconds() {
  double total = 0;
  for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    getrusage(who, &u);
    total += double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  return total;
}

struct Timing {
  double wall = 0, cpu = 0;
};

template <class F>
Timing seconds(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  f();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), cpu_seconds() - cpu_start};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SURFACE.off [switches] [n]\n", argv[0]);
    return 2;
  }
  try {
    const dthex::TriSurface surface = read_off(argv[1]);
    dthex::TetgenOptions options;
    if (argc > 2) options.switches = argv[2];
    const int n = argc > 3 ? std::stoi(argv[3]) : 2;
    dthex::TetMesh tets;
    dthex::HexMesh hexes, diced;
    const Timing t_tet = seconds([&] { tets = dthex::tetrahedralize(surface, options); });
    const Timing t_thex = seconds([&] { hexes = dthex::thex(tets); });
    const Timing t_dice = seconds([&] { diced = dthex::dice(hexes, n); });
    const auto q = dthex::measure_hex_quality(hexes);
    std::printf("surface: %zu triangles\n", surface.triangles.size());
    std::printf("tetrahedralize (%s): %.3f s wall, %.3f s cpu, %zu points, %zu tets\n", options.switches.c_str(),
                t_tet.wall, t_tet.cpu,
                tets.points.size(), tets.tets.size());
    std::printf("thex: %.3f s wall, %.3f s cpu, %zu hexes, %zu nodes, shape avg %.4f min %.4f, SJ min %.4f\n", t_thex.wall, t_thex.cpu,
                hexes.hexes.size(), hexes.nodes.size(), q.shape_stats.avg, q.shape_stats.min,
                q.scaled_jacobian_stats.min);
    std::printf("dice(%d): %.3f s wall, %.3f s cpu, %zu hexes, %zu nodes\n", n, t_dice.wall, t_dice.cpu, diced.hexes.size(), diced.nodes.size());
    std::printf("tetgen / (thex + dice): wall %.1f, cpu %.1f\n", t_tet.wall / (t_thex.wall + t_dice.wall),
                t_tet.cpu / (t_thex.cpu + t_dice.cpu));
    if (argc > 4) {
      dthex::ConformityReport r;
      const Timing t_conf = seconds([&] { r = dthex::check_conformity(diced); });
      std::printf("conformity of the diced mesh: %s (%.3f s, %zu boundary faces)\n",
                  r.conforming() ? "conforming" : "NOT conforming", t_conf.wall, r.boundary_faces);
    }
  } catch (const dthex::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const dthex::MeshingError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
  return 0;
}
