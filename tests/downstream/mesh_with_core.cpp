// SPDX-License-Identifier: MIT
// A downstream program of the core library: checks Verdict's measures on the unit cube,
// runs the whole DTHex pipeline on a closed surface and writes the hexes as Exodus II, so
// linking it needs every private dependency of the static library (TetGen, libexoIIv2c,
// OpenMP). Exits 1 when the cube does not measure 1 (to a few ulps) or the mesh is empty, inverted or
// not conforming. Usage: mesh_with_core INPUT OUTPUT.exo
#include <dthex/io/write_hex_mesh.h>
#include <dthex/mesh/quality.h>
#include <dthex/pipeline/pipeline.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s INPUT OUTPUT.exo\n", argv[0]);
    return 2;
  }
  const std::array<dthex::Vec3, 8> cube = {dthex::Vec3(0, 0, 0), dthex::Vec3(1, 0, 0), dthex::Vec3(1, 1, 0),
                                           dthex::Vec3(0, 1, 0), dthex::Vec3(0, 0, 1), dthex::Vec3(1, 0, 1),
                                           dthex::Vec3(1, 1, 1), dthex::Vec3(0, 1, 1)};
  const double cube_sj = dthex::hex_scaled_jacobian(cube), cube_shape = dthex::hex_shape(cube);
  try {
    dthex::Progress quiet;
    const dthex::PipelineResult result = dthex::run_pipeline(argv[1], dthex::PipelineOptions{}, quiet);
    dthex::write_hex_mesh(result.hexes, argv[2]);
    const bool written = std::ifstream(argv[2], std::ios::binary).peek() != std::ifstream::traits_type::eof();
    std::printf("unit cube: scaled Jacobian %.17g, shape %.17g; %s: %zu hexes, %zu inverted, min scaled Jacobian %g, %s\n",
                cube_sj, cube_shape, argv[1], result.hexes.hexes.size(), result.quality.inverted,
                result.quality.scaled_jacobian_stats.min, result.conforming ? "conforming" : "NOT conforming");
    const bool ok = std::abs(cube_sj - 1.0) < 1e-12 && std::abs(cube_shape - 1.0) < 1e-12 && !result.hexes.hexes.empty() &&
                    result.quality.inverted == 0 && result.quality.scaled_jacobian_stats.min > 0 &&
                    result.conforming && written;
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
