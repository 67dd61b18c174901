// SPDX-License-Identifier: MIT
#include <dthex/hexes/node_count.h>

#include <algorithm>

namespace dthex {

TetCounts count_tet_entities(const TetMesh& mesh) {
  TetCounts c;
  c.tets = mesh.tets.size();
  std::vector<char> used(mesh.points.size(), 0);
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> faces;
  edges.reserve(6 * c.tets);
  faces.reserve(4 * c.tets);
  for (const auto& t : mesh.tets) {
    for (int v : t) used[size_t(v)] = 1;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.push_back({std::min(t[size_t(i)], t[size_t(j)]), std::max(t[size_t(i)], t[size_t(j)])});
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      int k = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[size_t(k++)] = t[size_t(i)];
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  }
  std::sort(edges.begin(), edges.end());
  std::sort(faces.begin(), faces.end());
  c.edges = size_t(std::unique(edges.begin(), edges.end()) - edges.begin());
  c.faces = size_t(std::unique(faces.begin(), faces.end()) - faces.begin());
  c.vertices = size_t(std::count(used.begin(), used.end(), 1));
  return c;
}

size_t diced_thex_nodes(const TetCounts& c, int dice) {
  const size_t n1 = size_t(std::max(dice, 1) - 1);
  const size_t nodes = c.vertices + c.edges + c.faces + c.tets;
  const size_t edges = 2 * c.edges + 3 * c.faces + 4 * c.tets;
  const size_t quads = 3 * c.faces + 6 * c.tets;
  const size_t hexes = 4 * c.tets;
  return nodes + n1 * edges + n1 * n1 * quads + n1 * n1 * n1 * hexes;
}

}  // namespace dthex
