// SPDX-License-Identifier: BSL-1.0
/// \file
/// What surrounds each limb, as the feasibility rules need it (issue 24):
///  - `limb_obstacles`: the discs of every limb's skeleton (the union of a medial axis's discs is
///    the shape, Blum 1967), with a limb's base inside its parent modelled by the limb's own
///    radius. A window's clearance is its distance to the discs of every other limb
///    (`disc_index::surface_distance`). Every limb that meets this one at a junction is another
///    limb, even one that carries on straight through a fork or past a side limb: the skeleton
///    cannot tell the same wood from a fork's child, and the safe reading is the cautious one.
///  - `grounded_components`: which connected pieces of the mask hold something up: a piece that
///    reaches the bottom of the frame, or the main tree. A detached piece (a segmenter's gap, a
///    blob of foliage) is never a perch, whatever its shape.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include "perch/core/disc_index.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/mask.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/detail/scan.hpp"
#include "perch/graph/junctions.hpp"
#include "perch/graph/limbs.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

/// Which limbs count as obstacles (lengths in mm at the frame's scale).
struct obstacle_options {
  /// Limbs thinner than this are compliant twigs: a claw closes through them and a drone's
  /// rotors brush them aside. Only discs at least this thick are obstacles...
  float twig_max_mm = 20.0f;
  /// ... give or take this many pixels: a limb is a twig only when it is known to be one, its
  /// width read off the mask below `twig_max_mm` by the width's uncertainty.
  float uncertainty_px = width_uncertainty_px;

  /// The smallest distance-map radius (px) of an obstacle at `mm_per_px`: a disc of radius r
  /// stands for a width of about 2·r − 1 px. Thinner edges are twigs (also for
  /// `limb_continuations`: a limb runs on past them).
  [[nodiscard]] float twig_radius_px(float mm_per_px) const noexcept {
    if (!(mm_per_px > 0)) return 0;  // no scale: nothing is known to be a twig
    return 0.5f * (twig_max_mm / mm_per_px - uncertainty_px) + 0.5f;
  }

  [[nodiscard]] status validate() const noexcept {
    if (!(twig_max_mm >= 0 && twig_max_mm < 1e6f) || !(uncertainty_px >= 0 && uncertainty_px < 1e6f))
      return fail(errc::invalid_parameter, "obstacle_options");
    return {};
  }
};

/// Every limb's obstacle discs, and per limb the owners a clearance query leaves out (itself).
struct limb_obstacles {
  disc_index discs{};
  std::span<const owner_set> own{};  ///< per limb: the owners its clearance leaves out (itself)
};

namespace detail {
/// Slots of a `pixel_map` for `n` pixels: a power of two, at least twice `n`.
[[nodiscard]] constexpr std::size_t pixel_map_slots(std::size_t n) noexcept {
  std::size_t slots = 16;
  while (slots < 2 * n) slots *= 2;
  return slots;
}

}  // namespace detail

/// Bytes of workspace `find_limb_obstacles` takes at most (a disc per skeleton pixel, and one
/// at each end of a limb for the limbs leaving it there).
[[nodiscard]] constexpr std::size_t limb_obstacles_workspace_bytes(std::size_t limbs,
                                                                std::size_t skeleton_pixels,
                                                                int width, int height) noexcept {
  const std::size_t discs = skeleton_pixels + 2 * limbs;
  const std::size_t slots = detail::pixel_map_slots(skeleton_pixels);
  return workspace::footprint<owner_set>(limbs) + workspace::footprint<owned_disc>(discs) +
         2 * workspace::footprint<std::uint32_t>(slots) +
         2 * workspace::footprint<pixel>(skeleton_pixels) +
         disc_index::workspace_bytes(discs, width, height);
}

/// The owner of a disc that belongs to no limb: an obstacle to every limb.
inline constexpr std::int32_t unowned_disc = -2;

namespace detail {

/// Radius (px) of limb `limb`'s point `i`, as an obstacle: beside a junction node at either of
/// the limb's ends, inside the node's disc, the distance map measures the body the limb merges
/// into, not the limb; there the limb is taken to carry on with the radius it has where it
/// leaves the node's disc (its base modelled as reaching the parent's axis, as a limb grows).
struct junction_caps {
  float front_reach2 = -1, front_radius = 0;  ///< squared reach from the first point's node
  float back_reach2 = -1, back_radius = 0;
  point2f front_node{0, 0}, back_node{0, 0};
};

[[nodiscard]] inline junction_caps caps_of(const skeleton_graph& graph, const skeleton_limb& limb,
                                           bool closed) noexcept {
  junction_caps caps;
  const std::size_t n = limb.points.size();
  if (closed || n == 0) return caps;
  auto cap_at = [&](std::size_t end, bool front, float& reach2, float& radius, point2f& at) {
    const skeleton_node node = graph.node(node_at_end(graph, end));
    if (node.kind != node_kind::junction) return;
    at = to_point(node.position);
    const float reach = node.radius_px + 1.0f;
    reach2 = reach * reach;
    radius = front ? limb.radius_px[n - 1] : limb.radius_px[0];  // the farthest, at worst
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = front ? k : n - 1 - k;
      if ((to_point(limb.points[i]) - at).squaredNorm() > reach2) {
        radius = limb.radius_px[i];
        return;
      }
    }
  };
  cap_at(limb.first_end, true, caps.front_reach2, caps.front_radius, caps.front_node);
  cap_at(limb.last_end, false, caps.back_reach2, caps.back_radius, caps.back_node);
  return caps;
}

/// The disc that stands for the limbs leaving limb `limb` at the junction at its end `end`
/// (`front`: its first point's): as wide as the widest of them where it leaves the node, at
/// the base farthest from the node among theirs (`limb_at_junction`: where a limb's axis,
/// extended back, meets this limb's centreline), or at `stretch_end`, where the limb's stretch
/// ends (`limb_stretch`: clear of the junction's bodies), for a limb without a straight axis
/// there. The skeleton splits a narrow fork only where the limbs' surfaces part, beyond the
/// true fork, so a child's own discs begin too far along; a child that carries on straight is
/// still another limb, from the fork on. Limbs wider than this one there (`own_radius`) are the
/// parent it leaves, whose own discs stand for it. Radius 0: no such limb.
[[nodiscard]] inline owned_disc junction_disc(const skeleton_graph& graph,
                                              const skeleton_limb& limb, std::size_t end,
                                              bool front, pixel stretch_end,
                                              float own_radius) noexcept {
  owned_disc out{0, 0, 0, unowned_disc};
  const node_id id = node_at_end(graph, end);
  const skeleton_node node = graph.node(id);
  if (node.kind != node_kind::junction) return out;
  const std::size_t n = limb.points.size();
  auto own_at = [&](std::size_t k) { return limb.points[front ? k : n - 1 - k]; };
  const point2f centre = to_point(node.position);
  const float reach = 2.5f * node.radius_px + 4.0f;
  float farthest = -1;
  for (const incidence in : graph.topology().incidences(id)) {
    if (in.edge == edge_of_end(end)) continue;
    const skeleton_branch other = graph.branch(in.edge);
    const float r = leaving_axis_of(other, in.direction, node).radius_near_px;
    if (!(r > 0) || r > own_radius) continue;
    const junction_limb child = limb_at_junction(other, in.direction, node, own_at, n, reach);
    const point2f base = child.valid ? child.base : to_point(stretch_end);
    out.radius = std::max(out.radius, r);
    if ((base - centre).norm() > farthest) {
      farthest = (base - centre).norm();
      out.x = base.x();
      out.y = base.y();
    }
  }
  return out;
}

/// A map from pixels of a `width`-wide frame to indexes, in zeroed workspace slots
/// (`pixel_map_slots` of each): open addressing with linear probing, key y·width + x + 1 (0
/// marks an empty slot).
struct pixel_map {
  std::span<std::uint32_t> keys;
  std::span<std::uint32_t> values;
  int width = 0;
  [[nodiscard]] std::uint32_t key(pixel p) const noexcept {
    return static_cast<std::uint32_t>(p.y) * static_cast<std::uint32_t>(width) +
           static_cast<std::uint32_t>(p.x) + 1u;
  }
  [[nodiscard]] std::size_t slot(pixel p) const noexcept {
    const std::uint32_t k = key(p);
    std::size_t i = static_cast<std::size_t>(k * 0x9E3779B1u) & (keys.size() - 1);  // Fibonacci
    while (keys[i] != 0 && keys[i] != k) i = (i + 1) & (keys.size() - 1);
    return i;
  }
  void insert(pixel p, std::uint32_t value) const noexcept {
    const std::size_t i = slot(p);
    keys[i] = key(p);
    values[i] = value;
  }
  /// The value of `p`, or `absent`.
  static constexpr std::uint32_t absent = 0xFFFFFFFFu;
  [[nodiscard]] std::uint32_t find(pixel p) const noexcept {
    const std::size_t i = slot(p);
    return keys[i] != 0 ? values[i] : absent;
  }
};

/// The disc table `find_limb_obstacles` fills: `total` discs, and the map from each placed
/// pixel to its disc (`pending` for a skeleton pixel listed but not placed yet).
struct disc_table {
  std::span<owned_disc> discs;
  pixel_map disc_of;
  std::size_t total = 0;
  std::size_t count = 0;
  static constexpr std::uint32_t pending = pixel_map::absent - 1;

  void place(pixel p, float radius, std::int32_t owner) noexcept {
    discs[count] = {static_cast<float>(p.x), static_cast<float>(p.y), radius, owner};
    disc_of.insert(p, static_cast<std::uint32_t>(count++));
  }
};

/// Step 1 of `find_limb_obstacles`: a disc per limb point, of its distance-map radius, capped
/// beside the junctions at its ends (`caps_of`); and each limb's owner set (itself).
inline void place_limb_discs(const skeleton_graph& graph, std::span<const skeleton_limb> limbs,
                             const edge_continuations& next, std::span<owner_set> own,
                             disc_table& table) noexcept {
  for (std::size_t l = 0; l < limbs.size(); ++l) {
    const skeleton_limb& limb = limbs[l];
    const bool closed = next.joined(limb.first_end);
    own[l].ids[0] = static_cast<std::int32_t>(l);
    const junction_caps caps = caps_of(graph, limb, closed);
    for (std::size_t i = 0; i < limb.points.size(); ++i) {
      const point2f p = to_point(limb.points[i]);
      float r = limb.radius_px[i];
      if ((p - caps.front_node).squaredNorm() <= caps.front_reach2) r = std::min(r, caps.front_radius);
      if ((p - caps.back_node).squaredNorm() <= caps.back_reach2) r = std::min(r, caps.back_radius);
      if (table.count < table.total && table.disc_of.find(limb.points[i]) == pixel_map::absent)
        table.place(limb.points[i], r, static_cast<std::int32_t>(l));
    }
  }
}

/// Step 2: the skeleton's other pixels, marked `pending` and listed in `walk` (at most its
/// size); returns their count.
inline std::size_t list_other_pixels(image_view<const std::uint8_t> skeleton, const row_runs* runs,
                                     disc_table& table, std::span<pixel> walk) noexcept {
  std::size_t unplaced = 0;
  for_each_skeleton_pixel(skeleton, runs, [&](int x, int y) {
    if (table.disc_of.find({x, y}) != pixel_map::absent || unplaced == walk.size()) return;
    table.disc_of.insert({x, y}, disc_table::pending);
    walk[unplaced++] = {x, y};
  });
  return unplaced;
}

/// Step 3: a breadth-first walk from the limbs through the other pixels (`walk`): each takes
/// the owner of the placed neighbour it is reached from, and no more than its radius. First
/// those next to a limb point, then on along the spurs.
/// `width` × `height`: the frame's.
inline void walk_from_limbs(disc_table& table, std::span<const pixel> walk, std::span<pixel> queue,
                            image_view<const std::uint32_t> dist2, int width, int height) noexcept {
  constexpr std::uint32_t pending = disc_table::pending;
  auto inside = [&](pixel q) { return q.x >= 0 && q.y >= 0 && q.x < width && q.y < height; };
  auto placed_neighbour = [&](pixel p) -> const owned_disc* {
    for (const pixel d : neighbours8) {
      const pixel q{p.x + d.x, p.y + d.y};
      if (!inside(q)) continue;
      const std::uint32_t v = table.disc_of.find(q);
      if (v < pending) return &table.discs[v];
    }
    return nullptr;
  };
  std::size_t queued = 0;
  auto reach = [&](pixel q, const owned_disc& from) {
    table.place(q, std::min(std::sqrt(static_cast<float>(dist2(q.x, q.y))), from.radius),
                from.owner);
    queue[queued++] = q;
  };
  for (std::size_t k = 0; k < walk.size() && table.count < table.total; ++k) {
    const pixel p = walk[k];
    if (table.disc_of.find(p) != pending) continue;
    if (const owned_disc* from = placed_neighbour(p)) {
      const owned_disc parent = *from;
      reach(p, parent);
    }
  }
  for (std::size_t head = 0; head < queued && table.count < table.total; ++head) {
    const pixel from = queue[head];
    const owned_disc parent = table.discs[table.disc_of.find(from)];
    for (const pixel d : neighbours8) {
      const pixel q{from.x + d.x, from.y + d.y};
      if (table.count < table.total && inside(q) && table.disc_of.find(q) == pending)
        reach(q, parent);
    }
  }
}

/// Step 4: what the walk never reached: pieces of skeleton with no limb, everyone's obstacle.
inline void place_unreached(disc_table& table, std::span<const pixel> walk,
                            image_view<const std::uint32_t> dist2) noexcept {
  for (std::size_t k = 0; k < walk.size() && table.count < table.total; ++k) {
    const pixel p = walk[k];
    if (table.disc_of.find(p) == disc_table::pending)
      table.place(p, std::sqrt(static_cast<float>(dist2(p.x, p.y))), unowned_disc);
  }
}

/// Step 5: obstacles: the discs at least a twig thick (`min_radius_px`), less ½ px.
inline void keep_obstacles(disc_table& table, float min_radius_px) noexcept {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < table.count; ++i)
    if (table.discs[i].radius >= min_radius_px) {
      owned_disc d = table.discs[i];
      d.radius -= 0.5f;
      table.discs[kept++] = d;
    }
  table.count = kept;
}

/// Step 6: the limbs leaving each limb at the junctions at its ends, from the fork on
/// (`junction_disc`), when at least a twig thick, less ½ px.
inline void place_junction_discs(const skeleton_graph& graph, std::span<const skeleton_limb> limbs,
                                 const edge_continuations& next,
                                 std::span<const branch_stretch> stretches, float min_radius_px,
                                 disc_table& table) noexcept {
  for (std::size_t l = 0; l < limbs.size(); ++l) {
    const skeleton_limb& limb = limbs[l];
    const branch_stretch s = stretches[l];
    if (next.joined(limb.first_end) || s.count == 0) continue;
    for (const bool front : {true, false}) {
      const std::size_t i = front ? s.first : s.first + s.count - 1;
      owned_disc d = junction_disc(graph, limb, front ? limb.first_end : limb.last_end, front,
                                   limb.points[i], limb.radius_px[i]);
      if (d.radius < min_radius_px || table.count >= table.total) continue;
      d.radius -= 0.5f;
      table.discs[table.count++] = d;
    }
  }
}
}  // namespace detail

/// The obstacle discs of every limb and the owner sets of `limbs` (from `trace_limbs` with the
/// continuations `next`; `stretches` from `limb_stretch`), for a frame of `width` × `height`
/// (the limbs' coordinates) at `mm_per_px`:
///  - a disc per limb point, of its distance-map radius less ½ px (the map measures to the
///    nearest background pixel centre, half a pixel beyond the outline), capped beside the
///    junctions at its ends (`detail::caps_of`);
///  - a disc per other pixel of `skeleton` (`dist2` its squared distances): the spurs pruning
///    took off (a bump of the outline, the short end of a limb hugging its parent) and the
///    junctions' own pixels, owned by the limb they hang from along the skeleton (a breadth-first walk
///    from the limbs' points: a spur belongs to the body it grows from, not to a limb across a
///    gap), and no wider than the limb point they hang from. The mask keeps what pruning drops
///    from the graph, and a claw meets the mask. A piece of skeleton joined to no limb (a blob
///    pruning took whole) is everyone's obstacle;
///  - at each end of a limb at a junction, a disc for the limbs leaving it there
///    (`detail::junction_disc`).
/// Discs thinner than a twig (`obstacle_options`) are left out.
/// Errors: `workspace_too_small` for a borrowed workspace.
/// Complexity: O(skeleton pixels + cells).
[[nodiscard]] inline result<limb_obstacles> find_limb_obstacles(
    const skeleton_graph& graph, std::span<const skeleton_limb> limbs,
    const edge_continuations& next, std::span<const branch_stretch> stretches,
    image_view<const std::uint8_t> skeleton, image_view<const std::uint32_t> dist2,
    const row_runs* runs, float mm_per_px, workspace& ws,
    const obstacle_options& options = {}) noexcept {
  PERCH_ASSERT(stretches.size() == limbs.size(), "find_limb_obstacles: stretches");
  const int width = skeleton.width();
  const int height = skeleton.height();
  std::size_t points = 0;
  for (const skeleton_limb& l : limbs) points += l.points.size();
  const std::size_t pixels = std::max(points, detail::count_set_pixels(skeleton, runs));
  const std::size_t total = pixels + 2 * limbs.size();
  const std::size_t slots = detail::pixel_map_slots(pixels);
  auto own = ws.allocate<owner_set>(limbs.size());
  auto discs = ws.allocate<owned_disc>(total);
  auto keys = ws.allocate_zeroed<std::uint32_t>(slots);
  auto values = ws.allocate<std::uint32_t>(slots);
  auto walk = ws.allocate<pixel>(pixels);   // the pixels not on a limb
  auto queue = ws.allocate<pixel>(pixels);  // the breadth-first walk's queue
  PERCH_TRY(all_ok(own, discs, keys, values, walk, queue));
  // Limb points, then the skeleton's other pixels (`pending`), mapped to their discs.
  detail::disc_table table{*discs, detail::pixel_map{*keys, *values, width}, total};
  const float min_radius_px = options.twig_radius_px(mm_per_px);
  detail::place_limb_discs(graph, limbs, next, *own, table);
  const std::size_t unplaced = detail::list_other_pixels(skeleton, runs, table, *walk);
  const std::span<const pixel> others = walk->first(unplaced);
  detail::walk_from_limbs(table, others, *queue, dist2, width, height);
  detail::place_unreached(table, others, dist2);
  detail::keep_obstacles(table, min_radius_px);
  detail::place_junction_discs(graph, limbs, next, stretches, min_radius_px, table);
  auto index = disc_index::build(std::span<const owned_disc>(*discs).first(table.count), width,
                                 height, ws);
  PERCH_TRY(all_ok(index));
  return limb_obstacles{*index, *own};
}

/// Marks in `grounded` (one flag per graph component) the components that hold something up:
/// those with a limb whose outline reaches the bottom row of the frame (within `reach_px`),
/// and the main tree, the component with the most limb area (Σ r² over its limbs' points).
/// `bottom_row` is the frame's last row in the limbs' coordinates.
inline void grounded_components(std::span<const skeleton_limb> limbs, float bottom_row,
                                std::span<std::uint8_t> grounded, std::span<float> area,
                                float reach_px = 2.0f) noexcept {
  std::fill(grounded.begin(), grounded.end(), std::uint8_t{0});
  std::fill(area.begin(), area.end(), 0.0f);
  for (const skeleton_limb& limb : limbs) {
    if (limb.component < 0 || static_cast<std::size_t>(limb.component) >= grounded.size()) continue;
    const auto c = static_cast<std::size_t>(limb.component);
    for (std::size_t i = 0; i < limb.points.size(); ++i) {
      const float r = limb.radius_px[i];
      area[c] += r * r;
      if (static_cast<float>(limb.points[i].y) + r + reach_px >= bottom_row) grounded[c] = 1;
    }
  }
  if (area.empty()) return;
  const auto main = static_cast<std::size_t>(std::max_element(area.begin(), area.end()) - area.begin());
  grounded[main] = 1;
}

}  // namespace perch
