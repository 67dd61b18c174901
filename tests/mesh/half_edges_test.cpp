// SPDX-License-Identifier: MIT
#include <dthex/mesh/half_edges.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace dthex {
namespace {

// Random triangles over `vertices` vertex numbers, some repeating a vertex (the sort must give
// those a fixed order too) and some repeated whole.
std::vector<std::array<int, 3>> random_triangles(size_t count, int vertices, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> vertex(0, vertices - 1);
  std::vector<std::array<int, 3>> triangles;
  for (size_t t = 0; t < count; ++t) {
    std::array<int, 3> tri{vertex(random), vertex(random), vertex(random)};
    if (t % 97 == 5) tri[2] = tri[0];
    if (t % 89 == 7 && t > 0) tri = triangles[t / 2];
    triangles.push_back(tri);
  }
  return triangles;
}

std::vector<HalfEdge> half_edges_by_std_sort(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<HalfEdge> out;
  for (size_t t = 0; t < triangles.size(); ++t)
    for (size_t k = 0; k < 3; ++k) {
      const int a = triangles[t][k], b = triangles[t][(k + 1) % 3];
      out.push_back({uint64_t(std::min(a, b)) << 32 | uint64_t(std::max(a, b)), int(t), a});
    }
  std::sort(out.begin(), out.end());
  return out;
}

bool same(const std::vector<HalfEdge>& a, const std::vector<HalfEdge>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].key != b[i].key || a[i].triangle != b[i].triangle || a[i].from != b[i].from) return false;
  return true;
}

TEST(HalfEdges, CountingSortGivesTheComparisonSortsOrder) {
  // Dense vertex numbers (the counting sort) and sparse ones (the comparison sort it falls
  // back to), above and below the size where it starts.
  for (const auto& [count, vertices] : {std::pair<size_t, int>{20000, 9000}, {20000, 1000000}, {50, 30}}) {
    const auto triangles = random_triangles(count, vertices, unsigned(count + size_t(vertices)));
    const std::vector<HalfEdge> sorted = sorted_half_edges(triangles);
    EXPECT_TRUE(same(sorted, half_edges_by_std_sort(triangles))) << count << " triangles, " << vertices << " vertices";
    EXPECT_TRUE(std::is_sorted(sorted.begin(), sorted.end()));
  }
}

TEST(HalfEdges, TriangleKeysStandSideBySideLowerIndexFirst) {
  const auto triangles = random_triangles(30000, 5000, 3);
  std::vector<int> odd;  // a subset, as the repair passes the triangles it keeps
  for (int t = 1; t < int(triangles.size()); t += 2) odd.push_back(t);
  const std::vector<TriangleKey> keys = sorted_triangle_keys(triangles, odd);
  std::vector<TriangleKey> expected;
  for (int t : odd) {
    std::array<int, 3> key = triangles[size_t(t)];
    std::sort(key.begin(), key.end());
    expected.push_back({key, t});
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(keys, expected);
  size_t repeats = 0;
  for (size_t k = 1; k < keys.size(); ++k) repeats += keys[k].first == keys[k - 1].first;
  EXPECT_GT(repeats, 0u);  // the input repeats triangles: the test sees them side by side
}

}  // namespace
}  // namespace dthex
