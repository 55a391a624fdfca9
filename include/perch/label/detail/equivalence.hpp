/// \file
/// The label-equivalence array of the two-pass labeller: union-find over provisional labels
/// with path compression, the smaller label always the root.
#pragma once

#include <cstdint>

#include "perch/core/assert.hpp"

namespace perch::detail {

/// Union-find over provisional labels 1..count stored in one int32 array `parent` (index 0 is
/// the background and maps to 0). A root `i` has `parent[i] == i`; every other entry points to a
/// smaller label. Merging makes the smaller root the root of both sets, so the root of a set is
/// always the first label it was given — in a raster scan, the label of the component's first
/// pixel. Implements the array-based union-find of Wu, Otoo & Suzuki, "Optimizing two-pass
/// connected-component labeling algorithms", Pattern Anal. Appl. 12 (2009) 117–135, §3
/// (`findRoot`, `setRoot`, `union` with path compression, and `flattenL`).
struct label_equivalence {
  std::int32_t* parent = nullptr;
  std::int32_t count = 0;     ///< provisional labels issued so far
  std::int32_t capacity = 0;  ///< labels `parent` can hold (its size − 1)

  /// A new provisional label (its own root).
  std::int32_t make() noexcept {
    PERCH_ASSERT(count < capacity, "label_equivalence: provisional label bound broken");
    ++count;
    parent[count] = count;
    return count;
  }

  /// The root of label `i`.
  [[nodiscard]] std::int32_t find(std::int32_t i) const noexcept {
    while (parent[i] < i) i = parent[i];
    return i;
  }

  /// Points every label on the path from `i` to its root at `root` (path compression).
  void set_root(std::int32_t i, std::int32_t root) noexcept {
    while (parent[i] < i) {
      const std::int32_t next = parent[i];
      parent[i] = root;
      i = next;
    }
    parent[i] = root;
  }

  /// Records that `i` and `j` are equivalent; returns the root of the merged set (the smaller
  /// of the two roots).
  std::int32_t merge(std::int32_t i, std::int32_t j) noexcept {
    std::int32_t root = find(i);
    if (i != j) {
      const std::int32_t root_j = find(j);
      if (root > root_j) root = root_j;
      set_root(j, root);
    }
    set_root(i, root);
    return root;
  }

  /// Replaces every entry by its set's final label 1..n, numbered in increasing order of the
  /// roots (so in raster order of each component's first pixel); returns n. One pass, because
  /// a label's parent is smaller and hence already final when the label is reached.
  std::int32_t flatten() noexcept {
    std::int32_t next = 1;
    parent[0] = 0;
    for (std::int32_t i = 1; i <= count; ++i)
      parent[i] = parent[i] < i ? parent[parent[i]] : next++;
    return next - 1;
  }
};

}  // namespace perch::detail
