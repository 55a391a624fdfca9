/// \file
/// Private: visiting the non-zero pixels of a binary view in raster order, skipping runs of
/// zero bytes eight at a time when the pixels are bytes (skeletons are sparse).
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "perch/core/image_view.hpp"

namespace perch::detail {

/// Calls `f(x, y)` for every non-zero pixel of `view`, row by row, left to right.
template <BinaryView V, class F>
constexpr void for_each_set_pixel(const V& view, F&& f) noexcept {
  using value = typename V::value_type;
  const int w = view.width();
  for (int y = 0; y < view.height(); ++y) {
    const auto row = view.row(y);
    int x = 0;
    if constexpr (sizeof(value) == 1 && std::is_integral_v<value>) {
      if (!std::is_constant_evaluated()) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(row.data());
        while (x < w) {
          if (x + 8 <= w) {
            std::uint64_t chunk = 0;
            std::memcpy(&chunk, bytes + x, 8);
            if (chunk != 0)
              for (int i = 0; i < 8; ++i)
                if (bytes[x + i] != 0) f(x + i, y);
            x += 8;
            continue;
          }
          if (bytes[x] != 0) f(x, y);
          ++x;
        }
        continue;
      }
    }
    for (; x < w; ++x)
      if (static_cast<bool>(row[static_cast<std::size_t>(x)])) f(x, y);
  }
}

}  // namespace perch::detail
