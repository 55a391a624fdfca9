// SPDX-License-Identifier: BSL-1.0
/// \file
/// Drawing primitives for annotated pictures (the perch tool's `--annotate`). Host code, not
/// part of the library.
///
/// **Canvas.** A canvas is a `perch::image_view<P>` of an 8-bit RGB pixel type `P` (concept
/// `RgbPixel`: members `r`, `g`, `b` of type `std::uint8_t`). `perch::support::rgb` is the
/// pixel type defined here; `perch::png::rgb8` satisfies the concept as well, so a tool can
/// draw straight onto the `image<png::rgb8>` it reads and writes (`img.view()`). Colours are
/// always passed as `rgb`.
///
/// **Coordinates.** (x, y) = (column, row), origin top-left, y down, as everywhere in perch.
/// Integer coordinates are pixel *centres*: pixel (x, y) covers [x − ½, x + ½] × [y − ½, y + ½],
/// so a skeleton pixel's centre is exactly where its integer coordinates say.
///
/// **Clipping.** Every primitive clips to the canvas: any input — shapes far outside, huge
/// coordinates, infinities, NaN, negative sizes, an empty canvas — never writes outside the
/// view. Non-finite geometry draws nothing (except where stated); work is bounded by the
/// canvas area, never by the shape's size.
///
/// **Blending.** `alpha` in [0, 1] mixes the colour over the pixel: out = in + (c − in)·alpha,
/// rounded; NaN alpha draws nothing. Each filled shape touches each pixel at most once, so a
/// translucent shape has a uniform tint. (A polyline's segments may overlap at the joints.)
///
/// No anti-aliasing: shapes are sampled at pixel centres; thin lines are Bresenham lines.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <span>
#include <type_traits>

#include "perch/core/image_view.hpp"

namespace perch::support {

/// An 8-bit sRGB colour, and the canvas pixel type of this header.
struct rgb {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend constexpr bool operator==(const rgb&, const rgb&) noexcept = default;
};

/// A pixel type a canvas can hold: three `std::uint8_t` members `r`, `g`, `b`.
template <class P>
concept RgbPixel = std::is_default_constructible_v<P> && requires(P& p) {
  requires std::same_as<decltype(P::r), std::uint8_t>;
  requires std::same_as<decltype(P::g), std::uint8_t>;
  requires std::same_as<decltype(P::b), std::uint8_t>;
};

/// A few named colours for annotations.
namespace colours {
inline constexpr rgb black{0, 0, 0};
inline constexpr rgb white{255, 255, 255};
inline constexpr rgb gray{128, 128, 128};
inline constexpr rgb red{230, 40, 40};
inline constexpr rgb green{40, 200, 70};
inline constexpr rgb blue{50, 110, 240};
inline constexpr rgb yellow{250, 220, 30};
inline constexpr rgb orange{250, 140, 20};
inline constexpr rgb magenta{220, 50, 200};
inline constexpr rgb cyan{40, 210, 230};
}  // namespace colours

/// A point in canvas coordinates (pixel centres at integers).
struct draw_point {
  float x = 0.0f;
  float y = 0.0f;
};

/// A rectangle of `length` × `width` centred on `centre`, its length axis along
/// (cos angle, sin angle) in image coordinates — y points down, so a positive angle turns
/// clockwise on screen. Angles in degrees. Used for the chosen perch: length = claw width,
/// width = branch diameter, angle = branch direction.
struct rotated_rect {
  draw_point centre{};
  float length = 0.0f;
  float width = 0.0f;
  float angle_deg = 0.0f;
};

namespace detail {

/// The canvas pixels whose centres lie in [x_min, x_max] × [y_min, y_max]: x0..x1, y0..y1
/// inclusive, clipped to the canvas; `empty()` if none (or if a bound is NaN).
struct pixel_range {
  int x0 = 0;
  int y0 = 0;
  int x1 = -1;
  int y1 = -1;
  [[nodiscard]] bool empty() const noexcept { return x0 > x1 || y0 > y1; }
};

inline pixel_range clip_range(int width, int height, double x_min, double y_min, double x_max,
                              double y_max) noexcept {
  if (std::isnan(x_min) || std::isnan(y_min) || std::isnan(x_max) || std::isnan(y_max) ||
      width <= 0 || height <= 0)
    return {};
  const auto lo = [](double v, int size) {
    return static_cast<int>(std::clamp(std::ceil(v), 0.0, static_cast<double>(size)));
  };
  const auto hi = [](double v, int size) {
    return static_cast<int>(std::clamp(std::floor(v), -1.0, static_cast<double>(size - 1)));
  };
  return {lo(x_min, width), lo(y_min, height), hi(x_max, width), hi(y_max, height)};
}

inline std::uint8_t mix_channel(std::uint8_t in, std::uint8_t c, float alpha) noexcept {
  const float v = static_cast<float>(in) + (static_cast<float>(c) - static_cast<float>(in)) * alpha;
  return static_cast<std::uint8_t>(std::clamp(v + 0.5f, 0.0f, 255.0f));
}

inline float clamp_alpha(float alpha) noexcept {
  if (std::isnan(alpha)) return 0.0f;
  return std::clamp(alpha, 0.0f, 1.0f);
}

template <RgbPixel P>
void blend_unchecked(P& p, rgb c, float alpha) noexcept {
  if (alpha >= 1.0f) {
    p.r = c.r;
    p.g = c.g;
    p.b = c.b;
  } else if (alpha > 0.0f) {
    p.r = mix_channel(p.r, c.r, alpha);
    p.g = mix_channel(p.g, c.g, alpha);
    p.b = mix_channel(p.b, c.b, alpha);
  }
}

/// Blends `c` into every pixel of `range` whose centre satisfies `inside(x, y)` (doubles).
template <RgbPixel P, class Inside>
void fill_where(image_view<P> canvas, pixel_range range, rgb c, float alpha, Inside inside) {
  alpha = clamp_alpha(alpha);
  if (range.empty() || alpha <= 0.0f) return;
  for (int y = range.y0; y <= range.y1; ++y)
    for (int x = range.x0; x <= range.x1; ++x)
      if (inside(static_cast<double>(x), static_cast<double>(y)))
        blend_unchecked(canvas(x, y), c, alpha);
}

inline bool finite(draw_point p) noexcept { return std::isfinite(p.x) && std::isfinite(p.y); }

/// Squared distance from (px, py) to the segment a–b.
inline double segment_distance_sq(double px, double py, double ax, double ay, double bx,
                                  double by) noexcept {
  const double dx = bx - ax;
  const double dy = by - ay;
  const double len_sq = dx * dx + dy * dy;
  double t = 0.0;
  if (len_sq > 0.0) t = std::clamp(((px - ax) * dx + (py - ay) * dy) / len_sq, 0.0, 1.0);
  const double ex = px - (ax + t * dx);
  const double ey = py - (ay + t * dy);
  return ex * ex + ey * ey;
}

/// Clips the segment a–b to the box [lo_x, hi_x] × [lo_y, hi_y] (Liang–Barsky). False if
/// nothing is left or the numbers are not finite.
inline bool clip_segment(double& ax, double& ay, double& bx, double& by, double lo_x, double lo_y,
                         double hi_x, double hi_y) noexcept {
  const double dx = bx - ax;
  const double dy = by - ay;
  if (!std::isfinite(dx) || !std::isfinite(dy)) return false;
  double t0 = 0.0;
  double t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {ax - lo_x, hi_x - ax, ay - lo_y, hi_y - ay};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      if (t > t1) return false;
      t0 = std::max(t0, t);
    } else {
      if (t < t0) return false;
      t1 = std::min(t1, t);
    }
  }
  const double nax = ax + t0 * dx;
  const double nay = ay + t0 * dy;
  bx = ax + t1 * dx;
  by = ay + t1 * dy;
  ax = nax;
  ay = nay;
  return true;
}

}  // namespace detail

/// Blends `colour` into pixel (x, y); does nothing outside the canvas.
template <RgbPixel P>
void put_pixel(image_view<P> canvas, int x, int y, rgb colour, float alpha = 1.0f) noexcept {
  if (!canvas.contains(x, y)) return;
  detail::blend_unchecked(canvas(x, y), colour, detail::clamp_alpha(alpha));
}

/// The colour of pixel (x, y) as `rgb` (black outside the canvas).
template <RgbPixel P>
[[nodiscard]] rgb get_pixel(image_view<P> canvas, int x, int y) noexcept {
  if (!canvas.contains(x, y)) return {};
  const P& p = canvas(x, y);
  return {p.r, p.g, p.b};
}

/// Sets every pixel to `colour`.
template <RgbPixel P>
void fill(image_view<P> canvas, rgb colour) noexcept {
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = 0; x < canvas.width(); ++x) detail::blend_unchecked(canvas(x, y), colour, 1.0f);
}

/// Paints a binary mask onto the canvas: `tree` where the mask is non-zero, `background`
/// elsewhere. Only the overlap of the two views is painted (no size check needed).
template <ImageView M, RgbPixel P>
void paint_mask(const M& mask, image_view<P> canvas, rgb tree, rgb background) noexcept {
  const int w = std::min(mask.width(), canvas.width());
  const int h = std::min(mask.height(), canvas.height());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      detail::blend_unchecked(canvas(x, y), mask(x, y) ? tree : background, 1.0f);
}

/// How `dim` turns a photo into a quiet background for annotations.
struct dim_options {
  float saturation = 0.0f;  ///< 0 = gray (BT.601 luma), 1 = original colours
  rgb towards = colours::black;  ///< colour to fade towards
  float amount = 0.5f;      ///< 0 = unchanged, 1 = all `towards`
};

/// Desaturates every pixel, then fades it towards `options.towards` by `options.amount`
/// (both clamped to [0, 1]; NaN counts as 0).
template <RgbPixel P>
void dim(image_view<P> canvas, const dim_options& options = {}) noexcept {
  const float s = detail::clamp_alpha(options.saturation);
  const float a = detail::clamp_alpha(options.amount);
  for (int y = 0; y < canvas.height(); ++y) {
    for (int x = 0; x < canvas.width(); ++x) {
      P& p = canvas(x, y);
      const float luma = 0.299f * static_cast<float>(p.r) + 0.587f * static_cast<float>(p.g) +
                         0.114f * static_cast<float>(p.b);
      const auto channel = [&](std::uint8_t v, std::uint8_t target) {
        const float d = luma + (static_cast<float>(v) - luma) * s;
        const float out = d + (static_cast<float>(target) - d) * a;
        return static_cast<std::uint8_t>(std::clamp(out + 0.5f, 0.0f, 255.0f));
      };
      p.r = channel(p.r, options.towards.r);
      p.g = channel(p.g, options.towards.g);
      p.b = channel(p.b, options.towards.b);
    }
  }
}

/// Fills the axis-aligned rectangle of pixels [x, x + w) × [y, y + h) (clipped).
template <RgbPixel P>
void fill_rect(image_view<P> canvas, int x, int y, int w, int h, rgb colour,
               float alpha = 1.0f) noexcept {
  if (w <= 0 || h <= 0) return;
  const double x0 = x;
  const double y0 = y;
  const auto range = detail::clip_range(canvas.width(), canvas.height(), x0, y0,
                                        x0 + static_cast<double>(w) - 1.0,
                                        y0 + static_cast<double>(h) - 1.0);
  detail::fill_where(canvas, range, colour, alpha, [](double, double) { return true; });
}

/// Outlines the axis-aligned rectangle [x, x + w) × [y, y + h) with a border `thickness_px`
/// pixels wide, inside the rectangle (clipped).
template <RgbPixel P>
void draw_rect(image_view<P> canvas, int x, int y, int w, int h, rgb colour, int thickness_px = 1,
               float alpha = 1.0f) noexcept {
  if (w <= 0 || h <= 0 || thickness_px <= 0) return;
  const double x0 = x;
  const double y0 = y;
  const double x1 = x0 + static_cast<double>(w) - 1.0;
  const double y1 = y0 + static_cast<double>(h) - 1.0;
  const double t = thickness_px;
  const auto range = detail::clip_range(canvas.width(), canvas.height(), x0, y0, x1, y1);
  detail::fill_where(canvas, range, colour, alpha, [=](double px, double py) {
    return px < x0 + t || px > x1 - t || py < y0 + t || py > y1 - t;
  });
}

/// Fills the disc of `radius_px` around `centre`: pixels whose centre is within
/// sqrt(radius² + ¼) (so radius 0 on a pixel centre is one pixel, radius 1 a plus sign).
template <RgbPixel P>
void fill_circle(image_view<P> canvas, draw_point centre, float radius_px, rgb colour,
                 float alpha = 1.0f) noexcept {
  if (!detail::finite(centre) || std::isnan(radius_px) || radius_px < 0.0f) return;
  const double cx = static_cast<double>(centre.x);
  const double cy = static_cast<double>(centre.y);
  const double r = static_cast<double>(radius_px);
  const double limit = r * r + 0.25;
  const auto range = detail::clip_range(canvas.width(), canvas.height(), cx - r - 1.0,
                                        cy - r - 1.0, cx + r + 1.0, cy + r + 1.0);
  detail::fill_where(canvas, range, colour, alpha, [=](double x, double y) {
    return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= limit;
  });
}

/// Outlines the circle of `radius_px` around `centre` with a ring `thickness_px` wide (at
/// least one pixel), centred on the radius.
template <RgbPixel P>
void draw_circle(image_view<P> canvas, draw_point centre, float radius_px, rgb colour,
                 float thickness_px = 1.0f, float alpha = 1.0f) noexcept {
  if (!detail::finite(centre) || std::isnan(radius_px) || radius_px < 0.0f ||
      std::isnan(thickness_px))
    return;
  const double cx = static_cast<double>(centre.x);
  const double cy = static_cast<double>(centre.y);
  const double half = std::max(static_cast<double>(thickness_px), 1.0) / 2.0;
  const double outer = static_cast<double>(radius_px) + half;
  const double inner = std::max(static_cast<double>(radius_px) - half, 0.0);
  const double outer_sq = outer * outer + 0.25;
  const double inner_sq = inner * inner - 0.25;
  const auto range = detail::clip_range(canvas.width(), canvas.height(), cx - outer - 1.0,
                                        cy - outer - 1.0, cx + outer + 1.0, cy + outer + 1.0);
  detail::fill_where(canvas, range, colour, alpha, [=](double x, double y) {
    const double d = (x - cx) * (x - cx) + (y - cy) * (y - cy);
    return d <= outer_sq && d >= inner_sq;
  });
}

namespace detail {

/// Bresenham's line between the pixels nearest to a and b, clipped to the canvas;
/// `skip_first` leaves out a's pixel (for polyline joints).
template <RgbPixel P>
void bresenham(image_view<P> canvas, draw_point a, draw_point b, rgb colour, float alpha,
               bool skip_first) noexcept {
  if (!finite(a) || !finite(b) || canvas.empty()) return;
  double ax = static_cast<double>(a.x);
  double ay = static_cast<double>(a.y);
  double bx = static_cast<double>(b.x);
  double by = static_cast<double>(b.y);
  const bool a_inside = ax >= -0.5 && ay >= -0.5 && ax <= canvas.width() - 0.5 &&
                        ay <= canvas.height() - 0.5;
  if (!clip_segment(ax, ay, bx, by, -0.5, -0.5, canvas.width() - 0.5, canvas.height() - 0.5))
    return;
  if (!a_inside) skip_first = false;  // a's own pixel is off the canvas anyway
  // Coordinates are now within the canvas ± 1: ints are safe.
  int x0 = static_cast<int>(std::lround(ax));
  int y0 = static_cast<int>(std::lround(ay));
  const int x1 = static_cast<int>(std::lround(bx));
  const int y1 = static_cast<int>(std::lround(by));
  const int dx = std::abs(x1 - x0);
  const int dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1;
  const int sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  bool first = true;
  while (true) {
    if (!(first && skip_first)) put_pixel(canvas, x0, y0, colour, alpha);
    first = false;
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += sy;
    }
  }
}

/// Every pixel whose centre is within `half_px` (+ a quarter pixel²) of the segment a–b.
template <RgbPixel P>
void capsule(image_view<P> canvas, draw_point a, draw_point b, double half_px, rgb colour,
             float alpha) noexcept {
  if (!finite(a) || !finite(b) || std::isnan(half_px)) return;
  const double ax = static_cast<double>(a.x);
  const double ay = static_cast<double>(a.y);
  const double bx = static_cast<double>(b.x);
  const double by = static_cast<double>(b.y);
  const double limit = half_px * half_px + 0.25;
  const auto range = clip_range(canvas.width(), canvas.height(), std::min(ax, bx) - half_px - 1.0,
                                std::min(ay, by) - half_px - 1.0, std::max(ax, bx) + half_px + 1.0,
                                std::max(ay, by) + half_px + 1.0);
  fill_where(canvas, range, colour, alpha, [=](double x, double y) {
    return segment_distance_sq(x, y, ax, ay, bx, by) <= limit;
  });
}

}  // namespace detail

/// Draws the segment a–b. `thickness_px` ≤ 1: a Bresenham line between the pixels nearest
/// to a and b. Thicker: every pixel whose centre is within thickness/2 of the segment (a
/// line with round caps). Clipped; non-finite endpoints draw nothing.
template <RgbPixel P>
void draw_line(image_view<P> canvas, draw_point a, draw_point b, rgb colour,
               float thickness_px = 1.0f, float alpha = 1.0f) noexcept {
  if (std::isnan(thickness_px)) return;
  if (thickness_px <= 1.0f)
    detail::bresenham(canvas, a, b, colour, alpha, false);
  else
    detail::capsule(canvas, a, b, static_cast<double>(thickness_px) / 2.0, colour, alpha);
}

/// Draws the open polyline through `points` (segments as `draw_line`). Thin polylines do not
/// plot a joint twice; thick ones may overlap at the joints. A single point draws a dot.
template <RgbPixel P>
void draw_polyline(image_view<P> canvas, std::span<const draw_point> points, rgb colour,
                   float thickness_px = 1.0f, float alpha = 1.0f) noexcept {
  if (points.empty() || std::isnan(thickness_px)) return;
  if (points.size() == 1) {
    draw_line(canvas, points[0], points[0], colour, thickness_px, alpha);
    return;
  }
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (thickness_px <= 1.0f)
      detail::bresenham(canvas, points[i - 1], points[i], colour, alpha, i > 1);
    else
      detail::capsule(canvas, points[i - 1], points[i], static_cast<double>(thickness_px) / 2.0,
                      colour, alpha);
  }
}

/// The four corners of `rect`, in order around it.
[[nodiscard]] inline std::array<draw_point, 4> corners(const rotated_rect& rect) noexcept {
  const double a = static_cast<double>(rect.angle_deg) * 3.14159265358979323846 / 180.0;
  const double ux = std::cos(a) * static_cast<double>(rect.length) / 2.0;
  const double uy = std::sin(a) * static_cast<double>(rect.length) / 2.0;
  const double vx = -std::sin(a) * static_cast<double>(rect.width) / 2.0;
  const double vy = std::cos(a) * static_cast<double>(rect.width) / 2.0;
  const double cx = static_cast<double>(rect.centre.x);
  const double cy = static_cast<double>(rect.centre.y);
  const auto pt = [](double x, double y) {
    return draw_point{static_cast<float>(x), static_cast<float>(y)};
  };
  return {pt(cx - ux - vx, cy - uy - vy), pt(cx + ux - vx, cy + uy - vy),
          pt(cx + ux + vx, cy + uy + vy), pt(cx - ux + vx, cy - uy + vy)};
}

namespace detail {

/// Pixels inside the rectangle grown by `grow` on every side but not inside it shrunk by
/// `shrink` (no hole if `shrink` < 0).
template <RgbPixel P>
void rotated_band(image_view<P> canvas, const rotated_rect& rect, double grow, double shrink,
                  rgb colour, float alpha) noexcept {
  if (!finite(rect.centre) || !std::isfinite(rect.angle_deg) || std::isnan(rect.length) ||
      std::isnan(rect.width) || rect.length < 0.0f || rect.width < 0.0f)
    return;
  const double a = static_cast<double>(rect.angle_deg) * 3.14159265358979323846 / 180.0;
  const double ux = std::cos(a);
  const double uy = std::sin(a);
  const double cx = static_cast<double>(rect.centre.x);
  const double cy = static_cast<double>(rect.centre.y);
  const double half_l = static_cast<double>(rect.length) / 2.0;
  const double half_w = static_cast<double>(rect.width) / 2.0;
  const double out_l = std::max(half_l + grow, 0.5);  // never thinner than a pixel
  const double out_w = std::max(half_w + grow, 0.5);
  const double in_l = half_l - shrink;
  const double in_w = half_w - shrink;
  const bool hollow = shrink >= 0.0 && in_l > 0.0 && in_w > 0.0;
  const double extent = std::abs(ux) * out_l + std::abs(uy) * out_w + 1.0;
  const double extent_y = std::abs(uy) * out_l + std::abs(ux) * out_w + 1.0;
  const auto range = clip_range(canvas.width(), canvas.height(), cx - extent, cy - extent_y,
                                cx + extent, cy + extent_y);
  fill_where(canvas, range, colour, alpha, [=](double x, double y) {
    const double u = std::abs((x - cx) * ux + (y - cy) * uy);
    const double v = std::abs(-(x - cx) * uy + (y - cy) * ux);
    if (u > out_l || v > out_w) return false;
    return !(hollow && u < in_l && v < in_w);
  });
}

}  // namespace detail

/// Fills `rect`: pixels whose centre lies inside it or on its edge (sides shorter than a pixel
/// count as one pixel, so a thin rectangle still shows). Non-finite or negative sizes draw
/// nothing.
template <RgbPixel P>
void fill_rotated_rect(image_view<P> canvas, const rotated_rect& rect, rgb colour,
                       float alpha = 1.0f) noexcept {
  detail::rotated_band(canvas, rect, 1e-6, -1.0, colour, alpha);
}

/// Outlines `rect` with a border `thickness_px` wide (at least one pixel) centred on its
/// edges. Each pixel is touched once, so a translucent outline has a uniform tint.
template <RgbPixel P>
void draw_rotated_rect(image_view<P> canvas, const rotated_rect& rect, rgb colour,
                       float thickness_px = 1.0f, float alpha = 1.0f) noexcept {
  if (std::isnan(thickness_px)) return;
  const double half = std::max(static_cast<double>(thickness_px), 1.0) / 2.0;
  detail::rotated_band(canvas, rect, half, half, colour, alpha);
}

/// Colour ramps for `colour_map`.
enum class colour_ramp : std::uint8_t {
  perceptual,  ///< dark violet → blue → teal → green → yellow; luminance rises monotonically
               ///< (viridis-like, perch's own control points)
  gray,        ///< black → white
};

/// The colour at `t` ∈ [0, 1] on `ramp` (clamped; NaN maps to 0), linear between control
/// points.
[[nodiscard]] inline rgb colour_map(float t, colour_ramp ramp = colour_ramp::perceptual) noexcept {
  if (std::isnan(t)) t = 0.0f;
  t = std::clamp(t, 0.0f, 1.0f);
  if (ramp == colour_ramp::gray) {
    const auto v = static_cast<std::uint8_t>(t * 255.0f + 0.5f);
    return {v, v, v};
  }
  // perch's own control points, evenly spaced in t (luma 39, 81, 114, 157, 215).
  static constexpr rgb stops[] = {
      {72, 20, 96}, {62, 84, 150}, {36, 132, 142}, {86, 180, 100}, {240, 226, 40},
  };
  constexpr int segments = static_cast<int>(std::size(stops)) - 1;
  const float position = t * static_cast<float>(segments);
  const int i = std::min(static_cast<int>(position), segments - 1);
  const float f = position - static_cast<float>(i);
  const rgb a = stops[i];
  const rgb b = stops[i + 1];
  return {detail::mix_channel(a.r, b.r, f), detail::mix_channel(a.g, b.g, f),
          detail::mix_channel(a.b, b.b, f)};
}

/// `colour_map` of `value` scaled from [low, high] to [0, 1] (low == high maps to 0).
[[nodiscard]] inline rgb colour_map(float value, float low, float high,
                                    colour_ramp ramp = colour_ramp::perceptual) noexcept {
  const float span = high - low;
  if (!(span > 0.0f) || !std::isfinite(span)) return colour_map(0.0f, ramp);
  return colour_map((value - low) / span, ramp);
}

/// Draws `ramp` left (t = 0) to right (t = 1) as a horizontal bar filling the pixel
/// rectangle [x, x + w) × [y, y + h) (clipped).
template <RgbPixel P>
void draw_colour_bar(image_view<P> canvas, int x, int y, int w, int h,
                     colour_ramp ramp = colour_ramp::perceptual) noexcept {
  if (w <= 0 || h <= 0) return;
  const double x0 = x;
  const double y0 = y;
  const auto range = detail::clip_range(canvas.width(), canvas.height(), x0, y0,
                                        x0 + static_cast<double>(w) - 1.0,
                                        y0 + static_cast<double>(h) - 1.0);
  if (range.empty()) return;
  for (int px = range.x0; px <= range.x1; ++px) {
    const double t = w == 1 ? 0.0 : (static_cast<double>(px) - x0) / static_cast<double>(w - 1);
    const rgb c = colour_map(static_cast<float>(t), ramp);
    for (int py = range.y0; py <= range.y1; ++py) detail::blend_unchecked(canvas(px, py), c, 1.0f);
  }
}

}  // namespace perch::support
