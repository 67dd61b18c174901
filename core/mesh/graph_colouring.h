// SPDX-License-Identifier: MIT
// Greedy colouring of items (nodes, groups of nodes) that conflict where they share a cell:
// two items of one colour never share a cell, so the items of one colour can be worked on by
// several threads at once, each writing only its own cells, with the same result as by one.
//
// Items are coloured one at a time in the order they are added, each with the lowest colour
// that no earlier item sharing one of its cells has. With a colour limit, an item that finds
// every colour below it taken gets the limit itself, the overflow class, and marks no cell:
// the items of that class may share cells with anything and must be worked on one at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace dthex {

class GreedyCellColouring {
 public:
  static constexpr size_t kNoLimit = std::numeric_limits<size_t>::max();

  //! Items over cells 0 .. cell_count - 1, with colours below `max_colours`.
  explicit GreedyCellColouring(size_t cell_count, size_t max_colours = kNoLimit);

  //! Colours the next item, whose cells are [first, last) (repeats allowed), and returns its
  //! colour: below max_colours, or max_colours for the overflow class.
  size_t add(const int* first, const int* last);

  //! Colours used so far (the overflow class not counted).
  size_t colour_count() const { return colour_count_; }

 private:
  size_t cell_count_, max_colours_;
  size_t words_ = 1;                  //!< 64-bit words of colour bits per cell
  std::vector<std::uint64_t> used_;   //!< per cell, words_ words: the colours of the items holding it
  std::vector<std::uint64_t> taken_;  //!< scratch of add: the colours the item may not take
  size_t colour_count_ = 0;
};

}  // namespace dthex
