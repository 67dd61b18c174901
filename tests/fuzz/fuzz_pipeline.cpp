// SPDX-License-Identifier: MIT
// libFuzzer target: the whole pipeline (read, verify, coarsen, TetGen, THex, dice,
// project, untangle, measure) on small inputs, with small time limits. Any input must
// end in a result, an InputError (bad input) or a MeshingError (a stage gave up):
// never a crash, a hang or another exception. A result must be a hex mesh whose
// connectivity refers to existing, finite nodes.
#include <dthex/pipeline/pipeline.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > 4096) return 0;  // small inputs: the meshing stages are slow
  static const char* const extensions[] = {".off", ".obj", ".stl", ".ply"};
  const std::string path = "/tmp/dthex_fuzz_pipeline_" + std::to_string(::getpid()) + extensions[data[0] % 4];
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  }
  dthex::PipelineOptions options;
  options.time_limit_seconds = 2;
  options.dice = 1 + data[0] / 4 % 2;
  dthex::Progress progress(dthex::Progress::Mode::Quiet);
  try {
    const dthex::PipelineResult result = dthex::run_pipeline(path, options, progress);
    if (result.hexes.hexes.empty()) std::abort();
    for (const auto& n : result.hexes.nodes)
      if (!n.allFinite()) std::abort();
    for (const auto& h : result.hexes.hexes)
      for (int v : h)
        if (v < 0 || size_t(v) >= result.hexes.nodes.size()) std::abort();
  } catch (const dthex::InputError&) {
  } catch (const dthex::MeshingError&) {
  }
  std::remove(path.c_str());
  return 0;
}
