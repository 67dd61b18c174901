// SPDX-License-Identifier: MIT
// libFuzzer target: every surface reader on arbitrary bytes. The first byte picks the
// format, the rest is the file. A reader may refuse (InputError) but must never crash,
// hang, read out of bounds or throw anything else; what it accepts must be well formed.
#include <dthex/io/read_surface.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const extensions[] = {".off", ".obj", ".stl", ".ply"};
  const std::string extension = extensions[data[0] % 4];
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const dthex::TriSurface surface = dthex::read_surface_from_memory(bytes, extension, "fuzz" + extension);
    // The reader's guarantees (read_surface.h): triangles, finite points, indices in range.
    if (surface.triangles.empty()) std::abort();
    for (const auto& p : surface.points)
      if (!p.allFinite()) std::abort();
    for (const auto& t : surface.triangles)
      for (int v : t)
        if (v < 0 || size_t(v) >= surface.points.size()) std::abort();
  } catch (const dthex::InputError&) {
  }
  return 0;
}
