// SPDX-License-Identifier: MIT
// Benchmark of the DTHex coarsening: the paper's Table I (triangle shape of the input and
// after eps 0.01, 0.1, 0.5), Table II (local vs global smoothing at eps 0.01 and 0.05) and
// coarsening time against OpenMesh's ModQuadricT decimating to the same vertex count.
// Usage: coarsen_bench [--only EPS] [--split-from N] [--rough-from N] [--rough-fraction F] MESH.off [...]
//        (--only: one coarsening per mesh at EPS, timing only, for profiling;
//         --split-from: CoarsenOptions::split_from_vertices, 0 = never in two halves;
//         --rough-from, --rough-fraction: CoarsenOptions::rough_pass_from_vertices and
//         rough_pass_fraction, 0 = no rough pass)
#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>

#include <OpenMesh/Core/Utils/Noncopyable.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>

namespace {

dthex::TriSurface load(const std::string& path) {
  dthex::TriSurface surface = dthex::read_surface(path);
  dthex::verify_surface(surface, path);
  return surface;
}

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

void print_stats(const char* label, const dthex::TriSurface& s, double seconds = -1) {
  const auto q = dthex::summarize(dthex::triangle_shapes(s));
  std::printf("| %-22s | %7zu | %7zu | %.4f | %.4f | %.4f | %.4f |", label, s.points.size(), s.triangles.size(), q.avg,
              q.std_dev, q.min, q.max);
  if (seconds >= 0) std::printf(" %.3f |", seconds);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  omlog().disable();
  omout().disable();
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MESH.off [...]\n", argv[0]);
    return 2;
  }
  double only = 0;
  size_t split_from = dthex::CoarsenOptions().split_from_vertices;
  size_t rough_from = dthex::CoarsenOptions().rough_pass_from_vertices;
  double rough_fraction = dthex::CoarsenOptions().rough_pass_fraction;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--only" && i + 1 < argc) {
      only = std::stod(argv[++i]);
      continue;
    }
    if (std::string(argv[i]) == "--split-from" && i + 1 < argc) {
      split_from = size_t(std::stoul(argv[++i]));
      continue;
    }
    if (std::string(argv[i]) == "--rough-from" && i + 1 < argc) {
      rough_from = size_t(std::stoul(argv[++i]));
      continue;
    }
    if (std::string(argv[i]) == "--rough-fraction" && i + 1 < argc) {
      rough_fraction = std::stod(argv[++i]);
      continue;
    }
    try {
      if (only > 0) {
        const dthex::TriSurface input = load(argv[i]);
        dthex::CoarsenOptions options;
        options.eps = only;
        options.split_from_vertices = split_from;
        options.rough_pass_from_vertices = rough_from;
        options.rough_pass_fraction = rough_fraction;
        const double c0 = cpu_seconds();
        const auto r = dthex::coarsen(input, options);
        const double cpu = cpu_seconds() - c0;
        std::printf("%s eps %g: %zu -> %zu vertices, %zu collapses, %zu swaps, %zu moves, %d repairs, "
                    "%.3f s wall, %.3f s CPU, %zu feature edges, %zu corners, %zu cut vertices\n",
                    argv[i], only, input.points.size(), r.surface.points.size(), r.collapses, r.swaps,
                    r.smoothing_moves, r.repair_rounds, r.seconds, cpu, r.feature_edges, r.feature_corners,
                    r.cut_vertices);
        continue;
      }
      const dthex::TriSurface input = load(argv[i]);
      std::printf("\n## %s (%zu vertices, %zu triangles)\n\nTable I: triangle shape\n\n", argv[i],
                  input.points.size(), input.triangles.size());
      std::printf("| surface | vertices | triangles | avg | std | min | max | CPU s |\n|---|---|---|---|---|---|---|---|\n");
      print_stats("input", input);
      size_t vertices_at_01 = 0;
      double seconds_at_01 = 0;
      for (double eps : {0.01, 0.1, 0.5}) {
        dthex::CoarsenOptions options;
        options.eps = eps;
        options.split_from_vertices = split_from;
        options.rough_pass_from_vertices = rough_from;
        options.rough_pass_fraction = rough_fraction;
        const double c0 = cpu_seconds();
        const auto r = dthex::coarsen(input, options);
        const double cpu = cpu_seconds() - c0;
        char label[64];
        std::snprintf(label, sizeof label, "eps %.2f (repairs %d)", eps, r.repair_rounds);
        print_stats(label, r.surface, cpu);
        if (eps == 0.1) vertices_at_01 = r.surface.points.size(), seconds_at_01 = r.seconds;
      }
      std::printf("\nTable II: local vs global smoothing\n\n");
      std::printf("| run | vertices | triangles | avg | std | min | max | CPU s |\n|---|---|---|---|---|---|---|---|\n");
      for (double eps : {0.01, 0.05})
        for (bool global : {false, true}) {
          dthex::CoarsenOptions options;
          options.eps = eps;
          options.split_from_vertices = split_from;
        options.rough_pass_from_vertices = rough_from;
        options.rough_pass_fraction = rough_fraction;
          options.local_smoothing = !global;
          options.global_smoothing = global;
          const double c0 = cpu_seconds();
          const auto r = dthex::coarsen(input, options);
          const double cpu = cpu_seconds() - c0;
          char label[64];
          std::snprintf(label, sizeof label, "eps %.2f %s", eps, global ? "global" : "local");
          print_stats(label, r.surface, cpu);
        }
      // ModQuadricT to the same vertex count as eps 0.1, same input, same run.
      dthex::SurfaceMesh mesh = dthex::to_openmesh(input);
      mesh.request_vertex_status();
      mesh.request_edge_status();
      mesh.request_face_status();
      const auto t0 = std::chrono::steady_clock::now();
      size_t live = mesh.n_vertices();
      {
        OpenMesh::Decimater::DecimaterT<dthex::SurfaceMesh> decimater(mesh);
        OpenMesh::Decimater::ModQuadricT<dthex::SurfaceMesh>::Handle quadric;
        decimater.add(quadric);
        decimater.initialize();
        live -= decimater.decimate_to(vertices_at_01);
        mesh.garbage_collection();
      }
      const double quadric_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("\nTiming at eps 0.1: DTHex coarsen %.3f s (%zu vertices), ModQuadricT %.3f s (%zu vertices), "
                  "ratio %.2f\n",
                  seconds_at_01, vertices_at_01, quadric_seconds, live, seconds_at_01 / quadric_seconds);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", argv[i], e.what());
      return 3;
    }
  }
  return 0;
}
