// SPDX-License-Identifier: BSL-1.0
/// \file
/// The skeleton graph (paper §"Section into Branches" and §"Create Graph"): junction clusters
/// and branch ends as nodes, branches as edges carrying their ordered centreline with the
/// radius at each point; one graph for every connected component, each with its trunk node.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <utility>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/union_find.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/adjacency_list.hpp"
#include "perch/graph/detail/records.hpp"
#include "perch/graph/detail/scan.hpp"
#include "perch/graph/pixel_kinds.hpp"

namespace perch {

/// The role of a node in the skeleton graph (from its degree, so it stays true after pruning).
enum class node_kind : std::uint8_t {
  end,       ///< degree 1: a branch tip (skan's "tip")
  junction,  ///< degree ≥ 2: a junction cluster where branches meet
  isolated,  ///< degree 0: a lone pixel (or a blob of junction pixels with no branch)
  loop,      ///< the node of a closed loop without junctions: its only edge is a self-loop
};

/// A branch's type in skan's words, from the degrees of its end nodes.
enum class branch_type : std::uint8_t {
  tip_tip,            ///< both ends are tips: a whole component that is one line
  tip_junction,       ///< one end is a tip
  junction_junction,  ///< both ends are junctions
  cycle,              ///< starts and ends at the same node
};

[[nodiscard]] constexpr std::string_view to_string(node_kind k) noexcept {
  switch (k) {
    case node_kind::end:
      return "end";
    case node_kind::junction:
      return "junction";
    case node_kind::isolated:
      return "isolated";
    case node_kind::loop:
      return "loop";
  }
  return "unknown";
}

[[nodiscard]] constexpr std::string_view to_string(branch_type t) noexcept {
  switch (t) {
    case branch_type::tip_tip:
      return "tip-tip";
    case branch_type::tip_junction:
      return "tip-junction";
    case branch_type::junction_junction:
      return "junction-junction";
    case branch_type::cycle:
      return "cycle";
  }
  return "unknown";
}

/// A node as a user reads it (a value; cheap to copy).
struct skeleton_node {
  node_id id = no_id;
  pixel position{};              ///< end / loop / isolated pixel; a cluster's widest pixel
  node_kind kind = node_kind::isolated;
  std::int32_t component = -1;   ///< 0, 1, ... in raster order of each component's first pixel
  float radius_px = 0;           ///< radius at `position` (a cluster: its largest)
  std::int32_t degree = 0;       ///< edge ends here (a self-loop counts 2)
  std::uint32_t pixel_count = 0; ///< skeleton pixels the node owns: cluster size, 1 isolated, else 0
  bool trunk = false;            ///< the trunk node of its component
};

/// A branch (edge) as a user reads it (a value of spans into the graph; cheap to copy).
///
/// `points` is the ordered centreline from the `from` node's side to the `to` node's side;
/// `radius_px[i]` is the distance to the background at `points[i]`. Points are the skeleton
/// pixels the branch owns: junction pixels are not included, except that pruning's degree-2
/// merges insert the (one or two) junction pixels where the two joined branches attached, so a
/// merged polyline is continuous. `length_px` is the sum of steps (1 or √2) along the points,
/// plus the step from each junction attachment pixel into the first / last point (an end node
/// adds nothing: its pixel is the first or last point; a closed loop adds its closing step).
struct skeleton_branch {
  edge_id id = no_id;
  node_id from = no_id;
  node_id to = no_id;
  std::int32_t component = -1;
  branch_type type = branch_type::tip_tip;
  std::span<const pixel> points{};
  std::span<const float> radius_px{};
  float length_px = 0;
  float mean_diameter_px = 0;  ///< mean of 2·r − 1 over `points`
  float weight = 0;            ///< paper eq. 1, set by `weigh_skeleton_graph` / pruning
};

/// Options of `build_skeleton_graph`: capacities (0 = as many as the skeleton can need, i.e.
/// one node and one edge per skeleton pixel; a larger capacity is lowered to that).
struct graph_options {
  std::size_t max_nodes = 0;
  std::size_t max_branches = 0;
};

namespace detail {
struct skeleton_graph_access;
}

/// The graph of a skeleton: nodes are junction clusters, branch ends, loops and isolated pixels;
/// edges are branches with their polylines. Built by `build_skeleton_graph`, edited by
/// `prune_skeleton_graph`.
///
/// A handle over workspace memory: valid until the workspace is reset or rewound past it;
/// move-only. Node and branch ids are stable (see `adjacency_list`); removed ones stay removed.
class skeleton_graph {
 public:
  using topology_type = adjacency_list<detail::skeleton_node_data, detail::skeleton_edge_data>;

  skeleton_graph() noexcept = default;
  skeleton_graph(const skeleton_graph&) = delete;
  skeleton_graph& operator=(const skeleton_graph&) = delete;
  skeleton_graph(skeleton_graph&&) noexcept = default;
  skeleton_graph& operator=(skeleton_graph&&) noexcept = default;
  ~skeleton_graph() = default;

  /// Live nodes / branches.
  [[nodiscard]] std::size_t node_count() const noexcept { return g_.node_count(); }
  [[nodiscard]] std::size_t branch_count() const noexcept { return g_.edge_count(); }
  /// Size of the node id space: a per-node array of this size can be indexed by any node id.
  [[nodiscard]] std::size_t node_capacity() const noexcept { return g_.node_capacity(); }
  [[nodiscard]] std::size_t branch_capacity() const noexcept { return g_.edge_capacity(); }
  [[nodiscard]] bool contains_node(node_id n) const noexcept { return g_.contains_node(n); }
  [[nodiscard]] bool contains_branch(edge_id e) const noexcept { return g_.contains_edge(e); }
  /// Skeleton pixels the graph was built from.
  [[nodiscard]] std::size_t skeleton_pixels() const noexcept { return skeleton_pixels_; }

  /// Connected components, numbered 0.. in raster order of their first skeleton pixel.
  [[nodiscard]] std::int32_t component_count() const noexcept { return components_; }
  /// The trunk node of component `c` (see `build_skeleton_graph` for the rule).
  [[nodiscard]] node_id trunk(std::int32_t c) const noexcept {
    PERCH_ASSERT(c >= 0 && c < components_, "skeleton_graph::trunk: no such component");
    return trunks_[static_cast<std::size_t>(c)];
  }

  /// Live node `n` (checked by `PERCH_ASSERT`).
  [[nodiscard]] skeleton_node node(node_id n) const noexcept {
    const detail::skeleton_node_data& d = g_.node(n);
    skeleton_node out;
    out.id = n;
    out.position = d.position;
    out.component = d.component;
    out.radius_px = d.radius_px;
    out.degree = g_.degree(n);
    out.pixel_count = d.pixel_count;
    out.trunk = d.trunk != 0;
    out.kind = kind_of(n);
    return out;
  }

  /// Live branch `e` (checked by `PERCH_ASSERT`).
  [[nodiscard]] skeleton_branch branch(edge_id e) const noexcept {
    const detail::skeleton_edge_data& d = g_.edge(e);
    PERCH_ASSERT(d.line.rope < 0, "skeleton_graph::branch during pruning");
    skeleton_branch out;
    out.id = e;
    out.from = g_.source(e);
    out.to = g_.target(e);
    out.component = d.component;
    if (out.from == out.to) {
      out.type = branch_type::cycle;
    } else {
      const int tips = (g_.degree(out.from) == 1 ? 1 : 0) + (g_.degree(out.to) == 1 ? 1 : 0);
      out.type = tips == 2 ? branch_type::tip_tip
                           : (tips == 1 ? branch_type::tip_junction : branch_type::junction_junction);
    }
    const auto pool = static_cast<std::size_t>(active_);
    out.points = std::span<const pixel>(points_[pool]).subspan(d.line.offset, d.line.count);
    out.radius_px = std::span<const float>(radii_[pool]).subspan(d.line.offset, d.line.count);
    out.length_px = d.length_px;
    out.mean_diameter_px =
        d.pixel_total > 0 ? d.diameter_sum_px / static_cast<float>(d.pixel_total) : 0.0f;
    out.weight = d.weight;
    return out;
  }

  /// Calls `f(const skeleton_node&)` for every live node, in id order.
  template <class F>
  void for_each_node(F&& f) const {
    g_.for_each_node([&](node_id n) {
      const skeleton_node v = node(n);
      f(v);
    });
  }
  /// Calls `f(const skeleton_branch&)` for every live branch, in id order.
  template <class F>
  void for_each_branch(F&& f) const {
    g_.for_each_edge([&](edge_id e) {
      const skeleton_branch v = branch(e);
      f(v);
    });
  }

  /// The underlying adjacency list, to walk neighbours and incidences
  /// (`topology().incidences(n)`, `neighbours(n)`, `incident_edges(n)`, `degree(n)`).
  [[nodiscard]] const topology_type& topology() const noexcept { return g_; }

 private:
  friend struct detail::skeleton_graph_access;

  [[nodiscard]] node_kind kind_of(node_id n) const noexcept {
    const std::int32_t degree = g_.degree(n);
    if (degree == 0) return node_kind::isolated;
    if (degree == 1) return node_kind::end;
    if (degree == 2) {
      auto edges = g_.incident_edges(n);
      auto it = edges.begin();
      const edge_id first = *it;
      ++it;
      if (*it == first) return node_kind::loop;
    }
    return node_kind::junction;
  }

  topology_type g_{};
  std::span<pixel> points_[2]{};
  std::span<float> radii_[2]{};
  int active_ = 0;
  std::span<node_id> trunks_{};
  std::int32_t components_ = 0;
  std::size_t skeleton_pixels_ = 0;
};

namespace detail {

inline constexpr std::uint32_t no_owner = 0xFFFFFFFFu;
inline constexpr std::uint32_t node_owner_tag = 0x80000000u;

/// Workspace bytes of the graph's own storage.
[[nodiscard]] constexpr std::size_t graph_storage_bytes(std::size_t pixels, std::size_t nodes,
                                                        std::size_t edges) noexcept {
  return skeleton_graph::topology_type::workspace_bytes(nodes, edges) +
         2 * workspace::footprint<pixel>(pixels) + 2 * workspace::footprint<float>(pixels) +
         workspace::footprint<node_id>(nodes);
}
/// Workspace bytes `build_skeleton_graph` uses temporarily (released before it returns).
[[nodiscard]] constexpr std::size_t graph_build_scratch_bytes(std::size_t pixels,
                                                              std::size_t nodes) noexcept {
  return workspace::footprint<pixel>(pixels) + 3 * workspace::footprint<std::uint8_t>(pixels) +
         2 * workspace::footprint<std::uint32_t>(pixels) +
         workspace::footprint<std::uint32_t>(2 * pixels) + workspace::footprint<float>(pixels) +
         2 * workspace::footprint<std::int32_t>(nodes) + workspace::footprint<float>(nodes);
}
/// Workspace bytes `prune_skeleton_graph` uses temporarily.
[[nodiscard]] constexpr std::size_t graph_prune_scratch_bytes(std::size_t nodes,
                                                              std::size_t edges) noexcept {
  return workspace::footprint<rope_node>(nodes) + workspace::footprint<std::int32_t>(edges) +
         workspace::footprint<rope_item>(3 * nodes + 4);
}
/// Workspace bytes `distances_to_trunk` uses temporarily.
[[nodiscard]] constexpr std::size_t graph_distance_scratch_bytes(std::size_t nodes) noexcept {
  return 2 * workspace::footprint<std::int32_t>(nodes);
}

/// The builder and the pruner reach the graph's storage through this.
struct skeleton_graph_access {
  static skeleton_graph::topology_type& topology(skeleton_graph& g) noexcept { return g.g_; }
  static std::span<pixel>& points(skeleton_graph& g, int pool) noexcept {
    return g.points_[static_cast<std::size_t>(pool)];
  }
  static std::span<float>& radii(skeleton_graph& g, int pool) noexcept {
    return g.radii_[static_cast<std::size_t>(pool)];
  }
  static int& active(skeleton_graph& g) noexcept { return g.active_; }
  static std::span<node_id>& trunks(skeleton_graph& g) noexcept { return g.trunks_; }
  static std::int32_t& components(skeleton_graph& g) noexcept { return g.components_; }
  static std::size_t& skeleton_pixels(skeleton_graph& g) noexcept { return g.skeleton_pixels_; }
};

/// The skeleton pixels in raster order and what tracing reads of each (step 1 of
/// `build_skeleton_graph`): position, neighbourhood, path neighbours, kind, radius, and the
/// node or branch that owns it. A neighbour's index follows from the neighbourhood and where in
/// the order the pixels from (x − 1, y − 1) and from (x − 1, y + 1) on start (`above`,
/// `below`), so no image-sized index map is needed.
struct skeleton_pixel_table {
  std::span<pixel> pos;
  std::span<std::uint8_t> mask;  ///< 8-neighbourhood (bit i = `neighbours8[i]`)
  std::span<std::uint8_t> path;  ///< path neighbours (`pixel_kinds_by_mask.path`)
  std::span<std::uint8_t> kind;  ///< `pixel_kind`
  std::span<std::uint32_t> owner;  ///< node id | `node_owner_tag`, edge id, or `no_owner`
  std::span<std::uint32_t> above;
  std::span<std::uint32_t> below;
  std::span<float> radii;

  /// The neighbour of pixel i in direction `bit` (which must be set in its neighbourhood): the
  /// row's other pixels are its raster neighbours; a row above or below holds the set ones of
  /// its three (west to east) consecutively from `above[i]` / `below[i]`.
  [[nodiscard]] std::size_t neighbour(std::size_t i, int bit) const noexcept {
    const unsigned m = mask[i];
    switch (bit) {
      case 0:  // E
        return i + 1;
      case 1:  // NE
        return above[i] + ((m >> 3) & 1u) + ((m >> 2) & 1u);
      case 2:  // N
        return above[i] + ((m >> 3) & 1u);
      case 3:  // NW
        return above[i];
      case 4:  // W
        return i - 1;
      case 5:  // SW
        return below[i];
      case 6:  // S
        return below[i] + ((m >> 5) & 1u);
      default:  // SE
        return below[i] + ((m >> 5) & 1u) + ((m >> 6) & 1u);
    }
  }
  [[nodiscard]] bool is(std::size_t i, pixel_kind pk) const noexcept {
    return kind[i] == static_cast<std::uint8_t>(pk);
  }
  [[nodiscard]] node_id node_of(std::size_t i) const noexcept {
    return static_cast<node_id>(owner[i] & ~node_owner_tag);
  }
  [[nodiscard]] bool node_owned(std::size_t i) const noexcept {
    return owner[i] != no_owner && (owner[i] & node_owner_tag) != 0;
  }
  [[nodiscard]] bool edge_owned(std::size_t i) const noexcept {
    return owner[i] != no_owner && (owner[i] & node_owner_tag) == 0;
  }
};

/// Step 1 of `build_skeleton_graph`: fills `t` with the `t.pos.size()` skeleton pixels in
/// raster order, their neighbourhoods, kinds and radii (√dist2), none owned yet.
template <BinaryView Skeleton>
void index_skeleton_pixels(const Skeleton& skeleton, image_view<const std::uint32_t> dist2,
                           const row_runs* runs, const skeleton_pixel_table& t) noexcept {
  const std::size_t n = t.pos.size();
  std::size_t k = 0;
  for_each_skeleton_pixel(skeleton, runs, [&](int x, int y) { t.pos[k++] = pixel{x, y}; });
  PERCH_ASSERT(k == n, "build_skeleton_graph: pixel count changed");
  auto before = [&](std::size_t j, int x, int y) {  // pos[j] before (x, y) in raster order
    return t.pos[j].y < y || (t.pos[j].y == y && t.pos[j].x < x);
  };
  std::size_t up = 0;
  std::size_t down = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const pixel p = t.pos[i];
    // The distances are read at scattered pixels: each fetched 16 pixels ahead.
    if (i + 16 < n) prefetch(&dist2(t.pos[i + 16].x, t.pos[i + 16].y));
    while (before(up, p.x - 1, p.y - 1)) ++up;  // stops at i at the latest
    while (down < n && before(down, p.x - 1, p.y + 1)) ++down;
    t.above[i] = static_cast<std::uint32_t>(up);
    t.below[i] = static_cast<std::uint32_t>(down);
    const std::uint8_t m = neighbour_mask(skeleton, p.x, p.y);
    t.mask[i] = m;
    t.path[i] = pixel_kinds_by_mask.path[m];
    t.kind[i] = static_cast<std::uint8_t>(pixel_kinds_by_mask.kind[m]);
    t.owner[i] = no_owner;
    t.radii[i] = static_cast<float>(std::sqrt(static_cast<double>(dist2(p.x, p.y))));
  }
}

/// One junction cluster (the 8-connected junction pixels reached from pixel `first`) as node
/// `id`, placed at its widest pixel (first in raster order on ties). `stack`: scratch of one
/// entry per skeleton pixel.
inline void gather_junction_cluster(skeleton_graph::topology_type& g,
                                    const skeleton_pixel_table& t, std::span<std::uint32_t> stack,
                                    std::size_t first, node_id id) noexcept {
  const std::uint32_t tag = node_owner_tag | static_cast<std::uint32_t>(id);
  std::size_t top = 0;
  stack[top++] = static_cast<std::uint32_t>(first);
  t.owner[first] = tag;
  std::uint32_t count = 0;
  std::size_t widest = first;
  float widest_r = t.radii[first];
  while (top > 0) {
    const std::size_t j = stack[--top];
    ++count;
    const float r = t.radii[j];
    if (r > widest_r || (r == widest_r && j < widest)) {
      widest = j;
      widest_r = r;
    }
    for (int b = 0; b < 8; ++b) {
      if (((static_cast<unsigned>(t.mask[j]) >> b) & 1u) == 0) continue;
      const std::size_t q = t.neighbour(j, b);
      if (t.is(q, pixel_kind::junction) && t.owner[q] == no_owner) {
        t.owner[q] = tag;
        stack[top++] = static_cast<std::uint32_t>(q);
      }
    }
  }
  skeleton_node_data& d = g.node(id);
  d.position = t.pos[widest];
  d.radius_px = widest_r;
  d.pixel_count = count;
}

/// Step 2 of `build_skeleton_graph`: nodes in raster order of their first pixel: junction
/// clusters (8-connected junction pixels), ends, isolated pixels.
inline status add_skeleton_nodes(skeleton_graph::topology_type& g, const skeleton_pixel_table& t,
                                 std::span<std::uint32_t> stack) noexcept {
  for (std::size_t i = 0; i < t.pos.size(); ++i) {
    if (t.is(i, pixel_kind::junction)) {
      if (t.owner[i] != no_owner) continue;
      auto id = g.add_node();
      PERCH_TRY(all_ok(id));
      gather_junction_cluster(g, t, stack, i, *id);
    } else if (t.is(i, pixel_kind::end) || t.is(i, pixel_kind::isolated)) {
      skeleton_node_data d;
      d.position = t.pos[i];
      d.radius_px = t.radii[i];
      d.pixel_count = t.is(i, pixel_kind::isolated) ? 1u : 0u;
      auto id = g.add_node(d);
      PERCH_TRY(all_ok(id));
      t.owner[i] = node_owner_tag | static_cast<std::uint32_t>(*id);
    }
  }
  return {};
}

/// `error::detail` of a build that met its branch cap (`graph_options::max_branches`); one
/// that met its node cap names `adjacency_list`'s nodes.
inline constexpr std::string_view skeleton_graph_branches_detail = "skeleton_graph branches";

/// The branch polylines being written into the graph's first pool.
struct branch_writer {
  std::span<pixel> points;
  std::span<float> radii;
  std::size_t used = 0;
};

/// One branch: from pixel `start` (after junction pixel `from_pixel`, or `no_owner` from an
/// end or a loop) along path neighbours until an end pixel, a junction, or back at the start
/// of a closed loop; added as an edge from node `from`.
inline status trace_branch(skeleton_graph::topology_type& g, const skeleton_pixel_table& t,
                           branch_writer& w, std::size_t start, std::size_t from_pixel,
                           node_id from) noexcept {
  if (static_cast<std::size_t>(g.edge_id_end()) == g.edge_capacity())
    return fail(errc::capacity_exceeded, skeleton_graph_branches_detail, g.edge_capacity() + 1);
  const auto id = static_cast<std::uint32_t>(g.edge_id_end());
  skeleton_edge_data d;
  d.line.offset = static_cast<std::uint32_t>(w.used);
  if (from_pixel != no_owner)
    d.from_anchor = branch_anchor{t.pos[from_pixel], t.radii[from_pixel], 1};
  std::size_t prev = from_pixel;
  std::size_t cur = start;
  node_id to = from;
  for (std::size_t guard = 0; guard <= t.pos.size(); ++guard) {
    if (t.node_owned(cur)) to = t.node_of(cur);  // an end pixel: its node
    const float r = t.radii[cur];
    w.points[w.used] = t.pos[cur];
    w.radii[w.used] = r;
    ++w.used;
    d.diameter_sum_px += diameter_from_radius(r);
    if (prev != no_owner) d.length_px += pixel_step_px(t.pos[prev], t.pos[cur]);
    t.owner[cur] = id;
    std::size_t next = no_owner;
    std::size_t junction = no_owner;
    for (int b = 0; b < 8; ++b) {
      if (((static_cast<unsigned>(t.path[cur]) >> b) & 1u) == 0) continue;
      const std::size_t q = t.neighbour(cur, b);
      if (q == prev) continue;
      if (t.is(q, pixel_kind::junction)) {
        if (junction == no_owner) junction = q;
      } else if (next == no_owner) {
        next = q;
      }
    }
    if (junction != no_owner) {
      d.length_px += pixel_step_px(t.pos[cur], t.pos[junction]);
      d.to_anchor = branch_anchor{t.pos[junction], t.radii[junction], 1};
      to = t.node_of(junction);
      break;
    }
    if (next == no_owner) break;  // an end pixel
    if (t.edge_owned(next)) {     // back at the start of a closed loop
      if (t.owner[next] == id) d.length_px += pixel_step_px(t.pos[cur], t.pos[next]);
      break;
    }
    prev = cur;
    cur = next;
  }
  d.line.count = static_cast<std::uint32_t>(w.used - d.line.offset);
  d.pixel_total = d.line.count;
  auto e = g.add_edge(from, to, d);
  PERCH_TRY(all_ok(e));
  return {};
}

/// Step 3 of `build_skeleton_graph`: branches, walked along path neighbours from each end and
/// from each junction pixel's untraced path neighbours; then closed loops from their first
/// raster pixel, each with a node of its own.
inline status trace_skeleton_branches(skeleton_graph::topology_type& g,
                                      const skeleton_pixel_table& t, branch_writer& w) noexcept {
  const std::size_t n = t.pos.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (t.is(i, pixel_kind::end) && t.node_owned(i)) {
      PERCH_TRY(trace_branch(g, t, w, i, no_owner, t.node_of(i)));
    } else if (t.is(i, pixel_kind::junction)) {
      for (int b = 0; b < 8; ++b) {
        if (((static_cast<unsigned>(t.path[i]) >> b) & 1u) == 0) continue;
        const std::size_t q = t.neighbour(i, b);
        if (t.is(q, pixel_kind::junction) || t.edge_owned(q)) continue;
        PERCH_TRY(trace_branch(g, t, w, q, i, t.node_of(i)));
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!t.is(i, pixel_kind::body) || t.owner[i] != no_owner) continue;
    skeleton_node_data d;
    d.position = t.pos[i];
    d.radius_px = t.radii[i];
    auto id = g.add_node(d);
    PERCH_TRY(all_ok(id));
    PERCH_TRY(trace_branch(g, t, w, i, no_owner, *id));
  }
  return {};
}

/// Step 4 of `build_skeleton_graph`: components by union–find over the edges, numbered in
/// raster order of their first pixel; returns their count. `parent`, `number`: scratch of
/// one entry per node id.
inline std::int32_t number_skeleton_components(skeleton_graph::topology_type& g,
                                               const skeleton_pixel_table& t,
                                               std::span<std::int32_t> parent,
                                               std::span<std::int32_t> number) noexcept {
  const auto node_end = static_cast<std::size_t>(g.node_id_end());
  union_find sets{parent.data(), 0, static_cast<std::int32_t>(parent.size()) - 1};
  sets.make_singletons(g.node_id_end());
  for (std::size_t i = 0; i < node_end; ++i) number[i] = -1;
  g.for_each_edge([&](edge_id e) { (void)sets.merge(g.source(e), g.target(e)); });
  sets.resolve();
  auto root_of = [&](node_id v) { return static_cast<std::size_t>(sets.parent[v]); };
  std::int32_t components = 0;
  for (std::size_t i = 0; i < t.pos.size(); ++i) {
    const node_id any = t.node_owned(i) ? t.node_of(i) : g.source(static_cast<edge_id>(t.owner[i]));
    const std::size_t root = root_of(any);
    if (number[root] < 0) number[root] = components++;
  }
  g.for_each_node([&](node_id v) { g.node(v).component = number[root_of(v)]; });
  g.for_each_edge([&](edge_id e) { g.edge(e).component = g.node(g.source(e)).component; });
  return components;
}

/// Step 5 of `build_skeleton_graph`: the trunk node of each of the `trunks.size()` components
/// (see there for the rule), marked in the graph. `largest`: scratch of one entry per
/// component; `radii`: the pool the branches' radii were written to.
inline void choose_trunks(skeleton_graph::topology_type& g, std::span<const float> radii,
                          std::span<float> largest, std::span<node_id> trunks) noexcept {
  for (std::size_t c = 0; c < trunks.size(); ++c) {
    largest[c] = -1.0f;
    trunks[c] = no_id;
  }
  auto end_radius = [&](node_id v) {  // the mean radius of an end's branch
    const edge_id e = *g.incident_edges(v).begin();
    const skeleton_edge_data& d = g.edge(e);
    double sum = 0;
    for (std::size_t i = 0; i < d.line.count; ++i)
      sum += static_cast<double>(radii[d.line.offset + i]);
    return d.line.count > 0 ? static_cast<float>(sum / static_cast<double>(d.line.count)) : 0.0f;
  };
  g.for_each_node([&](node_id v) {
    if (g.degree(v) != 1) return;
    const auto c = static_cast<std::size_t>(g.node(v).component);
    const float r = end_radius(v);
    if (r > largest[c]) largest[c] = r;
  });
  auto better = [&](node_id a, float ra, node_id b, float rb) {
    const pixel pa = g.node(a).position;
    const pixel pb = g.node(b).position;
    if (pa.y != pb.y) return pa.y > pb.y;
    if (ra != rb) return ra > rb;
    return pa.x < pb.x;
  };
  g.for_each_node([&](node_id v) {
    const auto c = static_cast<std::size_t>(g.node(v).component);
    const bool has_ends = largest[c] >= 0.0f;
    float r = 0;
    if (has_ends) {
      if (g.degree(v) != 1) return;
      r = end_radius(v);
      if (r < 0.5f * largest[c]) return;
    } else {
      r = g.node(v).radius_px;
    }
    const node_id best = trunks[c];
    if (best == no_id) {
      trunks[c] = v;
      return;
    }
    const float rb = has_ends ? end_radius(best) : g.node(best).radius_px;
    if (better(v, r, best, rb)) trunks[c] = v;
  });
  for (const node_id v : trunks)
    if (v != no_id) g.node(v).trunk = 1;
}

/// Everything of `build_skeleton_graph` after the graph's storage is allocated, its five steps
/// in order; `scratch` memory is drawn from `ws` and released by the caller.
template <BinaryView Skeleton>
[[nodiscard]] status trace_skeleton(const Skeleton& skeleton, image_view<const std::uint32_t> dist2,
                                    const row_runs* runs, skeleton_graph& out,
                                    workspace& ws) noexcept {
  using access = skeleton_graph_access;
  auto& g = access::topology(out);
  const std::size_t n = access::skeleton_pixels(out);
  const std::size_t node_cap = g.node_capacity();
  auto pos = ws.allocate<pixel>(n);
  auto mask = ws.allocate<std::uint8_t>(n);
  auto path = ws.allocate<std::uint8_t>(n);
  auto kind = ws.allocate<std::uint8_t>(n);
  auto owner = ws.allocate<std::uint32_t>(n);
  auto stack = ws.allocate<std::uint32_t>(n);
  auto rows = ws.allocate<std::uint32_t>(2 * n);  // `above`, then `below`
  auto radii = ws.allocate<float>(n);
  auto parent = ws.allocate<std::int32_t>(node_cap);
  auto number = ws.allocate<std::int32_t>(node_cap);
  auto largest = ws.allocate<float>(node_cap);
  PERCH_TRY(all_ok(pos, mask, path, kind, owner, stack, rows, radii, parent, number, largest));
  const skeleton_pixel_table t{*pos,  *mask, *path, *kind, *owner, rows->first(n),
                               rows->subspan(n), *radii};

  index_skeleton_pixels(skeleton, dist2, runs, t);
  PERCH_TRY(add_skeleton_nodes(g, t, *stack));
  branch_writer w{access::points(out, 0), access::radii(out, 0)};
  PERCH_TRY(trace_skeleton_branches(g, t, w));
  const std::int32_t components = number_skeleton_components(g, t, *parent, *number);
  access::components(out) = components;
  choose_trunks(g, access::radii(out, 0), *largest,
                access::trunks(out).first(static_cast<std::size_t>(components)));
  return {};
}

}  // namespace detail

/// Bytes of workspace that `build_skeleton_graph`, `prune_skeleton_graph` and
/// `distances_to_trunk` need together at most, for a `width` × `height` skeleton with
/// `skeleton_pixels` pixels and default `graph_options` (pass `width · height` when the count
/// is not known: an upper bound). A borrowed workspace of this size never fails for lack of room.
[[nodiscard]] constexpr std::size_t skeleton_graph_workspace_bytes(
    int width, int height, std::size_t skeleton_pixels) noexcept {
  const std::size_t image = width > 0 && height > 0
                                ? static_cast<std::size_t>(width) * static_cast<std::size_t>(height)
                                : 0;
  const std::size_t n = skeleton_pixels < image ? skeleton_pixels : image;
  const std::size_t build = detail::graph_build_scratch_bytes(n, n);
  const std::size_t prune = detail::graph_prune_scratch_bytes(n, n);
  const std::size_t dist = detail::graph_distance_scratch_bytes(n);
  std::size_t scratch = build > prune ? build : prune;
  scratch = scratch > dist ? scratch : dist;
  return detail::graph_storage_bytes(n, n, n) + scratch;
}

/// Builds the skeleton graph of every connected component of `skeleton`.
///
/// 1. Pixel kinds: each skeleton pixel (non-zero) is isolated, end, body or junction by its
///    8-neighbourhood (`classify_neighbourhood`: crossing number, 2×2 blocks are junctions).
/// 2. Junction clusters: 8-connected junction pixels form one cluster = one node, placed at its
///    pixel of largest radius (first in raster order on ties); its `pixel_count` is its size.
/// 3. Branches: the skeleton minus the junction clusters, walked along path neighbours
///    (`path_neighbours`), never by contour following, so each pixel is visited once: from each
///    end pixel, then from each untraced path neighbour of a junction pixel (raster order), and
///    last each closed loop without junction from its first raster pixel, first along the
///    first path neighbour in `neighbours8` order. A loop gets a node of kind `loop` with one
///    self-loop edge (type cycle); an isolated pixel one node of kind `isolated` and no edge.
///    Every skeleton pixel ends up in exactly one branch polyline or one node (`pixel_count`).
///    Length convention: see `skeleton_branch`.
/// 4. Components: numbered 0.. in raster order of their first pixel.
/// 5. Trunk node of each component: the medial axis forks or thins where a branch is cut by
///    the image border, so an end pixel's own radius says little; ends are ranked by the mean
///    radius of their branch. Among the ends (degree-1 nodes) whose branch's mean radius is at
///    least half the component's largest, the lowest (largest y) is the trunk; ties go to the
///    larger mean radius, then the smaller x. A component without ends (a loop) takes its
///    lowest node (ties: larger radius, smaller x).
/// Node ids: junction clusters, ends and isolated pixels in raster order of their first pixel,
/// then loop nodes; branch ids in tracing order. Weights are 0 until weighed.
///
/// Preconditions: `skeleton` one pixel thin and 8-connected (other input is handled, e.g. blobs
/// become junction clusters, but the graph then says little); `dist2` the squared Euclidean
/// distance to the background (radius = √dist2 px).
/// Errors: view errors of either view, `size_mismatch`, `capacity_exceeded` when
/// `options.max_nodes` / `max_branches` are too small, `workspace_too_small` for a borrowed
/// workspace smaller than `skeleton_graph_workspace_bytes`.
/// Memory: the graph lives in `ws` (about 100 bytes per skeleton pixel); the scratch (about 40
/// bytes per skeleton pixel) is released before returning. No heap allocation once `ws` has
/// grown. Complexity: O(width × height / 32 + skeleton pixels).
/// Implements §"Section into Branches" and §"Create Graph" of the paper, with junction clusters
/// as single nodes and branches traced once (the paper's prototype doubled every length).
/// `within` (the overload that takes it): row runs that contain every skeleton pixel, so only
/// they are scanned for them: the runs of the mask the skeleton was thinned from, by a
/// skeletoniser whose skeleton lies inside its mask (every `RowRunSkeletoniser`'s does). Runs
/// of an image of another size are ignored (the skeleton is scanned); a skeleton pixel outside
/// them would be missed.
template <BinaryView Skeleton>
[[nodiscard]] result<skeleton_graph> build_skeleton_graph(const Skeleton& skeleton,
                                                          image_view<const std::uint32_t> dist2,
                                                          workspace& ws,
                                                          const graph_options& options,
                                                          const row_runs& within) noexcept {
  PERCH_TRY(validate_non_empty(skeleton));
  PERCH_TRY(validate_non_empty(dist2));
  PERCH_TRY(same_size(skeleton, dist2));
  const row_runs* runs = within.spans(skeleton) ? &within : nullptr;
  const std::size_t n = detail::count_set_pixels(skeleton, runs);
  // A skeleton has at most one node and one branch per pixel: a larger cap would only waste
  // memory (and a size query counts on these).
  const std::size_t node_cap = options.max_nodes != 0 ? std::min(options.max_nodes, n) : n;
  const std::size_t edge_cap = options.max_branches != 0 ? std::min(options.max_branches, n) : n;

  skeleton_graph out;
  using access = detail::skeleton_graph_access;
  auto topology = skeleton_graph::topology_type::make(ws, node_cap, edge_cap);
  PERCH_TRY(all_ok(topology));
  access::topology(out) = std::move(*topology);
  for (int pool = 0; pool < 2; ++pool) {
    auto points = ws.allocate<pixel>(n);
    PERCH_TRY(all_ok(points));
    auto radii = ws.allocate<float>(n);
    PERCH_TRY(all_ok(radii));
    access::points(out, pool) = *points;
    access::radii(out, pool) = *radii;
  }
  auto trunks = ws.allocate<node_id>(node_cap);
  PERCH_TRY(all_ok(trunks));
  access::trunks(out) = *trunks;
  access::skeleton_pixels(out) = n;
  const workspace::checkpoint scratch = ws.mark();
  const status traced = detail::trace_skeleton(skeleton, dist2, runs, out, ws);
  ws.rewind(scratch);
  PERCH_TRY(all_ok(traced));
  return result<skeleton_graph>(std::move(out));
}

/// `build_skeleton_graph` scanning the whole skeleton for its pixels.
template <BinaryView Skeleton>
[[nodiscard]] result<skeleton_graph> build_skeleton_graph(const Skeleton& skeleton,
                                                          image_view<const std::uint32_t> dist2,
                                                          workspace& ws,
                                                          const graph_options& options = {}) noexcept {
  return build_skeleton_graph(skeleton, dist2, ws, options, row_runs{});
}

}  // namespace perch
