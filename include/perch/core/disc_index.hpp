// SPDX-License-Identifier: BSL-1.0
/// \file
/// `disc_index`: a set of discs (centre, radius, owner) bucketed on a uniform grid, answering
/// "how far is this point from the surface of the nearest disc not owned by these owners?".
///
/// A medial axis with its radii is a union of discs that reconstructs the shape (Blum 1967), so
/// the distance from a point to the surface of a set of limbs is the smallest |p − c| − r over
/// their skeleton's discs: `find_perch` measures a window's clearance from every other limb this
/// way, with the discs of the skeleton graph's limbs (see `graph/limb_surroundings.hpp`).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "perch/core/geometry.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// One disc: centre (px), radius (px) and the id of what it belongs to (e.g. a limb).
struct owned_disc {
  float x = 0;
  float y = 0;
  float radius = 0;
  std::int32_t owner = -1;
};

/// Up to three owners a query leaves out (e.g. the limb whose clearance is asked; -1: none).
struct owner_set {
  std::int32_t ids[3] = {-1, -1, -1};
  [[nodiscard]] constexpr bool contains(std::int32_t id) const noexcept {
    return id >= 0 && (id == ids[0] || id == ids[1] || id == ids[2]);
  }
};

/// Discs bucketed by the grid cell of their centre. Built once per frame in a workspace; queries
/// visit the cells near the point and skip a cell whose nearest edge, less its largest radius,
/// is already beyond what the query asks about.
class disc_index {
 public:
  disc_index() noexcept = default;

  /// Bytes of workspace `build` takes for `discs` discs over a `width` × `height` frame.
  [[nodiscard]] static constexpr std::size_t workspace_bytes(std::size_t discs, int width, int height,
                                                   int cell_px = default_cell_px) noexcept {
    const std::size_t cells = cell_count(width, cell_px) * cell_count(height, cell_px);
    return workspace::footprint<owned_disc>(discs) + workspace::footprint<std::uint32_t>(cells + 1) +
           workspace::footprint<float>(cells);
  }

  /// Buckets `discs` (centres in [0, width) × [0, height); others are clamped to the border
  /// cells) in cells of `cell_px`. Errors: `workspace_too_small` for a borrowed workspace.
  /// Complexity O(discs + cells).
  [[nodiscard]] static result<disc_index> build(std::span<const owned_disc> discs, int width,
                                                int height, workspace& ws,
                                                int cell_px = default_cell_px) noexcept {
    disc_index out;
    out.cell_ = std::max(1, cell_px);
    out.columns_ = static_cast<int>(cell_count(width, out.cell_));
    out.rows_ = static_cast<int>(cell_count(height, out.cell_));
    const auto cells = static_cast<std::size_t>(out.columns_) * static_cast<std::size_t>(out.rows_);
    auto sorted = ws.allocate<owned_disc>(discs.size());
    auto start = ws.allocate_zeroed<std::uint32_t>(cells + 1);
    auto largest = ws.allocate_zeroed<float>(cells);
    PERCH_TRY(all_ok(sorted, start, largest));
    for (const owned_disc& d : discs) {
      const std::size_t c = out.cell_of(d.x, d.y);
      ++(*start)[c + 1];
      (*largest)[c] = std::max((*largest)[c], d.radius);
      out.max_radius_ = std::max(out.max_radius_, d.radius);
    }
    for (std::size_t c = 0; c < cells; ++c) (*start)[c + 1] += (*start)[c];
    // Counting sort: `start[c]` walks through cell c's slots, then is restored below.
    for (const owned_disc& d : discs) (*sorted)[(*start)[out.cell_of(d.x, d.y)]++] = d;
    for (std::size_t c = cells; c > 0; --c) (*start)[c] = (*start)[c - 1];
    (*start)[0] = 0;
    out.discs_ = *sorted;
    out.start_ = *start;
    out.largest_ = *largest;
    return out;
  }

  /// The smallest |p − c| − r over the discs whose owner is not in `excluded`, or `cap` when
  /// none is nearer than that (the search stops looking beyond `cap`). Complexity: the discs
  /// of the cells within `cap` + the largest radius of p.
  [[nodiscard]] float surface_distance(point2f p, const owner_set& excluded,
                                       float cap) const noexcept {
    if (discs_.empty()) return cap;
    const float reach = cap + max_radius_;
    const auto cell = static_cast<float>(cell_);
    const int c0 = clamp_cell(std::floor((p.x() - reach) / cell), columns_);
    const int c1 = clamp_cell(std::floor((p.x() + reach) / cell), columns_);
    const int r0 = clamp_cell(std::floor((p.y() - reach) / cell), rows_);
    const int r1 = clamp_cell(std::floor((p.y() + reach) / cell), rows_);
    float best = cap;
    // A cell's extent for the skip test; the border cells reach on beyond the frame, where the
    // discs clamped into them lie.
    auto gap_to_cell = [cell](int i, int count, float v) {
      const float lo = i == 0 ? -std::numeric_limits<float>::infinity()
                              : static_cast<float>(i) * cell;
      const float hi = i == count - 1 ? std::numeric_limits<float>::infinity()
                                      : static_cast<float>(i + 1) * cell;
      return std::max({lo - v, v - hi, 0.0f});
    };
    for (int r = r0; r <= r1; ++r) {
      const float dy = gap_to_cell(r, rows_, p.y());
      for (int c = c0; c <= c1; ++c) {
        const std::size_t k = static_cast<std::size_t>(r) * static_cast<std::size_t>(columns_) +
                              static_cast<std::size_t>(c);
        if (start_[k] == start_[k + 1]) continue;
        const float dx = gap_to_cell(c, columns_, p.x());
        if (std::sqrt(dx * dx + dy * dy) - largest_[k] >= best) continue;
        for (std::uint32_t i = start_[k]; i < start_[k + 1]; ++i) {
          const owned_disc& d = discs_[i];
          if (excluded.contains(d.owner)) continue;
          const float ex = d.x - p.x();
          const float ey = d.y - p.y();
          const float gap = std::sqrt(ex * ex + ey * ey) - d.radius;
          best = std::min(best, gap);
        }
      }
    }
    return best;
  }

  [[nodiscard]] std::size_t size() const noexcept { return discs_.size(); }
  [[nodiscard]] std::span<const owned_disc> discs() const noexcept { return discs_; }

  /// Cell size when the caller does not choose: a few limb radii at camera resolutions.
  static constexpr int default_cell_px = 16;

 private:
  [[nodiscard]] static constexpr std::size_t cell_count(int extent, int cell_px) noexcept {
    return static_cast<std::size_t>(std::max(1, (std::max(extent, 1) + cell_px - 1) / cell_px));
  }
  [[nodiscard]] static int clamp_cell(float v, int count) noexcept {
    return static_cast<int>(std::clamp(v, 0.0f, static_cast<float>(count - 1)));
  }
  [[nodiscard]] std::size_t cell_of(float x, float y) const noexcept {
    const auto cell = static_cast<float>(cell_);
    const int c = clamp_cell(std::floor(x / cell), columns_);
    const int r = clamp_cell(std::floor(y / cell), rows_);
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(columns_) +
           static_cast<std::size_t>(c);
  }

  std::span<const owned_disc> discs_{};
  std::span<const std::uint32_t> start_{};
  std::span<const float> largest_{};
  int cell_ = default_cell_px;
  int columns_ = 1;
  int rows_ = 1;
  float max_radius_ = 0;
};

}  // namespace perch
