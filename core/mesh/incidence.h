// SPDX-License-Identifier: MIT
// The cells (hexes, quads, triangles, tets) at each node of a mesh, built once from the
// cells' node lists and read-only after: what the boundary passes walk to find the hexes a
// node move changes.
//
// One array holds every node's cells, a range per node (a vector per node costs more than a
// whole pass on a mesh of a million nodes). At each node the cells come in ascending cell
// index; a cell that lists a node twice appears twice. Built with corners, a parallel array
// gives each entry the node's position in the cell's node list (the corner), so that
// callers needing (cell, corner) pairs read them without searching the cell.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dthex {

class NodeCellIncidence {
 public:
  //! The cell indices at one node, ascending.
  struct Range {
    const int *first = nullptr, *last = nullptr;
    const int* begin() const { return first; }
    const int* end() const { return last; }
    size_t size() const { return size_t(last - first); }
    bool empty() const { return first == last; }
    int operator[](size_t i) const { return first[i]; }
  };
  //! One entry at a node: the cell and the node's corner in it.
  struct Entry {
    int cell = 0;
    int corner = 0;
  };
  //! The (cell, corner) entries at one node, in the order of its Range.
  class Entries {
   public:
    class Iterator {
     public:
      Iterator(const int* cell, const std::uint8_t* corner) : cell_(cell), corner_(corner) {}
      Entry operator*() const { return {*cell_, int(*corner_)}; }
      Iterator& operator++() {
        ++cell_, ++corner_;
        return *this;
      }
      bool operator!=(const Iterator& o) const { return cell_ != o.cell_; }

     private:
      const int* cell_;
      const std::uint8_t* corner_;
    };
    Entries(const int* cells, const std::uint8_t* corners, size_t size)
        : cells_(cells), corners_(corners), size_(size) {}
    Iterator begin() const { return {cells_, corners_}; }
    Iterator end() const { return {cells_ + size_, corners_ + size_}; }
    size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    Entry operator[](size_t i) const { return {cells_[i], int(corners_[i])}; }

   private:
    const int* cells_;
    const std::uint8_t* corners_;
    size_t size_;
  };

  NodeCellIncidence() = default;
  //! The incidence of `node_count` nodes in `cells` (every node index below node_count;
  //! N at most 256 when `with_corners`).
  template <size_t N>
  NodeCellIncidence(size_t node_count, const std::vector<std::array<int, N>>& cells, bool with_corners = false)
      : start_(node_count + 1, 0) {
    static_assert(N <= 256, "corners are stored in one byte");
    for (const auto& c : cells)
      for (int v : c) ++start_[size_t(v) + 1];
    for (size_t v = 0; v < node_count; ++v) start_[v + 1] += start_[v];
    cells_.resize(start_.back());
    if (with_corners) corners_.resize(start_.back());
    std::vector<size_t> next(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < cells.size(); ++i)
      for (size_t k = 0; k < N; ++k) {
        const size_t slot = next[size_t(cells[i][k])]++;
        cells_[slot] = int(i);
        if (with_corners) corners_[slot] = std::uint8_t(k);
      }
  }

  size_t node_count() const { return start_.empty() ? 0 : start_.size() - 1; }
  //! The cells at node v.
  Range operator[](size_t v) const { return {cells_.data() + start_[v], cells_.data() + start_[v + 1]}; }
  //! The cells at node v with v's corner in each; only for an incidence built with corners.
  Entries entries(size_t v) const {
    return {cells_.data() + start_[v], corners_.data() + start_[v], start_[v + 1] - start_[v]};
  }

 private:
  std::vector<size_t> start_;  //!< node v's entries are [start_[v], start_[v + 1])
  std::vector<int> cells_;
  std::vector<std::uint8_t> corners_;  //!< parallel to cells_, empty without corners
};

}  // namespace dthex
