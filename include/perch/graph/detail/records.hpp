// SPDX-License-Identifier: BSL-1.0
/// \file
/// Private: what a skeleton graph stores per node and per edge, and the joined polylines
/// ("ropes") that degree-2 merges build during pruning before they are written out flat.
#pragma once

#include <cmath>
#include <cstdint>

#include "perch/core/geometry.hpp"
#include "perch/graph/adjacency_list.hpp"

namespace perch::detail {

/// A pixel at the end of a branch inside a junction cluster (where the branch attaches).
struct branch_anchor {
  pixel position{};
  float radius_px = 0;
  std::uint8_t valid = 0;
};

/// A polyline: flat (`rope < 0`: `count` points from `offset` in the graph's active pool) or a
/// rope (the join of two polylines around up to two branch_anchor pixels).
struct polyline_ref {
  std::uint32_t offset = 0;
  std::uint32_t count = 0;
  std::int32_t rope = -1;
};

/// left (walked `left_dir`), then `inner[0..inner_count)`, then right (walked `right_dir`).
struct rope_node {
  polyline_ref left{};
  polyline_ref right{};
  traversal left_dir = traversal::forward;
  traversal right_dir = traversal::forward;
  branch_anchor inner[2]{};
  std::uint8_t inner_count = 0;
};

/// One pending piece while a rope is written out.
struct rope_item {
  polyline_ref ref{};
  branch_anchor point{};
  traversal dir = traversal::forward;
  std::uint8_t is_anchor = 0;
};

/// Node data of a skeleton graph.
struct skeleton_node_data {
  pixel position{};
  float radius_px = 0;
  std::int32_t component = -1;
  std::uint32_t pixel_count = 0;
  std::uint8_t trunk = 0;
};

/// Edge data of a skeleton graph.
struct skeleton_edge_data {
  polyline_ref line{};
  std::uint32_t pixel_total = 0;  ///< points of the polyline (also while it is a rope)
  std::uint32_t in_range = 0;     ///< points whose diameter lies in the spec range (pruning)
  float length_px = 0;
  float diameter_sum_px = 0;
  float weight = 0;
  branch_anchor from_anchor{};
  branch_anchor to_anchor{};
  std::int32_t component = -1;
};

/// Diameter at a skeleton pixel of radius `r` (distance to the nearest background pixel
/// centre): 2·r − 1, exact for axis-aligned strips; 0 below r = 0.5.
[[nodiscard]] constexpr float diameter_from_radius(float r) noexcept {
  return r > 0.5f ? 2.0f * r - 1.0f : 0.0f;
}

/// Length of the step between two pixels (1 or √2 for neighbours).
[[nodiscard]] inline float pixel_step_px(pixel a, pixel b) noexcept {
  const int dx = a.x - b.x;
  const int dy = a.y - b.y;
  if (dx * dx + dy * dy == 1) return 1.0f;
  if (dx * dx + dy * dy == 2) return 1.41421356f;
  return static_cast<float>(std::sqrt(static_cast<double>(dx * dx + dy * dy)));
}

}  // namespace perch::detail
