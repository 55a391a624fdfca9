// SPDX-License-Identifier: BSL-1.0
/// \file
/// Branch weighting (paper eq. 1) and iterative pruning of a skeleton graph (paper §"Prune
/// Graph"), with the tip-spur rule that removes the medial axis's forks at round branch tips
/// whatever the image scale.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

#include "perch/core/mask.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/adjacency_list.hpp"
#include "perch/graph/detail/records.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

/// Weighting and pruning parameters (defaults: the paper's α 0.6, W 0.4, 50 mm, and the
/// tendon-driven claw's 30–110 mm diameter range of Li et al. 2025).
struct prune_options {
  float alpha = 0.6f;             ///< eq. 1 length-to-width bias α ∈ [0, 1]
  float weight_threshold = 0.4f;  ///< leaf edges lighter than this ...
  float max_length_mm = 50.0f;    ///< ... and shorter than this are removed
  float diameter_min_mm = 30.0f;  ///< eq. 1 spec range of diameters (δ_i)
  float diameter_max_mm = 110.0f;
  /// Leaf edges with length ≤ factor·r + tip_spur_px are spurs (r = radius of the node they hang
  /// from), at any scale: the medial axis forks at round tips (spurs of about r) and reaches
  /// every bump of a rough outline along the bump's bisector, about 45° to the axis (spurs of
  /// √2·r plus the bump). A smaller factor lets spurs survive that cut limbs into pieces
  /// shorter than a window; 1.8 is the smallest that scored best on the synthetic population
  /// (docs/accuracy-log.md).
  float tip_spur_factor = 1.8f;
  float tip_spur_px = 2.0f;

  /// `invalid_parameter` for NaN, infinite or negative values or α > 1; `range_inverted` for
  /// diameter_min_mm > diameter_max_mm.
  [[nodiscard]] status validate() const noexcept {
    for (const float v : {alpha, weight_threshold, max_length_mm, diameter_min_mm,
                          diameter_max_mm, tip_spur_factor, tip_spur_px})
      if (!(std::isfinite(v) && v >= 0.0f)) return fail(errc::invalid_parameter, "prune_options");
    if (alpha > 1.0f) return fail(errc::invalid_parameter, "prune_options.alpha");
    if (diameter_min_mm > diameter_max_mm)
      return fail(errc::range_inverted, "prune_options.diameter_min_mm");
    return {};
  }
};

/// What `prune_skeleton_graph` did.
struct prune_report {
  std::uint32_t tip_spurs_removed = 0;    ///< leaf edges removed by the tip-spur rule
  std::uint32_t weak_leaves_removed = 0;  ///< leaf edges removed by weight and length (eq. 1)
  /// Leaf edges left that are light and short enough to be weak but run out of the image.
  std::uint32_t cut_leaves_kept = 0;
  std::uint32_t nodes_removed = 0;        ///< tip nodes left without an edge, removed
  std::uint32_t nodes_merged = 0;         ///< degree-2 nodes joined away
  std::uint32_t passes = 0;               ///< rounds until nothing changed
  std::size_t branches_before = 0;
  std::size_t branches_after = 0;
};

namespace detail {

[[nodiscard]] inline status validate_mm_per_px(float mm_per_px) noexcept {
  if (!(std::isfinite(mm_per_px) && mm_per_px > 0.0f))
    return fail(errc::invalid_parameter, "mm_per_px");
  return {};
}

/// δ_i of eq. 1: is the diameter at radius `r` inside the spec range?
[[nodiscard]] inline bool in_spec_range(float r, float mm_per_px, const prune_options& o) noexcept {
  const float d_mm = diameter_from_radius(r) * mm_per_px;
  return d_mm >= o.diameter_min_mm && d_mm <= o.diameter_max_mm;
}

/// Counts each flat branch's in-spec points.
inline void count_in_spec(skeleton_graph& graph, float mm_per_px,
                          const prune_options& o) noexcept {
  using access = skeleton_graph_access;
  auto& g = access::topology(graph);
  const std::span<float> radii = access::radii(graph, access::active(graph));
  g.for_each_edge([&](edge_id e) {
    skeleton_edge_data& d = g.edge(e);
    std::uint32_t count = 0;
    for (std::size_t i = 0; i < d.line.count; ++i)
      count += in_spec_range(radii[d.line.offset + i], mm_per_px, o) ? 1u : 0u;
    d.in_range = count;
  });
}

/// Eq. 1 for every live edge from its aggregates; L_max and W_max over the whole graph.
inline void apply_weights(skeleton_graph::topology_type& g, float alpha) noexcept {
  float l_max = 0;
  float w_max = 0;
  g.for_each_edge([&](edge_id e) {
    const skeleton_edge_data& d = g.edge(e);
    const float w = d.pixel_total > 0 ? d.diameter_sum_px / static_cast<float>(d.pixel_total) : 0;
    if (d.length_px > l_max) l_max = d.length_px;
    if (w > w_max) w_max = w;
  });
  g.for_each_edge([&](edge_id e) {
    skeleton_edge_data& d = g.edge(e);
    const float n = static_cast<float>(d.pixel_total);
    const float w = d.pixel_total > 0 ? d.diameter_sum_px / n : 0;
    const float f_in = d.pixel_total > 0 ? static_cast<float>(d.in_range) / n : 0;
    const float length_term = l_max > 0 ? d.length_px / l_max : 0;
    const float width_term = w_max > 0 ? f_in * w / w_max : 0;
    d.weight = alpha * length_term + (1.0f - alpha) * width_term;
  });
}

/// Joins the two branches at a degree-2 node (`adjacency_list::merge_node`'s join): the new
/// branch is a rope over both polylines with the node's attachment pixel(s) between them, its
/// aggregates the sums of theirs.
struct branch_joiner {
  std::span<rope_node> ropes;
  std::size_t rope_count = 0;
  float mm_per_px = 1.0f;
  const prune_options* options = nullptr;

  void add_point(skeleton_edge_data& d, float r) const noexcept {
    ++d.pixel_total;
    d.diameter_sum_px += diameter_from_radius(r);
    d.in_range += in_spec_range(r, mm_per_px, *options) ? 1u : 0u;
  }

  skeleton_edge_data operator()(const edge_part<skeleton_edge_data>& first,
                                const skeleton_node_data&,
                                const edge_part<skeleton_edge_data>& second) noexcept {
    const skeleton_edge_data& a = first.data;
    const skeleton_edge_data& b = second.data;
    const branch_anchor a1 = first.direction == traversal::forward ? a.to_anchor : a.from_anchor;
    const branch_anchor a2 = second.direction == traversal::forward ? b.from_anchor : b.to_anchor;
    PERCH_ASSERT(rope_count < ropes.size(), "prune: rope table full");
    rope_node& r = ropes[rope_count];
    r.left = a.line;
    r.left_dir = first.direction;
    r.right = b.line;
    r.right_dir = second.direction;
    r.inner_count = 0;
    skeleton_edge_data out;
    out.line = polyline_ref{0, 0, static_cast<std::int32_t>(rope_count)};
    ++rope_count;
    out.pixel_total = a.pixel_total + b.pixel_total;
    out.in_range = a.in_range + b.in_range;
    out.diameter_sum_px = a.diameter_sum_px + b.diameter_sum_px;
    out.length_px = a.length_px + b.length_px;
    if (a1.valid != 0) {
      r.inner[r.inner_count++] = a1;
      add_point(out, a1.radius_px);
    }
    if (a2.valid != 0 && !(a1.valid != 0 && a1.position == a2.position)) {
      r.inner[r.inner_count++] = a2;
      add_point(out, a2.radius_px);
      if (a1.valid != 0) out.length_px += pixel_step_px(a1.position, a2.position);
    }
    out.from_anchor = first.direction == traversal::forward ? a.from_anchor : a.to_anchor;
    out.to_anchor = second.direction == traversal::forward ? b.to_anchor : b.from_anchor;
    out.component = a.component;
    return out;
  }
};

/// The leaf rules of `prune_skeleton_graph` on one graph: which leaves are spurs or weak, which
/// tips the frame cuts, and which leaf is where a branch goes on.
struct leaf_rules {
  const skeleton_graph::topology_type& g;
  const prune_options& options;
  float mm_per_px;
  pixel_box image;

  [[nodiscard]] bool is_trunk(node_id v) const noexcept { return g.node(v).trunk != 0; }

  /// Eq. 1's weak leaves: light and short.
  [[nodiscard]] bool light(const skeleton_edge_data& d) const noexcept {
    return d.weight < options.weight_threshold && d.length_px * mm_per_px < options.max_length_mm;
  }

  /// A tip on the image's edge: a leaf there is cut by the frame.
  [[nodiscard]] bool cut(node_id tip) const noexcept {
    const pixel p = g.node(tip).position;
    return !image.empty() && (p.x <= image.x_min + 1 || p.y <= image.y_min + 1 ||
                              p.x >= image.x_max - 1 || p.y >= image.y_max - 1);
  }

  /// Whether leaf edge `e` is where the branch at `stem` goes on: the longest leaf (ties: the
  /// lowest id; a leaf to the trunk node always wins) of a stem with at most one non-leaf
  /// edge. Removing it would cut the branch short (a round tip forks into two spurs; a spur
  /// near a tip sits beside the tip's segment).
  [[nodiscard]] bool continues_through(node_id stem, edge_id e) const noexcept {
    int non_leaf = 0;
    for (const edge_id f : g.incident_edges(stem)) {
      const node_id other = g.source(f) == stem ? g.target(f) : g.source(f);
      if (other == stem || g.degree(other) != 1) {
        ++non_leaf;
        continue;
      }
      if (f == e) continue;
      if (is_trunk(other)) return false;  // the branch goes on to the trunk
      const float lf = g.edge(f).length_px, le = g.edge(e).length_px;
      if (lf > le || (lf == le && f < e)) return false;  // a longer leaf goes on
    }
    return non_leaf <= 1;
  }
};

/// Step 2 of a pruning round: the leaf edges to remove, decided on this round's degrees and
/// weights, written to `removal`; returns their count.
inline std::size_t leaves_to_remove(const skeleton_graph::topology_type& g, const leaf_rules& rules,
                                    std::span<std::int32_t> removal,
                                    prune_report& report) noexcept {
  std::size_t count = 0;
  g.for_each_edge([&](edge_id e) {
    const node_id a = g.source(e);
    const node_id b = g.target(e);
    if (a == b) return;
    const bool leaf_a = g.degree(a) == 1;
    const bool leaf_b = g.degree(b) == 1;
    if ((!leaf_a && !leaf_b) || rules.is_trunk(a) || rules.is_trunk(b)) return;
    const skeleton_edge_data& d = g.edge(e);
    const node_id stem = leaf_a ? b : a;
    const float r = g.node(stem).radius_px;
    const bool spur =
        d.length_px <= rules.options.tip_spur_factor * r + rules.options.tip_spur_px;
    const bool weak = rules.light(d) && !rules.cut(leaf_a ? a : b);
    if ((spur || weak) && rules.continues_through(stem, e)) return;
    if (spur) ++report.tip_spurs_removed;
    else if (weak) ++report.weak_leaves_removed;
    if (spur || weak) removal[count++] = e;
  });
  return count;
}

/// Removes the edges `removal` and the nodes they leave without an edge.
inline void remove_leaves(skeleton_graph::topology_type& g, std::span<const std::int32_t> removal,
                          prune_report& report) noexcept {
  for (const edge_id e : removal) {
    const node_id a = g.source(e);
    const node_id b = g.target(e);
    g.remove_edge(e);
    for (const node_id v : {a, b})
      if (g.contains_node(v) && g.degree(v) == 0) {
        g.remove_node(v);
        ++report.nodes_removed;
      }
  }
}

/// Step 3 of a pruning round: joins the two branches of every node of degree 2 but the trunk
/// nodes and loops; returns how many were joined.
inline std::uint32_t merge_degree_two_nodes(skeleton_graph::topology_type& g,
                                            const leaf_rules& rules,
                                            branch_joiner& join) noexcept {
  std::uint32_t merged = 0;
  const node_id node_end = g.node_id_end();
  for (node_id v = 0; v < node_end; ++v) {
    if (!g.contains_node(v) || g.degree(v) != 2 || rules.is_trunk(v)) continue;
    auto it = g.incident_edges(v).begin();
    const edge_id e1 = *it;
    ++it;
    if (*it == e1) continue;  // a loop
    auto joined = g.merge_node(v, join);
    PERCH_ASSERT(joined.has_value(), "prune: merge of a degree-2 node failed");
    (void)joined;
    ++merged;
  }
  return merged;
}

/// Leaf edges left that would be weak but for a tip the frame cuts.
inline std::uint32_t count_cut_leaves_kept(const skeleton_graph::topology_type& g,
                                           const leaf_rules& rules) noexcept {
  std::uint32_t kept = 0;
  g.for_each_edge([&](edge_id e) {
    const node_id a = g.source(e), b = g.target(e);
    const node_id tip = g.degree(a) == 1 ? a : b;
    if (a != b && g.degree(tip) == 1 && !rules.is_trunk(a) && !rules.is_trunk(b) &&
        rules.light(g.edge(e)) && rules.cut(tip))
      ++kept;
  });
  return kept;
}

/// Writes every live polyline, joined ones walked through their ropes depth first, flat into
/// the graph's other pool, which becomes the active one (the pools swap roles). `stack`:
/// scratch for the rope walk (3 entries per rope + 4).
inline void flatten_ropes(skeleton_graph& graph, std::span<const rope_node> ropes,
                          std::span<rope_item> stack) noexcept {
  using access = skeleton_graph_access;
  auto& g = access::topology(graph);
  const int src = access::active(graph);
  const int dst = 1 - src;
  const std::span<pixel> from_pts = access::points(graph, src);
  const std::span<float> from_rad = access::radii(graph, src);
  const std::span<pixel> to_pts = access::points(graph, dst);
  const std::span<float> to_rad = access::radii(graph, dst);
  std::size_t cursor = 0;
  g.for_each_edge([&](edge_id e) {
    skeleton_edge_data& d = g.edge(e);
    const std::size_t first = cursor;
    std::size_t top = 0;
    stack[top++] = rope_item{d.line, branch_anchor{}, traversal::forward, 0};
    while (top > 0) {
      const rope_item item = stack[--top];
      if (item.is_anchor != 0) {
        PERCH_ASSERT(cursor < to_pts.size(), "prune: pool overflow");
        to_pts[cursor] = item.point.position;
        to_rad[cursor] = item.point.radius_px;
        ++cursor;
      } else if (item.ref.rope < 0) {
        PERCH_ASSERT(cursor + item.ref.count <= to_pts.size(), "prune: pool overflow");
        for (std::size_t i = 0; i < item.ref.count; ++i) {
          const std::size_t j = item.dir == traversal::forward
                                    ? item.ref.offset + i
                                    : item.ref.offset + item.ref.count - 1 - i;
          to_pts[cursor] = from_pts[j];
          to_rad[cursor] = from_rad[j];
          ++cursor;
        }
      } else {
        const rope_node& r = ropes[static_cast<std::size_t>(item.ref.rope)];
        // Emission order forward: left, inner[0], inner[1], right; pushed in reverse.
        rope_item seq[4];
        std::size_t m = 0;
        seq[m++] = rope_item{r.left, branch_anchor{}, r.left_dir, 0};
        for (std::size_t i = 0; i < r.inner_count; ++i)
          seq[m++] = rope_item{polyline_ref{}, r.inner[i], traversal::forward, 1};
        seq[m++] = rope_item{r.right, branch_anchor{}, r.right_dir, 0};
        if (item.dir == traversal::backward) {
          for (std::size_t i = 0; i < m / 2; ++i) std::swap(seq[i], seq[m - 1 - i]);
          for (std::size_t i = 0; i < m; ++i) seq[i].dir = reversed(seq[i].dir);
        }
        PERCH_ASSERT(top + m <= stack.size(), "prune: rope stack overflow");
        for (std::size_t i = m; i-- > 0;) stack[top++] = seq[i];
      }
    }
    d.line = polyline_ref{static_cast<std::uint32_t>(first),
                          static_cast<std::uint32_t>(cursor - first), -1};
  });
  access::active(graph) = dst;
}

}  // namespace detail

/// Sets every branch's `weight` by paper eq. 1:
/// `W = α·l/L_max + (1 − α)·f_in·w̄/W_max`, where l is the branch length, w̄ its mean diameter
/// (2·r − 1 per point), f_in the share of its points whose diameter in mm (× `mm_per_px`) lies
/// in [diameter_min_mm, diameter_max_mm], L_max the longest branch and W_max the largest mean
/// diameter over the whole graph (all components). Both ratios are scale-free.
/// Errors: `invalid_parameter` / `range_inverted` for bad options or scale. O(points).
[[nodiscard]] inline status weigh_skeleton_graph(skeleton_graph& graph, float mm_per_px,
                                                 const prune_options& options = {}) noexcept {
  PERCH_TRY(options.validate());
  PERCH_TRY(detail::validate_mm_per_px(mm_per_px));
  detail::count_in_spec(graph, mm_per_px, options);
  detail::apply_weights(detail::skeleton_graph_access::topology(graph), options.alpha);
  return {};
}

/// Prunes `graph` in place, repeating until a round changes nothing:
/// 1. weigh every branch (eq. 1, see `weigh_skeleton_graph`);
/// 2. remove every leaf edge (one end of degree 1, not a self-loop) that is
///    - a tip spur: `length_px ≤ tip_spur_factor · r + tip_spur_px`, r the radius of the node
///      at its other end (the medial axis forks at every round tip; this rule holds at any
///      scale, issue "tip spurs go regardless of scale"), or
///    - weak: `W < weight_threshold` and `length_px · mm_per_px < max_length_mm` (the paper),
///      unless its tip lies on the edge of `image` (within 1 px): a limb cut by the frame is
///      longer than the part in view, so its length cannot tell a twig from a limb (a short
///      leaf there is a limb leaving the picture, and the junction it makes stays);
///    except the longest leaf at a node with at most one other non-leaf edge, where the branch
///    goes on (it joins the branch in step 3); and remove the tip nodes left without an edge;
/// 3. merge every node of degree 2 (two distinct edges) by joining its two branches: the
///    polylines are concatenated in walking order with the node's attachment pixel(s) between
///    them, lengths and diameter sums add up.
/// Never removed or merged: the trunk node of each component and the edge(s) at it (the
/// trunk path), so every component keeps its trunk; loops are kept (a self-loop is no leaf).
/// Finally branches are weighed again and every joined polyline is written out flat into the
/// graph's second pool, so `skeleton_branch::points` stay contiguous spans.
/// `image`: the image's extent in the graph's coordinates (`find_perch`: the analysed frame
/// relative to the tree's box); empty (the default) when unknown: no leaf counts as cut.
/// Errors: `invalid_parameter` / `range_inverted` for bad options or scale (graph untouched);
/// `workspace_too_small` for a borrowed workspace (graph untouched).
/// Memory: scratch from `ws` (released before returning); no heap allocation once `ws` has
/// grown. Complexity: O(passes × (nodes + branches) + points); passes are few on real trees.
/// Implements §"Calculate Weightings" (eq. 1) and §"Prune Graph" of the paper.
[[nodiscard]] inline result<prune_report> prune_skeleton_graph(
    skeleton_graph& graph, float mm_per_px, workspace& ws, const prune_options& options = {},
    const pixel_box& image = {}) noexcept {
  using namespace detail;
  using access = skeleton_graph_access;
  PERCH_TRY(options.validate());
  PERCH_TRY(validate_mm_per_px(mm_per_px));
  auto& g = access::topology(graph);
  prune_report report;
  report.branches_before = g.edge_count();

  const workspace::checkpoint scratch = ws.mark();
  const std::size_t rope_cap = g.node_count();
  auto ropes = ws.allocate<rope_node>(rope_cap);
  auto removal = ws.allocate<std::int32_t>(g.edge_count());
  auto stack = ws.allocate<rope_item>(3 * rope_cap + 4);
  if (auto ok = all_ok(ropes, removal, stack); !ok) {
    ws.rewind(scratch);
    return unexpected{ok.error()};
  }

  count_in_spec(graph, mm_per_px, options);
  const leaf_rules rules{g, options, mm_per_px, image};
  branch_joiner join{*ropes, 0, mm_per_px, &options};
  for (;;) {
    ++report.passes;
    apply_weights(g, options.alpha);
    const std::size_t count = leaves_to_remove(g, rules, *removal, report);
    remove_leaves(g, removal->first(count), report);
    const std::uint32_t merged = merge_degree_two_nodes(g, rules, join);
    report.nodes_merged += merged;
    if (count == 0 && merged == 0) break;
  }
  apply_weights(g, options.alpha);
  report.cut_leaves_kept = count_cut_leaves_kept(g, rules);
  if (join.rope_count > 0) flatten_ropes(graph, ropes->first(join.rope_count), *stack);
  ws.rewind(scratch);
  report.branches_after = g.edge_count();
  return report;
}

}  // namespace perch
