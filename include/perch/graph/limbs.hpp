// SPDX-License-Identifier: BSL-1.0
/// \file
/// Limbs: skeleton-graph edges chained through the junctions where only a much thinner limb
/// leaves. The paper's "branch" is a limb of the tree, not a graph edge: a twig leaving a limb
/// splits the limb's skeleton at a junction node, yet the limb carries on past it, straight and
/// as thick, and a claw can perch across it. At every junction the two edges that continue one
/// another (the "continuation" pairing of skeleton-graph tree models, e.g. Bucksch & Lindenbergh
/// 2008, "CAMPINO"; Verroust & Lazarus 2000) are joined when every other edge there is thin.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>

#include "perch/core/geometry.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

/// When a limb runs on through a junction (`limb_continuations`). Thicknesses are compared
/// as 2·r, r the distance-map radius: within half a pixel of the true width on average, where
/// 2·r − 1 reads thin limbs up to a pixel low (see `cross_section_diameters`), which matters
/// when the side limb is a few pixels wide.
struct limb_options {
  /// A leaf edge (ending in a tip) leaving a junction is a side twig when its cross-section is
  /// at most this share of the thinner through edge's (thicknesses squared). In the pipe model
  /// (Shinozaki et al. 1964) a limb's cross-section carries on into the limbs it feeds, so the
  /// through limb keeps ≥ 95 % of its thickness past a side twig of 0.1: under a third of its
  /// thickness. Thicker side limbs, and thin edges that lead to another junction (a limb that
  /// crosses or touches another), end the limb.
  float side_area_share_max = 0.1f;
  /// The two through edges leave the junction in directions at most this far from opposite (°)
  /// ...
  float max_turn_deg = 30.0f;
  /// ... and the thinner is at least this share of the thicker.
  float through_thickness_ratio_min = 0.7f;

  [[nodiscard]] status validate() const noexcept {
    if (!(side_area_share_max >= 0 && side_area_share_max <= 1) ||
        !(max_turn_deg >= 0 && max_turn_deg <= 180) ||
        !(through_thickness_ratio_min >= 0 && through_thickness_ratio_min <= 1))
      return fail(errc::invalid_parameter, "limb_options");
    return {};
  }
};

namespace detail {

/// The straight stretch of an edge just beyond a junction node: its points between r(n) and
/// r(n) + max(3·r(n), 8 px) from the node (beyond the node's cluster, where the medial axis
/// bends toward it), walked from the node by `dir`.
struct leaving_axis {
  point2f start{0, 0};      ///< first point of the stretch
  point2f direction{0, 0};  ///< unit chord of the stretch, away from the node
  float radius_px = 0;      ///< mean radius over the stretch
  float radius_near_px = 0;  ///< radius at the stretch's first point (nearest the node)
  /// At least two points, a non-zero chord, and every point of the stretch within
  /// `straight_tolerance_px` + 10 % of the chord's length of it: a centreline that bends there
  /// (the medial axis of a limb cut by the image edge forks to the cut's corners) is no axis.
  bool valid = false;
};

/// A digital straight line lies within √2/2 px of its line and a medial axis wobbles by another
/// half pixel about it.
inline constexpr float straight_tolerance_px = 1.5f;

[[nodiscard]] inline leaving_axis leaving_axis_of(const skeleton_branch& edge, traversal dir,
                                                  const skeleton_node& node) noexcept {
  leaving_axis out;
  const std::size_t count = edge.points.size();
  const point2f centre = to_point(node.position);
  const float near = node.radius_px;
  const float far = node.radius_px + std::max(3.0f * node.radius_px, 8.0f);
  std::size_t first = count, last = count;
  float radius_sum = 0;
  std::size_t radius_n = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = dir == traversal::forward ? k : count - 1 - k;
    const float d = (to_point(edge.points[i]) - centre).norm();
    if (d > far) break;
    if (d < near) continue;
    if (first == count) {
      first = i;
      out.radius_near_px = edge.radius_px[i];
    }
    last = i;
    radius_sum += edge.radius_px[i];
    ++radius_n;
  }
  if (radius_n < 2) return out;
  const point2f chord = to_point(edge.points[last]) - to_point(edge.points[first]);
  const float length = chord.norm();
  if (!(length > 0)) return out;
  out.start = to_point(edge.points[first]);
  out.direction = chord / length;
  const float tolerance = straight_tolerance_px + 0.1f * length;
  for (std::size_t i = std::min(first, last); i <= std::max(first, last); ++i) {
    const point2f v = to_point(edge.points[i]) - out.start;
    if (std::abs(out.direction.x() * v.y() - out.direction.y() * v.x()) > tolerance) return out;
  }
  out.radius_px = radius_sum / static_cast<float>(radius_n);
  out.valid = true;
  return out;
}

}  // namespace detail

/// Index of edge end (`e`, `end`) in a continuation array: 2·e + end, end 0 at the edge's
/// `from` node, 1 at its `to` node.
[[nodiscard]] constexpr std::size_t edge_end_index(edge_id e, int end) noexcept {
  return 2 * static_cast<std::size_t>(e) + static_cast<std::size_t>(end);
}

/// The edge of edge end `end` (`edge_end_index`).
[[nodiscard]] constexpr edge_id edge_of_end(std::size_t end) noexcept {
  return static_cast<edge_id>(end / 2);
}

/// Whether edge end `end` is at its edge's `from` node.
[[nodiscard]] constexpr bool is_from_end(std::size_t end) noexcept { return end % 2 == 0; }

/// The other end of the same edge.
[[nodiscard]] constexpr std::size_t other_end(std::size_t end) noexcept {
  return end ^ std::size_t{1};
}

/// The node at edge end `end`.
[[nodiscard]] inline node_id node_at_end(const skeleton_graph& graph, std::size_t end) noexcept {
  const skeleton_branch e = graph.branch(edge_of_end(end));
  return is_from_end(end) ? e.from : e.to;
}

/// Which edge carries a limb on through each node: for every edge end (`edge_end_index`), the
/// edge end on the other side of the node that continues its limb there, or none. Joins are
/// symmetric. A view over caller memory of 2 · `graph.topology().edge_id_end()` entries
/// (`ends_for`), so the pipeline keeps it in its workspace.
class edge_continuations {
 public:
  edge_continuations() noexcept = default;
  explicit edge_continuations(std::span<std::int32_t> storage) noexcept : next_(storage) {}

  /// Entries needed for `graph`: one per edge end.
  [[nodiscard]] static std::size_t ends_for(const skeleton_graph& graph) noexcept {
    return 2 * static_cast<std::size_t>(graph.topology().edge_id_end());
  }
  [[nodiscard]] std::size_t size() const noexcept { return next_.size(); }

  /// Whether the limb carries on past edge end `end`.
  [[nodiscard]] bool joined(std::size_t end) const noexcept { return next_[end] >= 0; }
  /// The edge end that carries the limb on past `end` (only when `joined(end)`).
  [[nodiscard]] std::size_t after(std::size_t end) const noexcept {
    PERCH_ASSERT(joined(end), "edge_continuations::after: the limb ends here");
    return static_cast<std::size_t>(next_[end]);
  }
  /// No edge end joined.
  void clear() const noexcept {
    for (std::int32_t& v : next_) v = none;
  }
  /// Joins edge ends `a` and `b` (both ways).
  void join(std::size_t a, std::size_t b) const noexcept {
    next_[a] = static_cast<std::int32_t>(b);
    next_[b] = static_cast<std::int32_t>(a);
  }

 private:
  static constexpr std::int32_t none = -1;
  std::span<std::int32_t> next_{};
};

/// Joins, in `next`, the two edges at each junction that carry one limb through it. At a junction node
/// whose incident edges are all distinct (no self-loop), two edges continue one another when
/// they leave in nearly opposite directions (`max_turn_deg`) with similar thicknesses
/// (`through_thickness_ratio_min`) and every other edge there is a side twig: an edge with a
/// radius under `twig_radius_px` (a twig by the platform's measure, whether it ends in a tip,
/// touches something else or carries spurs: clutter a claw closes through, which the clearance
/// does not count either; 0 for none), or a leaf edge of at most `side_area_share_max` of the
/// through limb's cross-section (the pipe model: a thicker leaf may be the other child of a
/// fork); of several such pairs, the straightest. Directions and thicknesses are those of
/// each edge just beyond the node (`leaving_axis_of`).
/// `next` holds `edge_continuations::ends_for(graph)` entries.
/// Complexity: O(Σ over junctions of degree² + points near the junctions).
inline void limb_continuations(const skeleton_graph& graph, const edge_continuations& next,
                               const limb_options& options = {},
                               float twig_radius_px = 0) noexcept {
  PERCH_ASSERT(next.size() >= edge_continuations::ends_for(graph), "limb_continuations: next size");
  next.clear();
  constexpr std::size_t max_degree = 8;
  const float cos_max_turn =
      std::cos(options.max_turn_deg * std::numbers::pi_v<float> / 180.0f);
  graph.for_each_node([&](const skeleton_node& node) {
    if (node.kind != node_kind::junction || node.degree < 3) return;
    if (static_cast<std::size_t>(node.degree) > max_degree) return;
    detail::leaving_axis axes[max_degree];
    std::int32_t ends[max_degree];
    bool leaf[max_degree];
    std::size_t count = 0;
    for (const incidence in : graph.topology().incidences(node.id)) {
      if (in.neighbour == node.id) return;  // a self-loop: no continuation here
      const skeleton_branch edge = graph.branch(in.edge);
      axes[count] = detail::leaving_axis_of(edge, in.direction, node);
      if (!axes[count].valid) return;
      leaf[count] = graph.topology().degree(in.neighbour) == 1;
      ends[count] = static_cast<std::int32_t>(
          edge_end_index(in.edge, in.direction == traversal::forward ? 0 : 1));
      ++count;
    }
    const auto radius = [&](std::size_t i) { return axes[i].radius_px; };
    std::size_t best_a = count, best_b = count;
    float best_cos = 1;
    for (std::size_t a = 0; a < count; ++a) {
      for (std::size_t b = a + 1; b < count; ++b) {
        const float c = axes[a].direction.dot(axes[b].direction);
        if (c > -cos_max_turn || c >= best_cos) continue;
        const float thin = std::min(radius(a), radius(b));
        const float thick = std::max(radius(a), radius(b));
        if (!(thin >= options.through_thickness_ratio_min * thick)) continue;
        bool sides_thin = true;
        for (std::size_t s = 0; s < count && sides_thin; ++s)
          if (s != a && s != b)
            sides_thin =
                radius(s) < twig_radius_px ||
                (leaf[s] && radius(s) * radius(s) <= options.side_area_share_max * thin * thin);
        if (!sides_thin) continue;
        best_a = a;
        best_b = b;
        best_cos = c;
      }
    }
    if (best_a == count) return;
    next.join(static_cast<std::size_t>(ends[best_a]), static_cast<std::size_t>(ends[best_b]));
  });
}

/// The part of a branch's or limb's polyline outside the bodies of the junctions at its ends
/// (points [first, first + count)).
struct branch_stretch {
  std::size_t first = 0;
  std::size_t count = 0;
};

/// A limb: a chain of edges joined by `limb_continuations`, as one polyline: the edges'
/// points in walking order, with the node pixel of each junction walked through between two
/// edges (its radius the node's).
struct skeleton_limb {
  std::span<const pixel> points{};
  std::span<const float> radius_px{};
  std::span<const edge_id> edge_at{};  ///< the edge of each point (a node pixel: the edge before)
  std::int32_t component = -1;
  /// The edge ends (`edge_end_index`) at the limb's first and last points, each at the node
  /// the limb ends at; a closed limb is joined past its first end (`next.joined(first_end)`).
  std::uint32_t first_end = 0;
  std::uint32_t last_end = 0;
};

/// Bytes of workspace `trace_limbs` takes for a graph of at most `edges` edges over at most
/// `skeleton_pixels` pixels (a limb's points are skeleton pixels, each used once).
[[nodiscard]] constexpr std::size_t trace_limbs_workspace_bytes(
    std::size_t edges, std::size_t skeleton_pixels) noexcept {
  return workspace::footprint<skeleton_limb>(edges) + workspace::footprint<std::uint8_t>(edges) +
         workspace::footprint<pixel>(skeleton_pixels) +
         workspace::footprint<float>(skeleton_pixels) +
         workspace::footprint<edge_id>(skeleton_pixels);
}

/// The limbs of `graph` given the continuations `next` (`limb_continuations`): every live edge
/// lies on exactly one limb. Limbs are listed in order of their lowest edge id, each walked
/// from the end reached by walking back from that edge through its `from` node.
/// Errors: `workspace_too_small` for a borrowed workspace. Complexity: O(edges + points).
[[nodiscard]] inline result<std::span<const skeleton_limb>> trace_limbs(
    const skeleton_graph& graph, const edge_continuations& next, workspace& ws) noexcept {
  const auto edge_end = static_cast<std::size_t>(graph.topology().edge_id_end());
  PERCH_ASSERT(next.size() >= edge_continuations::ends_for(graph), "trace_limbs: next size");
  // The edges' points and one node pixel per junction walked through (seen from both ends).
  std::size_t total = 0, joined_ends = 0;
  graph.for_each_branch([&](const skeleton_branch& b) {
    total += b.points.size();
    for (const int end : {0, 1}) joined_ends += next.joined(edge_end_index(b.id, end)) ? 1u : 0u;
  });
  total += joined_ends / 2;
  auto limbs = ws.allocate<skeleton_limb>(graph.branch_count());
  auto visited = ws.allocate_zeroed<std::uint8_t>(edge_end);
  auto points = ws.allocate<pixel>(total);
  auto radii = ws.allocate<float>(total);
  auto edges = ws.allocate<edge_id>(total);
  PERCH_TRY(all_ok(limbs, visited, points, radii, edges));
  std::size_t limb_count = 0, used = 0;
  graph.for_each_branch([&](const skeleton_branch& b) {
    if ((*visited)[static_cast<std::size_t>(b.id)] != 0) return;
    // Walk back through `from` to the limb's first edge end (round a closed limb: back to b).
    std::size_t first = edge_end_index(b.id, 0);
    for (std::size_t hops = 0; hops < edge_end; ++hops) {
      if (!next.joined(first) || edge_of_end(next.after(first)) == b.id) break;
      first = other_end(next.after(first));
    }
    skeleton_limb limb;
    limb.component = b.component;
    limb.first_end = static_cast<std::uint32_t>(first);
    const std::size_t start = used;
    for (std::size_t end = first;;) {  // `end`: the end the walk enters the current edge by
      const edge_id e = edge_of_end(end);
      (*visited)[static_cast<std::size_t>(e)] = 1;
      const skeleton_branch edge = graph.branch(e);
      const std::size_t n = edge.points.size();
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = is_from_end(end) ? k : n - 1 - k;
        (*points)[used] = edge.points[i];
        (*radii)[used] = edge.radius_px[i];
        (*edges)[used++] = e;
      }
      limb.last_end = static_cast<std::uint32_t>(other_end(end));
      if (!next.joined(limb.last_end)) break;
      const std::size_t on = next.after(limb.last_end);
      if ((*visited)[static_cast<std::size_t>(edge_of_end(on))] != 0) break;
      const skeleton_node node = graph.node(is_from_end(end) ? edge.to : edge.from);
      (*points)[used] = node.position;
      (*radii)[used] = node.radius_px;
      (*edges)[used++] = e;
      end = on;
    }
    limb.points = std::span<const pixel>(*points).subspan(start, used - start);
    limb.radius_px = std::span<const float>(*radii).subspan(start, used - start);
    limb.edge_at = std::span<const edge_id>(*edges).subspan(start, used - start);
    (*limbs)[limb_count++] = limb;
  });
  return std::span<const skeleton_limb>(*limbs).first(limb_count);
}

}  // namespace perch
