// SPDX-License-Identifier: BSL-1.0
/// \file
/// Masks written as ASCII art, so a test shows its input as a picture and a failure prints one.
/// '#', '1', 'X', '@' and '*' are foreground; every other character is background. Rows are
/// separated by newlines; leading/trailing blank lines are dropped; rows are padded to the
/// longest with background.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "perch/core/image.hpp"

namespace perch::support {

/// True for the characters that mean "foreground".
inline bool is_ink(char c) noexcept {
  return c == '#' || c == '1' || c == 'X' || c == '@' || c == '*';
}

/// Parses `art` into a 0/1 mask. Indentation common to all non-blank rows is removed, so art can
/// be indented in a raw string literal.
image<std::uint8_t> mask_from_ascii(std::string_view art);

/// Renders any view as ASCII art: '#' for non-zero pixels, '.' for zero.
template <ImageView V>
std::string to_ascii(const V& view) {
  std::string out;
  for (int y = 0; y < view.height(); ++y) {
    for (int x = 0; x < view.width(); ++x) out += view(x, y) ? '#' : '.';
    out += '\n';
  }
  return out;
}

}  // namespace perch::support
