// SPDX-License-Identifier: BSL-1.0
// The kernel benchmarks' masks (distance_bench, skeleton_bench): a deterministic branching
// tree of thick strokes (~10-14 % foreground, touching the bottom edge) and a 50 % blob mask.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "perch/core/image.hpp"

namespace perch::bench {

// A deterministic tree: a trunk from the bottom centre, each branch forking twice with
// thinner, shorter children; strokes are discs swept along the segments.
inline void draw_stroke(perch::image<std::uint8_t>& m, double x0, double y0, double x1,
                        double y1, double r) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  const int steps = static_cast<int>(len) + 1;
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    const double cx = x0 + t * (x1 - x0), cy = y0 + t * (y1 - y0);
    const int ri = static_cast<int>(std::ceil(r));
    for (int dy = -ri; dy <= ri; ++dy)
      for (int dx = -ri; dx <= ri; ++dx) {
        const int x = static_cast<int>(std::lround(cx)) + dx;
        const int y = static_cast<int>(std::lround(cy)) + dy;
        if (x < 0 || y < 0 || x >= m.width() || y >= m.height()) continue;
        if (dx * dx + dy * dy <= r * r) m(x, y) = 1;
      }
  }
}

inline void draw_branch(perch::image<std::uint8_t>& m, double x, double y, double angle,
                        double length, double r, int depth) {
  const double x1 = x + length * std::cos(angle), y1 = y - length * std::sin(angle);
  draw_stroke(m, x, y, x1, y1, r);
  if (depth == 0 || r < 1.0) return;
  const double spread = 0.45 + 0.1 * (depth % 3);
  draw_branch(m, x1, y1, angle + spread, length * 0.72, r * 0.68, depth - 1);
  draw_branch(m, x1, y1, angle - spread * 0.8, length * 0.75, r * 0.7, depth - 1);
  if (depth % 2 == 0) draw_branch(m, x1, y1, angle + 0.1, length * 0.6, r * 0.6, depth - 1);
}

inline perch::image<std::uint8_t> tree_mask(int w, int h) {
  perch::image<std::uint8_t> m(w, h, 0);
  const double s = h / 1080.0;
  draw_branch(m, w / 2.0, h - 1.0, 1.5707963, 330.0 * s, 26.0 * s, 7);
  return m;
}

inline perch::image<std::uint8_t> blob_mask(int w, int h) {
  perch::image<std::uint8_t> m(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = std::sin(x * 0.013) * std::cos(y * 0.017) + 0.5 * std::sin((x + y) * 0.007);
      m(x, y) = v > 0.0 ? 1 : 0;
    }
  return m;
}

inline double foreground_share(const perch::image<std::uint8_t>& m) {
  std::size_t n = 0;
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x) n += m(x, y);
  return static_cast<double>(n) / static_cast<double>(m.view().size());
}

}  // namespace perch::bench
