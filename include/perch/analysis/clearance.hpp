// SPDX-License-Identifier: BSL-1.0
/// \file
/// Clearance around a window, two ways:
///  - from every other limb's surface (`limb_clearance`): how far the window's centreline is
///    from the nearest other limb thick enough to matter, less its own radius; what a claw that
///    reaches around the limb needs free (issue 24's safe perch);
///  - as a share of tree pixels in a band along the window, above it, or in a circle around it
///    (the paper's failure case of a branch buried in twigs, and the free space the tether,
///    metamorphic and ornithopter platforms need). Regions are convex; each query walks the
///    region's rows and counts each row's tree pixels 16 at a time, so it costs
///    O(region area / 16) and needs nothing built beforehand.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "perch/analysis/measures.hpp"
#include "perch/core/disc_index.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// Counts the tree pixels of a row interval straight from a byte mask, 16 pixels per step:
/// the clearance queries touch a few hundred rows per window, far less than building row
/// prefix sums of the whole mask (4 bytes per pixel) would. Keeps a view of the mask, which
/// must outlive the counter.
class tree_pixel_counter {
 public:
  tree_pixel_counter() noexcept = default;
  explicit tree_pixel_counter(image_view<const std::uint8_t> mask) noexcept : mask_(mask) {}

  /// Tree (non-zero) pixels in row y with column in [x0, x1] (clipped to the image).
  [[nodiscard]] std::uint32_t count(int y, int x0, int x1) const noexcept {
    if (y < 0 || y >= height()) return 0;
    x0 = std::max(x0, 0);
    x1 = std::min(x1, width() - 1);
    if (x1 < x0) return 0;
    return detail::count_nonzero(detail::row_pointer(mask_, y) + x0, x1 - x0 + 1);
  }
  [[nodiscard]] int width() const noexcept { return mask_.width(); }
  [[nodiscard]] int height() const noexcept { return mask_.height(); }

 private:
  image_view<const std::uint8_t> mask_{};
};

/// A convex region given as up to four slabs |n·p − c| ≤ r plus an optional disc; its rows are
/// intervals of pixel centres.
struct convex_region {
  struct slab {
    point2f normal{1, 0};  ///< unit normal
    float centre = 0;      ///< n·p at the slab's middle
    float half_width = 0;  ///< half thickness
  };
  slab slabs[4]{};
  int slab_count = 0;
  point2f disc_centre{0, 0};
  float disc_radius = -1;  ///< < 0: no disc
  float min_y = 0, max_y = -1;

  /// Columns [x0, x1] of row y inside the region; false when the row misses it.
  [[nodiscard]] bool row_interval(int y, float& x0, float& x1) const noexcept {
    x0 = -1e30f;
    x1 = 1e30f;
    const auto fy = static_cast<float>(y);
    if (disc_radius >= 0) {
      const float dy = fy - disc_centre.y();
      const float h2 = disc_radius * disc_radius - dy * dy;
      if (h2 < 0) return false;
      const float h = std::sqrt(h2);
      x0 = disc_centre.x() - h;
      x1 = disc_centre.x() + h;
    }
    for (int i = 0; i < slab_count; ++i) {
      const slab& s = slabs[i];
      const float base = s.normal.y() * fy;  // n·p = nx·x + base
      const float lo = s.centre - s.half_width - base;
      const float hi = s.centre + s.half_width - base;
      if (std::abs(s.normal.x()) < 1e-6f) {
        if (0 < lo || 0 > hi) return false;
        continue;
      }
      float a = lo / s.normal.x();
      float b = hi / s.normal.x();
      if (a > b) std::swap(a, b);
      x0 = std::max(x0, a);
      x1 = std::min(x1, b);
    }
    return x0 <= x1;
  }
};

/// Share of tree pixels in a region, not counting the window's own branch.
struct region_share {
  std::uint32_t tree = 0;   ///< tree pixels in the region, outside the own-branch strip
  std::uint32_t total = 0;  ///< pixels in the region, outside the own-branch strip
  [[nodiscard]] float share() const noexcept {
    return total == 0 ? 0.0f : static_cast<float>(tree) / static_cast<float>(total);
  }
};

/// One limb as `limb_clearance` reads it: its centreline, radii (distance map, px), the owners
/// its clearance leaves out (the limb's own discs), and a cache of one gap per point.
struct limb_neighbourhood {
  std::span<const pixel> points{};
  std::span<const float> radius_px{};
  owner_set own{};
  std::span<float> gap_px{};   ///< per point: the gap found, valid up to `reach_px`
  std::span<float> reach_px{};  ///< per point: how far the search looked (≤ 0: not yet)
};

/// The gap (px) between each limb point's outline and the surface of the nearest other limb in
/// `discs` (`find_limb_obstacles`): |p − c| − r(c) − r(p) at its smallest, with r(p) the point's
/// radius less ½ px like the discs'. Computed on demand and cached per point, so the windows
/// that overlap along a limb share their searches.
class limb_clearance {
 public:
  limb_clearance() noexcept = default;
  limb_clearance(const disc_index& discs, std::span<const limb_neighbourhood> limbs) noexcept
      : discs_(&discs), limbs_(limbs) {}

  /// The smallest gap over points [first, last] of `limb`, or `cap_px` when every gap is at
  /// least that. An unknown limb (or no discs) has nothing around it: `cap_px`.
  [[nodiscard]] float smallest_gap_px(std::int32_t limb, std::uint32_t first, std::uint32_t last,
                                      float cap_px) const noexcept {
    if (discs_ == nullptr || limb < 0 || static_cast<std::size_t>(limb) >= limbs_.size())
      return cap_px;
    const limb_neighbourhood& l = limbs_[static_cast<std::size_t>(limb)];
    float smallest = cap_px;
    for (std::uint32_t i = first; i <= last && i < l.points.size(); ++i)
      smallest = std::min(smallest, gap_at(l, i, cap_px));
    return smallest;
  }

 private:
  [[nodiscard]] float gap_at(const limb_neighbourhood& l, std::size_t i, float cap_px) const noexcept {
    // Cached: the search looked far enough, or found a surface nearer than it looked.
    const bool searched = l.reach_px[i] > 0;
    if (searched && (l.reach_px[i] >= cap_px || l.gap_px[i] < l.reach_px[i]))
      return std::min(l.gap_px[i], cap_px);
    const float own = std::max(l.radius_px[i] - 0.5f, 0.0f);
    const float reach = cap_px + own;
    const float surface = discs_->surface_distance(to_point(l.points[i]), l.own, reach);
    l.gap_px[i] = surface >= reach ? cap_px : surface - own;  // nothing within reach: the cap
    l.reach_px[i] = cap_px;
    return std::min(l.gap_px[i], cap_px);
  }

  const disc_index* discs_ = nullptr;
  std::span<const limb_neighbourhood> limbs_{};
};

/// What a clearance constraint may ask about one window. Built by the ranking stage for windows
/// that passed every geometric constraint; each query is computed on demand.
class window_context {
 public:
  window_context(const tree_pixel_counter& tree, const window_measures& m, point2f first_px,
                 point2f last_px, float own_radius_px, point2f up,
                 const limb_clearance* limbs = nullptr) noexcept
      : tree_(&tree), limbs_(limbs), m_(&m), a_(first_px), b_(last_px),
        own_radius_px_(own_radius_px), up_(up) {
    point2f d = b_ - a_;
    const float n = d.norm();
    along_ = n > 0 ? point2f(d / n) : point2f(up_.y(), -up_.x());
    across_ = point2f(-along_.y(), along_.x());
    centre_ = 0.5f * (a_ + b_);
  }

  [[nodiscard]] const window_measures& measures() const noexcept { return *m_; }

  /// The smallest gap (mm) between the window's limb and the surface of any other limb at any
  /// point of the window (`limb_clearance`), or `cap_mm` when it is at least that (the search
  /// looks no further). `cap_mm` without the other limbs' surroundings (no `limb_clearance`).
  [[nodiscard]] float limb_gap_mm(float cap_mm) const noexcept {
    if (limbs_ == nullptr) return cap_mm;
    const float cap_px = px(cap_mm);
    const float gap_px = limbs_->smallest_gap_px(m_->limb, m_->first, m_->last, cap_px);
    return gap_px >= cap_px ? cap_mm : gap_px * m_->mm_per_px;  // the cap exactly, not rounded
  }

  /// Other tree in a band along the window: `margin_mm` beyond the branch's surface on each
  /// side, over the window's chord.
  [[nodiscard]] region_share band(float margin_mm) const noexcept {
    convex_region r;
    const float half_len = 0.5f * (b_ - a_).norm();
    r.slabs[0] = {along_, along_.dot(centre_), half_len};
    r.slabs[1] = {across_, across_.dot(centre_), own_radius_px_ + px(margin_mm)};
    r.slab_count = 2;
    return count(r, half_len + own_radius_px_ + px(margin_mm));
  }

  /// Tree in the box `width_mm` wide (along the horizon) and `height_mm` tall right above the
  /// branch at the window's middle: the space a drone landing from above sweeps.
  [[nodiscard]] region_share above(float width_mm, float height_mm) const noexcept {
    convex_region r;
    const point2f horizon(-up_.y(), up_.x());
    const point2f base = centre_ + up_ * (own_radius_px_ + 1.0f);
    const point2f mid = base + up_ * (0.5f * px(height_mm));
    r.slabs[0] = {horizon, horizon.dot(mid), 0.5f * px(width_mm)};
    r.slabs[1] = {up_, up_.dot(mid), 0.5f * px(height_mm)};
    r.slab_count = 2;
    return count(r, 0.5f * (px(width_mm) + px(height_mm)), mid);
  }

  /// Other tree in a disc of `radius_mm` around the window's middle (a tether's wrap circle).
  [[nodiscard]] region_share circle(float radius_mm) const noexcept {
    convex_region r;
    r.disc_centre = centre_;
    r.disc_radius = px(radius_mm);
    return count(r, r.disc_radius);
  }

 private:
  [[nodiscard]] float px(float mm) const noexcept { return mm / m_->mm_per_px; }

  /// Counts tree and all pixels of `r` (rows within `reach` of its centre), minus the strip of
  /// the own branch (|across·(p − centre)| ≤ own radius + 1.5 px).
  [[nodiscard]] region_share count(const convex_region& r, float reach) const noexcept {
    return count(r, reach, centre_);
  }
  /// Column of the first (`std::ceil`) or last (`std::floor`) pixel centre of an interval end,
  /// clamped to [0, width - 1] in float first: an unbounded end (±1e30) must never reach the
  /// float-to-int conversion, which is undefined out of range.
  [[nodiscard]] int column(float v) const noexcept {
    return static_cast<int>(std::clamp(v, -1.0f, static_cast<float>(tree_->width())));
  }
  [[nodiscard]] region_share count(const convex_region& r, float reach,
                                   point2f middle) const noexcept {
    region_share out;
    const float strip = own_radius_px_ + 1.5f;
    const float h = static_cast<float>(tree_->height());
    const int y0 = static_cast<int>(std::clamp(std::floor(middle.y() - reach), 0.0f, h));
    const int y1 = static_cast<int>(std::clamp(std::ceil(middle.y() + reach), -1.0f, h - 1));
    for (int y = y0; y <= y1; ++y) {
      float fx0 = 0, fx1 = 0;
      if (!r.row_interval(y, fx0, fx1)) continue;
      const int x0 = std::max(0, column(std::ceil(fx0)));
      const int x1 = std::min(tree_->width() - 1, column(std::floor(fx1)));
      if (x1 < x0) continue;
      // The own-branch strip on this row, as an interval to leave out.
      convex_region own;
      own.slabs[0] = {across_, across_.dot(centre_), strip};
      own.slab_count = 1;
      float sx0 = 0, sx1 = 0;
      int ox0 = 1, ox1 = 0;  // empty
      if (own.row_interval(y, sx0, sx1)) {
        ox0 = std::max(x0, column(std::ceil(sx0)));
        ox1 = std::min(x1, column(std::floor(sx1)));
      }
      const auto span_all = static_cast<std::uint32_t>(x1 - x0 + 1);
      std::uint32_t tree = tree_->count(y, x0, x1);
      std::uint32_t all = span_all;
      if (ox0 <= ox1) {
        tree -= tree_->count(y, ox0, ox1);
        all -= static_cast<std::uint32_t>(ox1 - ox0 + 1);
      }
      out.tree += tree;
      out.total += all;
    }
    return out;
  }

  const tree_pixel_counter* tree_;
  const limb_clearance* limbs_;
  const window_measures* m_;
  point2f a_, b_, centre_, along_, across_;
  float own_radius_px_;
  point2f up_;
};

}  // namespace perch
