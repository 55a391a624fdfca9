// SPDX-License-Identifier: BSL-1.0
#include "perch/core/union_find.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

using perch::detail::union_find;

TEST_CASE("union_find: the smallest element is the root; flatten numbers sets by root") {
  std::vector<std::int32_t> parent(8, -7);
  union_find sets{parent.data(), 0, 7};
  for (int k = 1; k <= 6; ++k) CHECK(sets.make() == k);
  CHECK(sets.merge(5, 3) == 3);
  CHECK(sets.merge(6, 5) == 3);
  CHECK(sets.merge(4, 2) == 2);
  CHECK(sets.merge(4, 4) == 2);
  CHECK(sets.find(6) == 3);
  CHECK(sets.find(1) == 1);
  // Roots 1, 2, 3: labels 1, 2, 3 in root order; 0 (background) stays 0.
  CHECK(sets.flatten() == 3);
  CHECK(parent[0] == 0);
  const std::int32_t expected[] = {0, 1, 2, 3, 2, 3, 3};
  for (int i = 0; i <= 6; ++i) CHECK(parent[static_cast<std::size_t>(i)] == expected[i]);
}

TEST_CASE("union_find: singletons from 0 and resolve agree with a naive partition") {
  std::mt19937 rng(26);
  for (int round = 0; round < 200; ++round) {
    const int n = 1 + static_cast<int>(rng() % 40);
    std::vector<std::int32_t> parent(static_cast<std::size_t>(n));
    union_find sets{parent.data(), 0, n - 1};
    sets.make_singletons(n);
    CHECK(sets.count == n - 1);
    std::vector<int> naive(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) naive[static_cast<std::size_t>(i)] = i;
    const int merges = static_cast<int>(rng() % static_cast<unsigned>(n + 1));
    for (int k = 0; k < merges; ++k) {
      const auto a = static_cast<std::int32_t>(rng() % static_cast<unsigned>(n));
      const auto b = static_cast<std::int32_t>(rng() % static_cast<unsigned>(n));
      (void)sets.merge(a, b);
      // Naive: relabel the larger set id to the smaller everywhere.
      const int la = naive[static_cast<std::size_t>(a)], lb = naive[static_cast<std::size_t>(b)];
      const int lo = la < lb ? la : lb, hi = la < lb ? lb : la;
      for (int& l : naive)
        if (l == hi) l = lo;
    }
    sets.resolve();
    // Naive ids are each set's smallest element, as the union-find's roots.
    for (int i = 0; i < n; ++i)
      CHECK(parent[static_cast<std::size_t>(i)] == naive[static_cast<std::size_t>(i)]);
  }
}
