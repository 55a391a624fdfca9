// SPDX-License-Identifier: BSL-1.0
/// \file
/// A tiny bitmap font (perch's own 5 × 7 glyphs for printable ASCII 32–126), text drawing with
/// an optional background box, and a legend box for annotated pictures. Host code, not part of
/// the library. Canvases, colours and clipping are those of `draw.hpp`.
///
/// Metrics at scale 1: each glyph is 5 × 7 pixels in a 6 × 8 cell (one column of spacing on
/// the right, one row below). Lines are separated by '\n'. Scale s multiplies everything by s
/// (each font pixel becomes an s × s block). Bytes outside 32–126 draw as '?'.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string_view>

#include "perch/core/image_view.hpp"
#include "support/draw.hpp"

namespace perch::support {

/// Glyph width and height in font pixels (at scale 1).
inline constexpr int glyph_width = 5;
inline constexpr int glyph_height = 7;
/// Horizontal advance per character and vertical advance per line (at scale 1).
inline constexpr int glyph_advance_x = 6;
inline constexpr int glyph_advance_y = 8;
/// Largest scale `draw_text` honours (larger values are clamped).
inline constexpr int max_text_scale = 64;

/// One glyph: `glyph_height` rows top to bottom; in each row bit 4 is the leftmost column and
/// bit 0 the rightmost.
using glyph = std::array<std::uint8_t, glyph_height>;

/// perch's font: glyph i is ASCII character 32 + i.
inline constexpr std::array<glyph, 95> font_glyphs = {{
    {{0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000}},  // 32 space
    {{0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00100}},  // 33 !
    {{0b01010, 0b01010, 0b01010, 0b00000, 0b00000, 0b00000, 0b00000}},  // 34 "
    {{0b01010, 0b01010, 0b11111, 0b01010, 0b11111, 0b01010, 0b01010}},  // 35 #
    {{0b00100, 0b01111, 0b10100, 0b01110, 0b00101, 0b11110, 0b00100}},  // 36 $
    {{0b11000, 0b11001, 0b00010, 0b00100, 0b01000, 0b10011, 0b00011}},  // 37 %
    {{0b01100, 0b10010, 0b10100, 0b01000, 0b10101, 0b10010, 0b01101}},  // 38 &
    {{0b00100, 0b00100, 0b01000, 0b00000, 0b00000, 0b00000, 0b00000}},  // 39 quote
    {{0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010}},  // 40 (
    {{0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000}},  // 41 )
    {{0b00000, 0b00100, 0b10101, 0b01110, 0b10101, 0b00100, 0b00000}},  // 42 *
    {{0b00000, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0b00000}},  // 43 +
    {{0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b00100, 0b01000}},  // 44 ,
    {{0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000}},  // 45 -
    {{0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100}},  // 46 .
    {{0b00000, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b00000}},  // 47 /
    {{0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110}},  // 48 0
    {{0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110}},  // 49 1
    {{0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111}},  // 50 2
    {{0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110}},  // 51 3
    {{0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010}},  // 52 4
    {{0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110}},  // 53 5
    {{0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110}},  // 54 6
    {{0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000}},  // 55 7
    {{0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110}},  // 56 8
    {{0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100}},  // 57 9
    {{0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00000}},  // 58 :
    {{0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b00100, 0b01000}},  // 59 ;
    {{0b00010, 0b00100, 0b01000, 0b10000, 0b01000, 0b00100, 0b00010}},  // 60 <
    {{0b00000, 0b00000, 0b11111, 0b00000, 0b11111, 0b00000, 0b00000}},  // 61 =
    {{0b01000, 0b00100, 0b00010, 0b00001, 0b00010, 0b00100, 0b01000}},  // 62 >
    {{0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b00000, 0b00100}},  // 63 ?
    {{0b01110, 0b10001, 0b00001, 0b01101, 0b10101, 0b10101, 0b01110}},  // 64 @
    {{0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001}},  // 65 A
    {{0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110}},  // 66 B
    {{0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110}},  // 67 C
    {{0b11100, 0b10010, 0b10001, 0b10001, 0b10001, 0b10010, 0b11100}},  // 68 D
    {{0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111}},  // 69 E
    {{0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000}},  // 70 F
    {{0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111}},  // 71 G
    {{0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001}},  // 72 H
    {{0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110}},  // 73 I
    {{0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100}},  // 74 J
    {{0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001}},  // 75 K
    {{0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111}},  // 76 L
    {{0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001}},  // 77 M
    {{0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001}},  // 78 N
    {{0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110}},  // 79 O
    {{0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000}},  // 80 P
    {{0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101}},  // 81 Q
    {{0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001}},  // 82 R
    {{0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110}},  // 83 S
    {{0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100}},  // 84 T
    {{0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110}},  // 85 U
    {{0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100}},  // 86 V
    {{0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010}},  // 87 W
    {{0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001}},  // 88 X
    {{0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100, 0b00100}},  // 89 Y
    {{0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111}},  // 90 Z
    {{0b01110, 0b01000, 0b01000, 0b01000, 0b01000, 0b01000, 0b01110}},  // 91 [
    {{0b00000, 0b10000, 0b01000, 0b00100, 0b00010, 0b00001, 0b00000}},  // 92 backslash
    {{0b01110, 0b00010, 0b00010, 0b00010, 0b00010, 0b00010, 0b01110}},  // 93 ]
    {{0b00100, 0b01010, 0b10001, 0b00000, 0b00000, 0b00000, 0b00000}},  // 94 ^
    {{0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b11111}},  // 95 _
    {{0b01000, 0b00100, 0b00010, 0b00000, 0b00000, 0b00000, 0b00000}},  // 96 `
    {{0b00000, 0b00000, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111}},  // 97 a
    {{0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b11110}},  // 98 b
    {{0b00000, 0b00000, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110}},  // 99 c
    {{0b00001, 0b00001, 0b01101, 0b10011, 0b10001, 0b10001, 0b01111}},  // 100 d
    {{0b00000, 0b00000, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110}},  // 101 e
    {{0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000}},  // 102 f
    {{0b00000, 0b01111, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110}},  // 103 g
    {{0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001}},  // 104 h
    {{0b00100, 0b00000, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110}},  // 105 i
    {{0b00010, 0b00000, 0b00110, 0b00010, 0b00010, 0b10010, 0b01100}},  // 106 j
    {{0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010}},  // 107 k
    {{0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110}},  // 108 l
    {{0b00000, 0b00000, 0b11010, 0b10101, 0b10101, 0b10001, 0b10001}},  // 109 m
    {{0b00000, 0b00000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001}},  // 110 n
    {{0b00000, 0b00000, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110}},  // 111 o
    {{0b00000, 0b00000, 0b11110, 0b10001, 0b11110, 0b10000, 0b10000}},  // 112 p
    {{0b00000, 0b00000, 0b01101, 0b10011, 0b01111, 0b00001, 0b00001}},  // 113 q
    {{0b00000, 0b00000, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000}},  // 114 r
    {{0b00000, 0b00000, 0b01110, 0b10000, 0b01110, 0b00001, 0b11110}},  // 115 s
    {{0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110}},  // 116 t
    {{0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101}},  // 117 u
    {{0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100}},  // 118 v
    {{0b00000, 0b00000, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010}},  // 119 w
    {{0b00000, 0b00000, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001}},  // 120 x
    {{0b00000, 0b00000, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110}},  // 121 y
    {{0b00000, 0b00000, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111}},  // 122 z
    {{0b00010, 0b00100, 0b00100, 0b01000, 0b00100, 0b00100, 0b00010}},  // 123 {
    {{0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100}},  // 124 |
    {{0b01000, 0b00100, 0b00100, 0b00010, 0b00100, 0b00100, 0b01000}},  // 125 }
    {{0b00000, 0b00000, 0b01000, 0b10101, 0b00010, 0b00000, 0b00000}},  // 126 ~
}};

/// The glyph of `c`; characters outside 32–126 get the glyph of '?'.
[[nodiscard]] constexpr const glyph& glyph_for(char c) noexcept {
  const auto code = static_cast<unsigned char>(c);
  if (code < 32 || code > 126) return font_glyphs['?' - 32];
  return font_glyphs[static_cast<std::size_t>(code - 32)];
}

namespace detail {
constexpr int clamp_scale(int scale) noexcept { return std::clamp(scale, 1, max_text_scale); }
}  // namespace detail

/// Width in pixels of the widest line of `text` at `scale` (no trailing spacing column);
/// 0 for empty text. Saturates at 2^20 characters per line. Complexity: O(text.size()).
[[nodiscard]] constexpr int text_width(std::string_view text, int scale = 1) noexcept {
  const int s = detail::clamp_scale(scale);
  std::size_t widest = 0;
  std::size_t current = 0;
  for (const char c : text) {
    if (c == '\n') {
      current = 0;
      continue;
    }
    ++current;
    widest = std::max(widest, current);
  }
  if (widest == 0) return 0;
  const std::size_t limit = std::size_t{1} << 20;  // saturates instead of overflowing
  return static_cast<int>(std::min(widest, limit)) * glyph_advance_x * s - s;
}

/// Height in pixels of `text` at `scale`: lines × 8 − 1 (times scale); 0 for empty text.
/// Saturates at 2^20 lines.
[[nodiscard]] constexpr int text_height(std::string_view text, int scale = 1) noexcept {
  if (text.empty()) return 0;
  const int s = detail::clamp_scale(scale);
  std::size_t lines = 1;
  for (const char c : text)
    if (c == '\n') ++lines;
  const std::size_t limit = std::size_t{1} << 20;  // saturates instead of overflowing
  return static_cast<int>(std::min(lines, limit)) * glyph_advance_y * s - s;
}

/// A pixel rectangle [x, x + width) × [y, y + height) (may extend past the canvas).
struct text_box {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

/// How `draw_text` draws.
struct text_options {
  int scale = 1;                     ///< 1..max_text_scale (clamped)
  float alpha = 1.0f;                ///< opacity of the glyphs
  std::optional<rgb> background{};   ///< a box behind the text, if set
  float background_alpha = 0.75f;    ///< opacity of the box
  int padding_px = 2;                ///< box margin around the text (clamped to 0..1000)
};

namespace detail {

/// Blends the pixel rectangle [x, x + w) × [y, y + h) given in 64-bit coordinates (clipped).
template <RgbPixel P>
void blend_box(image_view<P> canvas, std::int64_t x, std::int64_t y, std::int64_t w,
               std::int64_t h, rgb colour, float alpha) noexcept {
  const std::int64_t x0 = std::max<std::int64_t>(x, 0);
  const std::int64_t y0 = std::max<std::int64_t>(y, 0);
  const std::int64_t x1 = std::min<std::int64_t>(x + w, canvas.width());
  const std::int64_t y1 = std::min<std::int64_t>(y + h, canvas.height());
  if (x0 >= x1 || y0 >= y1) return;
  fill_rect(canvas, static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(x1 - x0),
            static_cast<int>(y1 - y0), colour, alpha);
}

}  // namespace detail

/// Draws `text` with the top-left of its first glyph at (x, y), lines separated by '\n', in
/// `colour`; with `options.background`, first a box `padding_px` larger than the text on each
/// side. Clipped to the canvas (any x, y is safe). Returns the box covered by the text and
/// its padding (whether or not a background was drawn).
/// Complexity: O(text.size() × scale²), glyphs wholly off the canvas are skipped.
template <RgbPixel P>
text_box draw_text(image_view<P> canvas, int x, int y, std::string_view text, rgb colour,
                   const text_options& options = {}) noexcept {
  const int s = detail::clamp_scale(options.scale);
  const int pad = std::clamp(options.padding_px, 0, 1000);
  const auto saturate = [](std::int64_t v) {
    return static_cast<int>(std::clamp<std::int64_t>(v, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
  };
  const text_box box{saturate(std::int64_t{x} - pad), saturate(std::int64_t{y} - pad),
                     text_width(text, s) + 2 * pad, text_height(text, s) + 2 * pad};
  if (text.empty()) return box;
  if (options.background)
    detail::blend_box(canvas, std::int64_t{x} - pad, std::int64_t{y} - pad, box.width,
                      box.height, *options.background, options.background_alpha);
  std::int64_t pen_x = x;
  std::int64_t pen_y = y;
  const std::int64_t advance_x = std::int64_t{glyph_advance_x} * s;
  const std::int64_t advance_y = std::int64_t{glyph_advance_y} * s;
  for (const char c : text) {
    if (c == '\n') {
      pen_x = x;
      pen_y += advance_y;
      continue;
    }
    const bool visible = pen_x + advance_x > 0 && pen_x < canvas.width() &&
                         pen_y + advance_y > 0 && pen_y < canvas.height();
    if (visible) {
      const glyph& g = glyph_for(c);
      for (int row = 0; row < glyph_height; ++row)
        for (int col = 0; col < glyph_width; ++col)
          if ((static_cast<unsigned>(g[static_cast<std::size_t>(row)]) >>
               static_cast<unsigned>(glyph_width - 1 - col)) & 1u)
            detail::blend_box(canvas, pen_x + std::int64_t{col} * s,
                              pen_y + std::int64_t{row} * s, s, s, colour, options.alpha);
    }
    pen_x += advance_x;
  }
  return box;
}

/// The marker drawn left of a legend label.
enum class legend_marker : std::uint8_t {
  swatch,  ///< a filled square
  line,    ///< a horizontal line two pixels thick (times scale)
  dot,     ///< a filled disc
  outline, ///< a hollow square
  ramp,    ///< the `colour_map` ramp (colour ignored), e.g. "skeleton: diameter 10-80 mm"
};

/// One legend row.
struct legend_entry {
  std::string_view label;
  rgb colour = colours::white;
  legend_marker marker = legend_marker::swatch;
  float alpha = 1.0f;  ///< opacity of the marker, e.g. faint for rejected windows
  colour_ramp ramp = colour_ramp::perceptual;  ///< for `legend_marker::ramp`
};

/// How `draw_legend` looks.
struct legend_options {
  int scale = 1;                      ///< text and marker scale (clamped to 1..max_text_scale)
  rgb text = colours::white;          ///< label colour
  rgb background = colours::black;    ///< box colour
  float background_alpha = 0.7f;      ///< box opacity
  int padding_px = 4;                 ///< margin inside the box, times scale
};

namespace detail {
struct legend_metrics {
  int s;
  int pad;
  int marker_w;
  int marker_h;
  int gap;
  int row_h;
};
constexpr legend_metrics legend_layout(const legend_options& options) noexcept {
  const int s = clamp_scale(options.scale);
  return {s, std::clamp(options.padding_px, 0, 100) * s, 14 * s, glyph_height * s, 4 * s,
          (glyph_advance_y + 3) * s};
}
}  // namespace detail

/// The size of the legend box `draw_legend` would draw (x = y = 0). Labels are single lines
/// ('\n' is drawn as nothing special: keep labels on one line).
[[nodiscard]] constexpr text_box legend_size(std::span<const legend_entry> entries,
                                             const legend_options& options = {}) noexcept {
  if (entries.empty()) return {};
  const detail::legend_metrics m = detail::legend_layout(options);
  int label_w = 0;
  for (const legend_entry& e : entries) label_w = std::max(label_w, text_width(e.label, m.s));
  const int rows = static_cast<int>(std::min<std::size_t>(entries.size(), 10000));
  return {0, 0, 2 * m.pad + m.marker_w + m.gap + label_w, 2 * m.pad + rows * m.row_h - 3 * m.s};
}

/// Draws a legend box with its top-left corner at (x, y): one row per entry, a marker then
/// the label. Clipped to the canvas. Returns the box (as `legend_size`, moved to x, y).
template <RgbPixel P>
text_box draw_legend(image_view<P> canvas, int x, int y, std::span<const legend_entry> entries,
                     const legend_options& options = {}) noexcept {
  text_box box = legend_size(entries, options);
  box.x = x;
  box.y = y;
  if (entries.empty()) return box;
  const detail::legend_metrics m = detail::legend_layout(options);
  detail::blend_box(canvas, x, y, box.width, box.height, options.background,
                    options.background_alpha);
  const std::int64_t left = std::int64_t{x} + m.pad;
  std::int64_t top = std::int64_t{y} + m.pad;
  for (const legend_entry& e : entries) {
    switch (e.marker) {
      case legend_marker::swatch:
        detail::blend_box(canvas, left + 3 * m.s, top, m.marker_h, m.marker_h, e.colour, e.alpha);
        break;
      case legend_marker::outline:
        for (int i = 0; i < m.s; ++i) {
          detail::blend_box(canvas, left + 3 * m.s, top + i, m.marker_h, 1, e.colour, e.alpha);
          detail::blend_box(canvas, left + 3 * m.s, top + m.marker_h - 1 - i, m.marker_h, 1,
                            e.colour, e.alpha);
          detail::blend_box(canvas, left + 3 * m.s + i, top + m.s, 1, m.marker_h - 2 * m.s,
                            e.colour, e.alpha);
          detail::blend_box(canvas, left + 3 * m.s + m.marker_h - 1 - i, top + m.s, 1,
                            m.marker_h - 2 * m.s, e.colour, e.alpha);
        }
        break;
      case legend_marker::line:
        detail::blend_box(canvas, left, top + 2 * m.s, m.marker_w, 2 * m.s, e.colour, e.alpha);
        break;
      case legend_marker::dot: {
        const std::int64_t cx = left + m.marker_w / 2;
        const std::int64_t cy = top + m.marker_h / 2;
        if (cx >= -1000 && cx <= std::int64_t{canvas.width()} + 1000 && cy >= -1000 &&
            cy <= std::int64_t{canvas.height()} + 1000)
          fill_circle(canvas, draw_point{static_cast<float>(cx), static_cast<float>(cy)},
                      static_cast<float>(m.marker_h) / 2.0f, e.colour, e.alpha);
        break;
      }
      case legend_marker::ramp:
        for (int i = 0; i < m.marker_w; ++i) {
          const float t = static_cast<float>(i) / static_cast<float>(m.marker_w - 1);
          detail::blend_box(canvas, left + i, top, 1, m.marker_h, colour_map(t, e.ramp), e.alpha);
        }
        break;
    }
    const std::int64_t text_x = left + m.marker_w + m.gap;
    if (text_x <= canvas.width() && top <= canvas.height() && text_x >= -(std::int64_t{1} << 30) &&
        top >= -(std::int64_t{1} << 30))
      draw_text(canvas, static_cast<int>(text_x), static_cast<int>(top), e.label, options.text,
                text_options{.scale = m.s, .alpha = 1.0f, .background = std::nullopt,
                             .background_alpha = 0.0f, .padding_px = 0});
    top += m.row_h;
  }
  return box;
}

}  // namespace perch::support
