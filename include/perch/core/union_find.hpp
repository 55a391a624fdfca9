// SPDX-License-Identifier: BSL-1.0
/// \file
/// Union-find over small integers in one int32 array, the smaller root always the root of a
/// merged set: the label equivalences of the two-pass labeller (label stage) and the
/// components of the skeleton graph (graph stage).
#pragma once

#include <cstdint>

#include "perch/core/assert.hpp"

namespace perch::detail {

/// Union-find over the elements 0..count stored in one int32 array `parent` (of capacity + 1
/// entries). A root `i` has `parent[i] == i`; every other entry points to a smaller element.
/// Merging makes the smaller root the root of both sets, so the root of a set is always its
/// smallest element — for provisional labels issued in a raster scan, the label of the
/// component's first pixel. Implements the array-based union-find of Wu, Otoo & Suzuki,
/// "Optimizing two-pass connected-component labeling algorithms", Pattern Anal. Appl. 12
/// (2009) 117–135, §3 (`findRoot`, `setRoot`, `union` with path compression, and `flattenL`).
///
/// Two ways to issue elements: `make` issues 1, 2, … one at a time, element 0 standing for the
/// background (the labeller's provisional labels; `flatten` numbers the sets 1..n and maps 0 to
/// 0); `make_singletons(n)` issues 0 … n − 1 at once, 0 an element like the others.
struct union_find {
  std::int32_t* parent = nullptr;
  std::int32_t count = 0;     ///< the largest element issued so far
  std::int32_t capacity = 0;  ///< the largest element `parent` can hold (its size − 1)

  /// A new element count + 1 (its own root).
  std::int32_t make() noexcept {
    PERCH_ASSERT(count < capacity, "union_find: element bound broken");
    ++count;
    parent[count] = count;
    return count;
  }

  /// Elements 0 … n − 1, each its own set (`n` ≤ capacity + 1).
  void make_singletons(std::int32_t n) noexcept {
    PERCH_ASSERT(n - 1 <= capacity, "union_find: element bound broken");
    for (std::int32_t i = 0; i < n; ++i) parent[i] = i;
    count = n - 1;
  }

  /// The root of element `i`.
  [[nodiscard]] std::int32_t find(std::int32_t i) const noexcept {
    while (parent[i] < i) i = parent[i];
    return i;
  }

  /// Points every element on the path from `i` to its root at `root` (path compression).
  void set_root(std::int32_t i, std::int32_t root) noexcept {
    while (parent[i] < i) {
      const std::int32_t next = parent[i];
      parent[i] = root;
      i = next;
    }
    parent[i] = root;
  }

  /// Records that `i` and `j` are in one set; returns the root of the merged set (the smaller
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

  /// Points every element 0..count at its root, so that `parent[i]` is the root of `i`. One
  /// pass, because an element's parent is smaller and hence already points at its root.
  void resolve() noexcept {
    for (std::int32_t i = 0; i <= count; ++i) parent[i] = parent[parent[i]];
  }

  /// Replaces every entry 1..count by its set's final label 1..n, numbered in increasing order
  /// of the roots (so in raster order of each component's first pixel), and entry 0 by 0;
  /// returns n. One pass, because a label's parent is smaller and hence already final when the
  /// label is reached. (For elements issued by `make`.)
  std::int32_t flatten() noexcept {
    std::int32_t next = 1;
    parent[0] = 0;
    for (std::int32_t i = 1; i <= count; ++i)
      parent[i] = parent[i] < i ? parent[parent[i]] : next++;
    return next - 1;
  }
};

}  // namespace perch::detail
