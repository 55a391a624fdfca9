// SPDX-License-Identifier: BSL-1.0
#include "annotate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "support/draw.hpp"
#include "support/font.hpp"

namespace perch::tool {
namespace {

using support::draw_point;
using support::text_width;
using support::rgb;
namespace colours = support::colours;

constexpr rgb perch_colour{255, 215, 0};
constexpr rgb site_colour{60, 220, 90};
constexpr rgb miss_colour{240, 70, 60};
constexpr rgb pruned_colour{150, 150, 150};
constexpr rgb end_colour{250, 140, 20};
constexpr rgb trunk_colour{40, 210, 230};
constexpr rgb bridge_colour{170, 110, 255};

constexpr rgb tentative_colour{110, 170, 255};
constexpr rgb lost_colour{150, 150, 150};

struct frame {
  const perch_result& r;
  float zoom = 1.0f;  ///< picture pixels per input pixel
  /// Local (analysed, cropped) pixel → picture point.
  [[nodiscard]] draw_point at(pixel local) const {
    const point2f p = r.mask.to_input(point2f(static_cast<float>(local.x + r.mask.offset.x),
                                              static_cast<float>(local.y + r.mask.offset.y)));
    return {p.x() * zoom, p.y() * zoom};
  }
  /// Picture pixels per analysed pixel.
  [[nodiscard]] float scale() const { return zoom / r.mask.factor; }
};

/// Line and text sizes for a picture: strokes about a 320th of its larger side (at least 2 px),
/// text scale about a 480th (1 to 6).
struct picture_metrics {
  float stroke = 2;
  int text_scale = 1;
};
picture_metrics metrics_of(int width, int height) {
  const float size = static_cast<float>(std::max(width, height));
  return {std::max(2.0f, size / 320.0f), std::clamp(static_cast<int>(std::lround(size / 480.0f)), 1, 6)};
}

/// The mask, tree light and background dark, slightly dimmed; at `zoom` < 1 each picture pixel
/// mixes the two colours by the share of tree in the input pixels it covers.
void paint_mask_background(image_view<png::rgb8> canvas, const image<std::uint8_t>& mask, float zoom) {
  constexpr rgb tree{200, 196, 188}, background{16, 20, 28};
  if (zoom == 1.0f) {
    support::paint_mask(mask.view(), canvas, tree, background);
  } else {
    const auto edge = [&](int i, int size) {
      return std::clamp(static_cast<int>(std::floor(static_cast<float>(i) / zoom)), 0, size);
    };
    for (int y = 0; y < canvas.height(); ++y) {
      const int y0 = edge(y, mask.height()), y1 = std::max(edge(y + 1, mask.height()), std::min(y0 + 1, mask.height()));
      for (int x = 0; x < canvas.width(); ++x) {
        const int x0 = edge(x, mask.width()), x1 = std::max(edge(x + 1, mask.width()), std::min(x0 + 1, mask.width()));
        int on = 0, all = 0;
        for (int v = y0; v < y1; ++v)
          for (int u = x0; u < x1; ++u) {
            on += mask(u, v) != 0 ? 1 : 0;
            ++all;
          }
        support::put_pixel(canvas, x, y, background);
        if (on > 0) support::put_pixel(canvas, x, y, tree, static_cast<float>(on) / static_cast<float>(all));
      }
    }
  }
  support::dim(canvas, {.saturation = 0.0f, .towards = colours::black, .amount = 0.2f});
}

/// The pruned skeleton's branches coloured by diameter (0 to `diameter_top_mm`).
void draw_branches(image_view<png::rgb8> canvas, const frame& f, float diameter_top_mm, float stroke) {
  const float analysed_mm_per_px = f.r.mm_per_px / f.r.mask.factor;
  f.r.graph.for_each_branch([&](const skeleton_branch& b) {
    for (std::size_t i = 0; i < b.points.size(); ++i) {
      const float d_mm = diameter_px(b.radius_px[i]) * analysed_mm_per_px;
      const rgb c = support::colour_map(d_mm, 0.0f, diameter_top_mm);
      const draw_point p = f.at(b.points[i]);
      const draw_point q = i + 1 < b.points.size() ? f.at(b.points[i + 1]) : p;
      support::draw_line(canvas, p, q, c, stroke);
    }
  });
}

/// The status line(s) at the left, at the top (or at row `y` when ≥ 0), on `background`, in the
/// largest scale up to `text_scale` that fits the picture's width.
support::text_box draw_title(image_view<png::rgb8> canvas, const std::string& text, rgb colour, int text_scale,
                             int y = -1, rgb background = colours::black, float background_alpha = 0.7f) {
  int title_scale = text_scale;
  while (title_scale > 1 && text_width(text, title_scale) + 2 * 3 * title_scale + 12 * title_scale > canvas.width())
    --title_scale;
  return support::draw_text(canvas, 6 * title_scale, y >= 0 ? y : 6 * title_scale, text, colour,
                            {.scale = title_scale, .background = background, .background_alpha = background_alpha,
                             .padding_px = 3 * title_scale});
}

/// Draws the legend in the corner (top right, bottom right, bottom left) that hides the least
/// tree (`mask` at picture pixel / `zoom`), never the title, as few labels as it can, and not
/// `keep_clear` (the chosen perch) when given.
void place_legend(image_view<png::rgb8> canvas, std::span<const support::legend_entry> shown, int text_scale,
                  const image<std::uint8_t>* mask, float zoom, const support::text_box& title,
                  std::span<const support::text_box> labels, const draw_point* keep_clear) {
  const support::legend_options legend{.scale = text_scale};
  const support::text_box box = support::legend_size(shown, legend);
  const int margin = 6 * text_scale;
  const int corners[3][2] = {{canvas.width() - box.width - margin, margin},
                             {canvas.width() - box.width - margin, canvas.height() - box.height - margin},
                             {margin, canvas.height() - box.height - margin}};
  long best_cost = -1;
  int best = 0;
  for (int k = 0; k < 3; ++k) {
    const int x0 = std::max(0, corners[k][0]);
    const int y0 = std::max(0, corners[k][1]);
    const int x1 = std::min(canvas.width(), corners[k][0] + box.width);
    const int y1 = std::min(canvas.height(), corners[k][1] + box.height);
    long cost = 0;
    const auto covers = [&](const support::text_box& b) {
      return x0 < b.x + b.width && b.x < x1 && y0 < b.y + b.height && b.y < y1;
    };
    if (covers(title)) cost += 1L << 41;  // never over the title
    for (const support::text_box& label : labels) cost += covers(label) ? 1L << 36 : 0;  // nor a label
    if (mask != nullptr)
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const int u = std::min(static_cast<int>(static_cast<float>(x) / zoom), mask->width() - 1);
          const int v = std::min(static_cast<int>(static_cast<float>(y) / zoom), mask->height() - 1);
          cost += (*mask)(u, v) != 0 ? 1 : 0;
        }
    if (keep_clear != nullptr) {
      const draw_point c = *keep_clear;
      const float reach = static_cast<float>(12 * text_scale * 6);
      if (c.x + reach >= static_cast<float>(corners[k][0]) && c.x - reach < static_cast<float>(corners[k][0] + box.width) &&
          c.y + reach >= static_cast<float>(corners[k][1]) && c.y - reach < static_cast<float>(corners[k][1] + box.height))
        cost += 1L << 40;
    }
    if (best_cost < 0 || cost < best_cost) {
      best_cost = cost;
      best = k;
    }
  }
  support::draw_legend(canvas, corners[best][0], corners[best][1], shown, legend);
}

/// The branch's heading: an arrow along the window from its trunk-side end to its tip-side end
/// (picture pixels), its head at the tip side.
void draw_heading_arrow(image_view<png::rgb8> canvas, draw_point base, draw_point tip, rgb colour, float stroke) {
  const float dx = tip.x - base.x, dy = tip.y - base.y;
  const float length = std::hypot(dx, dy);
  if (!(length > 0)) return;
  support::draw_line(canvas, base, tip, colour, stroke);
  const float head = std::min(0.35f * length, 6.0f * stroke + 4.0f);
  const float ux = dx / length, uy = dy / length;
  for (const float side : {1.0f, -1.0f}) {  // two barbs at ±30° back from the tip
    const float bx = -ux * 0.866f - side * uy * 0.5f, by = -uy * 0.866f + side * ux * 0.5f;
    support::draw_line(canvas, tip, {tip.x + head * bx, tip.y + head * by}, colour, stroke);
  }
}

/// The chosen perch: a rectangle claw width (`length`) × diameter (`width`) along the branch at
/// `angle_deg`, ringed, filled faintly, the heading arrow from `base` to `tip`, and `label`
/// beside it, kept on the picture.
struct perch_marker {
  support::rotated_rect rect;
  draw_point base, tip;
  std::string label;
};
void draw_perch_marker(image_view<png::rgb8> canvas, const perch_marker& marker, float stroke, int text_scale) {
  const support::rotated_rect& rect = marker.rect;
  support::draw_circle(canvas, rect.centre, 0.5f * rect.length + 4.0f * stroke, perch_colour, stroke, 0.8f);
  support::fill_rotated_rect(canvas, rect, perch_colour, 0.3f);
  support::draw_rotated_rect(canvas, rect, perch_colour, std::max(2.0f, 0.8f * stroke));
  draw_heading_arrow(canvas, marker.base, marker.tip, perch_colour, stroke);
  const int w = support::text_width(marker.label, text_scale);
  const int h = support::text_height(marker.label, text_scale);
  const float reach = 0.5f * std::max(rect.length, rect.width) + 4.0f * stroke;
  int x = static_cast<int>(rect.centre.x + reach);
  int y = static_cast<int>(rect.centre.y - reach) - h;
  if (x + w + 4 > canvas.width()) x = static_cast<int>(rect.centre.x - reach) - w;
  if (y < 4) y = static_cast<int>(rect.centre.y + reach);
  x = std::clamp(x, 4, std::max(4, canvas.width() - w - 4));
  y = std::clamp(y, 4, std::max(4, canvas.height() - h - 4));
  support::draw_text(canvas, x, y, marker.label, perch_colour,
                     {.scale = text_scale, .background = colours::black, .background_alpha = 0.75f, .padding_px = 3});
}

std::vector<draw_point> window_points(const frame& f, const window_measures& m) {
  std::vector<draw_point> out;
  if (m.limb < 0 || static_cast<std::size_t>(m.limb) >= f.r.limbs.size()) return out;
  const std::span<const pixel> points = f.r.limbs[static_cast<std::size_t>(m.limb)].points;
  for (std::size_t i = m.first; i <= m.last && i < points.size(); ++i)
    out.push_back(f.at(points[i]));
  return out;
}

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

/// Outlines the clearance envelope of window `m`: the union of discs around its centreline
/// points, each of the point's radius (less ½ px, as `limb_clearance` reads it) + `needed_mm`
/// at the window's scale, in input pixels. The outline is the region's boundary pixels,
/// thickened to about `stroke` (at least 3 px). Nothing for an unknown limb or a scale of 0.
void draw_envelope(image_view<png::rgb8> canvas, const frame& f, const window_measures& m, float needed_mm,
                   rgb colour, float stroke, float alpha) {
  if (m.limb < 0 || static_cast<std::size_t>(m.limb) >= f.r.limbs.size() || !(m.mm_per_px > 0)) return;
  const skeleton_limb& limb = f.r.limbs[static_cast<std::size_t>(m.limb)];
  struct disc {
    draw_point c;
    float r;
  };
  std::vector<disc> discs;
  const float needed_px = needed_mm / m.mm_per_px;  // analysed pixels
  float x0 = std::numeric_limits<float>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (std::size_t i = m.first; i <= m.last && i < limb.points.size(); ++i) {
    const float own = i < limb.radius_px.size() ? std::max(limb.radius_px[i] - 0.5f, 0.0f) : 0.0f;
    const disc d{f.at(limb.points[i]), (own + needed_px) * f.scale()};
    if (!std::isfinite(d.r) || !std::isfinite(d.c.x) || !std::isfinite(d.c.y)) continue;
    discs.push_back(d);
    x0 = std::min(x0, d.c.x - d.r);
    y0 = std::min(y0, d.c.y - d.r);
    x1 = std::max(x1, d.c.x + d.r);
    y1 = std::max(y1, d.c.y + d.r);
  }
  if (discs.empty()) return;
  // The region on a grid one pixel wider than its box on every side, clipped to the canvas.
  const int gx0 = std::max(static_cast<int>(std::floor(x0)) - 1, -1);
  const int gy0 = std::max(static_cast<int>(std::floor(y0)) - 1, -1);
  const int gx1 = std::min(static_cast<int>(std::ceil(x1)) + 1, canvas.width());
  const int gy1 = std::min(static_cast<int>(std::ceil(y1)) + 1, canvas.height());
  if (gx1 <= gx0 || gy1 <= gy0) return;
  const int gw = gx1 - gx0 + 1, gh = gy1 - gy0 + 1;
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh), 0);
  for (const disc& d : discs) {
    const int ax = std::max(gx0, static_cast<int>(std::floor(d.c.x - d.r)));
    const int bx = std::min(gx1, static_cast<int>(std::ceil(d.c.x + d.r)));
    const int ay = std::max(gy0, static_cast<int>(std::floor(d.c.y - d.r)));
    const int by = std::min(gy1, static_cast<int>(std::ceil(d.c.y + d.r)));
    const float r2 = d.r * d.r;
    for (int y = ay; y <= by; ++y)
      for (int x = ax; x <= bx; ++x) {
        const float dx = static_cast<float>(x) - d.c.x, dy = static_cast<float>(y) - d.c.y;
        if (dx * dx + dy * dy <= r2)
          inside[static_cast<std::size_t>(y - gy0) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(x - gx0)] = 1;
      }
  }
  const auto in = [&](int x, int y) {
    if (x < gx0 || x > gx1 || y < gy0 || y > gy1) return false;
    return inside[static_cast<std::size_t>(y - gy0) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(x - gx0)] != 0;
  };
  // Boundary pixels: inside, with a 4-neighbour outside. Thickened inwards and outwards.
  std::vector<std::uint8_t> ink(inside.size(), 0);
  const int half = std::max(1, static_cast<int>(std::lround(0.3f * stroke)));
  for (int y = gy0; y <= gy1; ++y)
    for (int x = gx0; x <= gx1; ++x) {
      if (!in(x, y) || (in(x - 1, y) && in(x + 1, y) && in(x, y - 1) && in(x, y + 1))) continue;
      for (int v = std::max(gy0, y - half); v <= std::min(gy1, y + half); ++v)
        for (int u = std::max(gx0, x - half); u <= std::min(gx1, x + half); ++u)
          ink[static_cast<std::size_t>(v - gy0) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(u - gx0)] = 1;
    }
  for (int y = std::max(gy0, 0); y <= std::min(gy1, canvas.height() - 1); ++y)
    for (int x = std::max(gx0, 0); x <= std::min(gx1, canvas.width() - 1); ++x)
      if (ink[static_cast<std::size_t>(y - gy0) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(x - gx0)] != 0)
        support::put_pixel(canvas, x, y, colour, alpha);
}

/// "clearance 12 mm": a rule and by how much it was missed.
std::string miss_label(std::string_view constraint, float miss, std::string_view unit) {
  if (unit.empty()) return std::string(constraint);
  const double v = static_cast<double>(miss);
  const char* pattern = v >= 100 ? " %.0f " : v >= 1 ? " %.1f " : " %.2g ";
  return std::string(constraint) + format(pattern, v) + std::string(unit);
}
std::string miss_label(const near_miss& m) { return miss_label(m.constraint, m.miss, m.unit); }

/// "#2 -> #5: infeasible (clearance 12 mm, 3 frames)": a change of target and why ("none" for
/// no track).
std::string change_label(const target_change& c) {
  const auto id = [](std::uint32_t v) { return v == 0 ? std::string("none") : "#" + std::to_string(v); };
  std::string text = id(c.from) + " -> " + id(c.to) + ": " + std::string(to_string(c.reason));
  if (!c.constraint.empty())
    text += " (" + miss_label(c.constraint, c.miss, c.unit) + ", " + std::to_string(c.frames) + " frames)";
  return text;
}

}  // namespace

image<png::rgb8> annotate(const perch_result& r, const platform_geometry& geometry,
                          const clearance_envelope& envelope, const image<std::uint8_t>& mask,
                          const image<png::rgb8>* photo) {
  image<png::rgb8> picture(mask.width(), mask.height());
  const image_view<png::rgb8> canvas = picture.view();
  if (photo != nullptr && photo->width() == mask.width() && photo->height() == mask.height()) {
    std::copy(photo->data(), photo->data() + static_cast<std::ptrdiff_t>(picture.width()) * picture.height(),
              picture.data());
    support::dim(canvas, {.saturation = 0.2f, .towards = colours::black, .amount = 0.55f});
  } else {
    paint_mask_background(canvas, mask, 1.0f);
  }

  const frame f{r};
  const picture_metrics metrics = metrics_of(mask.width(), mask.height());
  const float stroke = metrics.stroke;
  const int text_scale = metrics.text_scale;
  const float diameter_top_mm = 2.0f * geometry.grasp_max_mm;

  // 1. Skeleton pixels pruning removed (faint), under the graph.
  if (!r.skeleton.empty()) {
    const float dot = std::max(0.5f, 0.5f * f.scale());
    for (int y = 0; y < r.skeleton.height(); ++y)
      for (int x = 0; x < r.skeleton.width(); ++x)
        if (r.skeleton(x, y) != 0) support::fill_circle(canvas, f.at({x, y}), dot, pruned_colour, 0.6f);
  }

  // 2. Branches coloured by diameter.
  draw_branches(canvas, f, diameter_top_mm, stroke);

  // 3. Near misses (faint, a clearance miss with its envelope), then the ranked sites' windows
  //    and the chosen one's clearance envelope.
  const auto needed_mm = [&](const window_measures& m) {
    return envelope.margin_mm + envelope.uncertainty_px * m.mm_per_px;
  };
  std::vector<support::text_box> labels;  // the legend keeps off them
  for (const near_miss& m : r.near_misses) {
    if (!m.present) continue;
    const std::vector<draw_point> pts = window_points(f, m.window);
    if (envelope.margin_mm >= 0 && m.constraint == clearance::name)
      draw_envelope(canvas, f, m.window, needed_mm(m.window), miss_colour, std::max(1.0f, 0.5f * stroke), 0.45f);
    support::draw_polyline(canvas, pts, miss_colour, 3.0f * stroke, 0.45f);
    if (!pts.empty()) {
      const draw_point c = pts[pts.size() / 2];
      labels.push_back(support::draw_text(canvas, static_cast<int>(c.x + 2.0f * stroke), static_cast<int>(c.y + 2.0f * stroke),
                         miss_label(m), miss_colour,
                         {.scale = text_scale, .alpha = 0.9f, .background = colours::black,
                          .background_alpha = 0.5f}));
    }
  }
  for (std::size_t i = r.sites.size(); i-- > 0;) {
    const std::vector<draw_point> pts = window_points(f, r.sites[i].window);
    support::draw_polyline(canvas, pts, site_colour, 3.0f * stroke, i == 0 ? 0.9f : 0.7f);
  }
  constexpr rgb envelope_colour{envelope_rgb.r, envelope_rgb.g, envelope_rgb.b};
  if (envelope.margin_mm >= 0 && !r.sites.empty())
    draw_envelope(canvas, f, r.sites.front().window, needed_mm(r.sites.front().window), envelope_colour,
                  std::max(2.0f, 0.6f * stroke), 1.0f);

  // 4. Bridged gaps (input pixels), then the graph's nodes.
  for (const perch_bridge& b : r.bridges) {
    const draw_point from{static_cast<float>(b.from.x), static_cast<float>(b.from.y)};
    const draw_point to{static_cast<float>(b.to.x), static_cast<float>(b.to.y)};
    support::draw_line(canvas, from, to, bridge_colour, 2.0f * stroke);
    for (const draw_point& p : {from, to}) support::fill_circle(canvas, p, 1.2f * stroke, bridge_colour);
  }
  {
    r.graph.for_each_node([&](const skeleton_node& n) {
      const draw_point p = f.at(n.position);
      const rgb c = n.kind == node_kind::junction ? colours::white
                    : n.kind == node_kind::end    ? end_colour
                                                  : pruned_colour;
      support::fill_circle(canvas, p, 1.2f * stroke, c);
      if (n.trunk) support::draw_circle(canvas, p, 3.2f * stroke, trunk_colour, stroke);
    });
  }

  // 5. Ranked site numbers and the chosen perch.
  for (std::size_t i = 1; i < r.sites.size(); ++i) {
    const pixel c = r.sites[i].window.centre;
    const std::string label = "#" + std::to_string(i + 1);
    labels.push_back(support::draw_text(canvas, c.x + static_cast<int>(3.0f * stroke), c.y - static_cast<int>(6.0f * stroke),
                       label, site_colour, {.scale = text_scale, .background = colours::black, .background_alpha = 0.6f}));
  }
  // 6. Status line and legend.
  std::string status;
  if (r.outcome == perch_outcome::found)
    status = std::string(r.platform) + ": perch found, " + std::to_string(r.sites.size()) + " site" +
             (r.sites.size() == 1 ? "" : "s");
  else if (r.outcome == perch_outcome::no_perch) {
    const rejection_count* worst = nullptr;
    for (const rejection_count& c : r.rejections)
      if (worst == nullptr || c.windows > worst->windows) worst = &c;
    status = std::string(r.platform) + ": NO PERCH";
    if (worst != nullptr && worst->windows > 0)
      status += ", " + std::string(worst->constraint) + " rejected " + std::to_string(worst->windows) + " of " +
                std::to_string(r.windows) + " windows";
  }
  else
    status = std::string(r.platform) + ": NO TREE in the mask";
  status += format("\n%.2f mm/px", static_cast<double>(r.mm_per_px)) + " (" + std::string(r.scale) + ")";
  const support::text_box title =
      draw_title(canvas, status, r.outcome == perch_outcome::found ? perch_colour : miss_colour, text_scale);

  const std::string ramp = format("diameter 0-%.0f mm", static_cast<double>(diameter_top_mm));
  const std::string envelope_label = format("clearance: r + %.0f mm", static_cast<double>(envelope.margin_mm));
  std::vector<support::legend_entry> shown = {
      {.label = ramp, .marker = support::legend_marker::ramp},
      {.label = "pruned skeleton", .colour = pruned_colour, .marker = support::legend_marker::line, .alpha = 0.6f},
      {.label = "junction", .colour = colours::white, .marker = support::legend_marker::dot},
      {.label = "branch end", .colour = end_colour, .marker = support::legend_marker::dot},
      {.label = "trunk node", .colour = trunk_colour, .marker = support::legend_marker::outline},
      {.label = "ranked windows", .colour = site_colour, .marker = support::legend_marker::line},
      {.label = "near misses", .colour = miss_colour, .marker = support::legend_marker::line, .alpha = 0.45f},
      {.label = "perch: claw x diameter", .colour = perch_colour, .marker = support::legend_marker::outline},
      {.label = "heading: trunk side to tip", .colour = perch_colour, .marker = support::legend_marker::line},
  };
  // The envelope's entry only when the platform keeps a clearance, the bridges' when any.
  if (envelope.margin_mm >= 0)
    shown.push_back({.label = envelope_label, .colour = envelope_colour, .marker = support::legend_marker::outline});
  if (!r.bridges.empty())
    shown.push_back({.label = "bridged gap", .colour = bridge_colour, .marker = support::legend_marker::line});
  std::optional<draw_point> chosen;
  if (!r.sites.empty())
    chosen = draw_point{static_cast<float>(r.sites.front().window.centre.x),
                        static_cast<float>(r.sites.front().window.centre.y)};
  place_legend(canvas, shown, text_scale, &mask, 1.0f, title, labels, chosen ? &*chosen : nullptr);

  // 7. The chosen perch, on top of everything.
  if (!r.sites.empty()) {
    const window_measures& m = r.sites.front().window;
    const std::vector<draw_point> pts = window_points(f, m);
    float angle = 0.0f;
    if (pts.size() >= 2)
      angle = std::atan2(pts.back().y - pts.front().y, pts.back().x - pts.front().x) * 180.0f /
              std::numbers::pi_v<float>;
    const float px_per_mm = m.mm_per_px > 0 ? 1.0f / m.mm_per_px : 0.0f;
    draw_perch_marker(
        canvas,
        {.rect = {*chosen, geometry.claw_width_mm * px_per_mm, std::max(m.claw_diameter_mm * px_per_mm, 2.0f), angle},
         .base = {static_cast<float>(m.base_end.x), static_cast<float>(m.base_end.y)},
         .tip = {static_cast<float>(m.tip_end.x), static_cast<float>(m.tip_end.y)},
         .label = format("#1 slope %.0f deg, d %.0f mm, heading %.0f deg", static_cast<double>(m.slope_deg),
                         static_cast<double>(m.claw_diameter_mm), static_cast<double>(m.heading_deg))},
        stroke, text_scale);
  }

  return picture;
}

image<png::rgb8> annotate_tracks(const track_picture& p, const platform_geometry& geometry, int out_width) {
  PERCH_ASSERT(p.tracked != nullptr && p.width > 0 && p.height > 0, "annotate_tracks: a frame and its tracking");
  const int width = out_width > 0 ? std::min(out_width, p.width) : p.width;
  const float zoom = static_cast<float>(width) / static_cast<float>(p.width);
  const int height = std::max(1, static_cast<int>(std::lround(static_cast<float>(p.height) * zoom)));
  image<png::rgb8> picture(width, height);
  const image_view<png::rgb8> canvas = picture.view();
  const picture_metrics metrics = metrics_of(width, height);
  const float stroke = metrics.stroke;
  const int text_scale = metrics.text_scale;
  const bool have_mask = p.mask != nullptr && p.mask->width() == p.width && p.mask->height() == p.height;
  if (have_mask)
    paint_mask_background(canvas, *p.mask, zoom);
  else
    support::fill(canvas, rgb{13, 16, 22});
  const float diameter_top_mm = 2.0f * geometry.grasp_max_mm;
  const bool have_graph = p.found != nullptr && p.found->outcome != perch_outcome::no_tree;
  if (have_graph) draw_branches(canvas, frame{*p.found, zoom}, diameter_top_mm, std::max(1.0f, 0.75f * stroke));

  // Tracks: the window along the limb through the smoothed position, a dot or ring, the id.
  const tracking_result& t = *p.tracked;
  const auto ends_of = [&](const perch_track& track) {
    const draw_point c{track.position_px.x() * zoom, track.position_px.y() * zoom};
    const float half = 0.5f * track.window_px * zoom;
    const float ux = track.axis.x(), uy = track.axis.y();
    return std::array<draw_point, 3>{draw_point{c.x - ux * half, c.y - uy * half}, c,
                                     draw_point{c.x + ux * half, c.y + uy * half}};
  };
  std::vector<support::text_box> labels;
  for (const perch_track& track : t.tracks) {
    const auto [base, c, tip] = ends_of(track);
    const bool lost = track.state == track_state::lost;
    const rgb colour = track.state == track_state::confirmed ? site_colour : lost ? lost_colour : tentative_colour;
    support::draw_line(canvas, base, tip, colour, 2.0f * stroke, lost ? 0.45f : 0.85f);
    if (track.state == track_state::confirmed)
      support::fill_circle(canvas, c, 1.8f * stroke, colour);
    else
      support::draw_circle(canvas, c, 2.2f * stroke, colour, stroke, lost ? 0.6f : 1.0f);
    if (&track == t.target) continue;  // labelled as the target below
    labels.push_back(support::draw_text(canvas, static_cast<int>(c.x + 3.0f * stroke),
                                        static_cast<int>(c.y - 4.0f * stroke) - support::text_height("#", text_scale),
                                        "#" + std::to_string(track.id), colour,
                                        {.scale = text_scale, .alpha = lost ? 0.7f : 1.0f,
                                         .background = colours::black, .background_alpha = 0.6f}));
  }

  // Status line, and the change of target under it.
  std::string status = format("frame %.0f: ", p.frame) + std::string(to_string(t.status)) +
                       (t.target != nullptr ? ", target #" + std::to_string(t.target->id) : ", no target") + ", " +
                       std::to_string(t.tracks.size()) + (t.tracks.size() == 1 ? " track" : " tracks");
  const support::text_box title = draw_title(canvas, status, t.target != nullptr ? perch_colour : miss_colour, text_scale);
  int change_y = title.y + title.height + 2;
  if (!p.error.empty()) {  // on its own line, so a long message does not shrink the status
    labels.push_back(draw_title(canvas, std::string(p.error), miss_colour, text_scale, change_y));
    change_y = labels.back().y + labels.back().height + 2;
  }
  if (t.changed) {
    labels.push_back(draw_title(canvas, "target " + change_label(t.change), colours::white, text_scale, change_y,
                                miss_colour, 0.85f));
  } else if (p.last_change_frame >= 0) {
    labels.push_back(draw_title(canvas, format("since frame %.0f: ", p.last_change_frame) + change_label(p.last_change),
                                rgb{200, 200, 200}, text_scale, change_y, colours::black, 0.55f));
  }

  // Legend.
  const std::string ramp = format("diameter 0-%.0f mm", static_cast<double>(diameter_top_mm));
  const support::legend_entry entries[] = {
      {.label = "confirmed track", .colour = site_colour, .marker = support::legend_marker::line},
      {.label = "tentative track", .colour = tentative_colour, .marker = support::legend_marker::line},
      {.label = "lost track", .colour = lost_colour, .marker = support::legend_marker::line, .alpha = 0.45f},
      {.label = "target: claw x diameter", .colour = perch_colour, .marker = support::legend_marker::outline},
      {.label = "heading: trunk side to tip", .colour = perch_colour, .marker = support::legend_marker::line},
      {.label = ramp, .marker = support::legend_marker::ramp},
  };
  const std::span<const support::legend_entry> shown(entries, have_graph ? std::size(entries) : std::size(entries) - 1);
  std::optional<draw_point> target_at;
  if (t.target != nullptr) target_at = ends_of(*t.target)[1];
  place_legend(canvas, shown, text_scale, have_mask ? p.mask : nullptr, zoom, title, labels,
               target_at ? &*target_at : nullptr);

  // The target, on top of everything.
  if (t.target != nullptr) {
    const perch_track& target = *t.target;
    const auto [base, c, tip] = ends_of(target);
    const float mm_per_px = p.found != nullptr ? p.found->mm_per_px : 0.0f;  // per input pixel
    const float px_per_mm = mm_per_px > 0 ? zoom / mm_per_px : 0.0f;
    const float angle = std::atan2(target.axis.y(), target.axis.x()) * 180.0f / std::numbers::pi_v<float>;
    // Without a scale in this frame, a claw a fifth of the window long.
    const float claw = px_per_mm > 0 ? geometry.claw_width_mm * px_per_mm : 0.2f * target.window_px * zoom;
    std::string label = format("#%.0f target: slope %.0f deg, d %.0f mm", target.id, static_cast<double>(target.slope_deg),
                               static_cast<double>(target.diameter_mm)) +
                        format(", heading %.0f deg", static_cast<double>(target.heading_deg));
    if (target.doubtful)
      label += target.misses > 0
                   ? "\ndoubtful: unseen " + std::to_string(target.misses) + " frame" + (target.misses == 1 ? "" : "s")
                   : "\ndoubtful: " + miss_label(target.failed_constraint, target.failed_by, target.failed_unit);
    draw_perch_marker(canvas,
                      {.rect = {c, claw, std::max(target.diameter_mm * px_per_mm, 2.0f), angle},
                       .base = base,
                       .tip = tip,
                       .label = std::move(label)},
                      stroke, text_scale);
  }
  return picture;
}

}  // namespace perch::tool
