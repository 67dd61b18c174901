// SPDX-License-Identifier: MIT
#include <dthex/mesh/graph_colouring.h>

#include <algorithm>

namespace dthex {

GreedyCellColouring::GreedyCellColouring(size_t cell_count, size_t max_colours)
    : cell_count_(cell_count), max_colours_(max_colours), used_(cell_count, 0), taken_(1, 0) {}

size_t GreedyCellColouring::add(const int* first, const int* last) {
  std::fill(taken_.begin(), taken_.end(), 0);
  for (const int* c = first; c != last; ++c)
    for (size_t w = 0; w < words_; ++w) taken_[w] |= used_[size_t(*c) * words_ + w];
  size_t colour = 0;
  while (colour < max_colours_ && colour < 64 * words_ && (taken_[colour / 64] >> (colour % 64) & 1u)) ++colour;
  if (colour >= max_colours_) return max_colours_;
  if (colour == 64 * words_) {
    // Every colour the cells can record is taken: one more word per cell.
    std::vector<std::uint64_t> wider(cell_count_ * (words_ + 1), 0);
    for (size_t c = 0; c < cell_count_; ++c)
      for (size_t w = 0; w < words_; ++w) wider[c * (words_ + 1) + w] = used_[c * words_ + w];
    used_.swap(wider);
    ++words_;
    taken_.push_back(0);
  }
  const std::uint64_t bit = std::uint64_t(1) << (colour % 64);
  for (const int* c = first; c != last; ++c) used_[size_t(*c) * words_ + colour / 64] |= bit;
  if (colour + 1 > colour_count_) colour_count_ = colour + 1;
  return colour;
}

}  // namespace dthex
