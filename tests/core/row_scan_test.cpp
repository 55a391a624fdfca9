// SPDX-License-Identifier: BSL-1.0
#include "perch/core/row_scan.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace {

// Obviously correct scans, one pixel at a time.
int naive_next(const std::vector<std::uint8_t>& row, int x, bool set) {
  const int w = static_cast<int>(row.size());
  while (x < w && (row[static_cast<std::size_t>(x)] != 0) != set) ++x;
  return x;
}

int naive_last_set(const std::vector<std::uint8_t>& row, int from) {
  int x = static_cast<int>(row.size()) - 1;
  while (x >= from && row[static_cast<std::size_t>(x)] == 0) --x;
  return x;
}

}  // namespace

TEST_CASE("row scans (next_set, next_clear, last_set, binarise_row, count_nonzero) = naive loops") {
  // Long uniform stretches (the 64-, 16- and 8-pixel steps) broken by single pixels of every
  // kind of non-zero byte (the steps' tests must find the exact byte, not just the step).
  std::mt19937 rng(7);
  const std::uint8_t inks[] = {1, 0x7F, 0x80, 0xFF, 0x01, 0x81};
  int compared = 0;
  for (int round = 0; round < 400; ++round) {
    const bool wide = round % 2 == 1;  // rows and stretches long enough for 64-pixel steps
    const int w = static_cast<int>(rng() % (wide ? 300 : 70));
    std::vector<std::uint8_t> row(static_cast<std::size_t>(w) + 8, 0xAA);  // bytes past the end
    row.resize(static_cast<std::size_t>(w));
    const bool dense = rng() % 2 == 0;
    int x = 0;
    while (x < w) {
      const int run = 1 + static_cast<int>(rng() % (wide ? 150 : 20));
      const bool ink = dense ? rng() % 4 != 0 : rng() % 4 == 0;
      for (int k = 0; k < run && x < w; ++k, ++x)
        row[static_cast<std::size_t>(x)] = ink ? inks[rng() % std::size(inks)] : 0;
    }
    std::vector<std::uint8_t> ones(row.size() + 1, 9);
    std::uint32_t expected = 0;
    for (const std::uint8_t v : row) expected += v != 0 ? 1 : 0;
    CHECK(perch::detail::binarise_row(row.data(), ones.data(), w) == expected);
    CHECK(perch::detail::count_nonzero(row.data(), w) == expected);
    bool binarised = ones.back() == 9;  // nothing written past the row
    for (std::size_t i = 0; i < row.size(); ++i)
      binarised = binarised && ones[i] == (row[i] != 0 ? 1 : 0);
    CHECK(binarised);
    for (int from = 0; from <= w; ++from) {
      const std::uint8_t* p = row.data();
      CHECK(perch::detail::next_set(p, from, w) == naive_next(row, from, true));
      CHECK(perch::detail::next_clear(p, from, w) == naive_next(row, from, false));
      CHECK(perch::detail::last_set(p, from, w) == naive_last_set(row, from));
      ++compared;
    }
  }
  CHECK(compared > 10000);
}
