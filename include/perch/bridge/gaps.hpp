// SPDX-License-Identifier: BSL-1.0
/// \file
/// Stage "bridges" (issue 24, rule 7): small gaps a segmenter left in the tree, closed in
/// perch's own copy of the mask before it is analysed. A segmenter breaks a limb with a gap of
/// a few pixels (a leaf in front of it, a thin stretch lost) or cuts a child limb off its
/// parent at the junction. The piece beyond such a gap looks detached (`supported` refuses
/// it), and a parent whose child lost its base shows no junction there, so a window may sit
/// right beside the child. The skeleton graph shows each break as an end of a limb:
/// `find_gap_bridges` reads each end's axis off the graph and bridges it to the piece of mask
/// it faces across a small gap, end to end (two aligned ends of one limb, of similar width) or
/// end to body (an end pointing at the side of another limb: the junction it was cut from);
/// `draw_gap_bridges` draws each bridge into the mask as a capsule of the ends' radii.
///
/// Conservative by construction: a bridge only joins two pieces of mask that are apart (it
/// never closes a loop), and `find_perch` lets no window run across one (`on_gap_bridge`), so
/// a bridge can make a piece count as supported, or show a junction and an obstacle, but never
/// adds a stretch of limb to perch on.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>
#include <string_view>

#include "perch/core/bounded_vector.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/mask.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/union_find.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/detail/records.hpp"
#include "perch/graph/limbs.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

/// Which gaps `find_perch` bridges (`perch_options::bridging`). Lengths are in input pixels: a
/// segmenter's gaps are a matter of its pixels, not of the tree's millimetres. Whether two ends
/// are one limb (how far each may point off the line to the other, how alike their widths
/// are) is the rule by which a limb runs on through a junction (`limb_options`), written once
/// there.
struct bridge_options {
  /// Bridge at all; false takes every piece of mask as it is.
  bool enabled = true;
  /// The widest gap bridged, between the two outlines along the bridge ...
  float max_gap_px = 6.0f;
  /// ... and at most this many diameters of the end (the thinner end, end to end): across a
  /// gap no wider than the limb, its two ends are plainly one limb.
  float max_gap_diameters = 1.0f;
  /// The most bridges drawn, the shortest gaps first (their memory is taken before the mask is
  /// analysed).
  std::uint32_t max_bridges = 64;

  [[nodiscard]] status validate() const noexcept {
    if (!(max_gap_px >= 0 && max_gap_px <= 1e4f) ||
        !(max_gap_diameters >= 0 && max_gap_diameters <= 1e4f))
      return fail(errc::invalid_parameter, "perch_options.bridging");
    return {};
  }
};

/// What a bridge joins.
enum class bridge_kind : std::uint8_t {
  end_to_end,   ///< two aligned ends of one limb, of similar width
  end_to_body,  ///< an end to the side of another limb (the junction it was cut from)
};

[[nodiscard]] constexpr std::string_view to_string(bridge_kind k) noexcept {
  return k == bridge_kind::end_to_end ? "end-to-end" : "end-to-body";
}

/// A bridge across a gap, in the coordinates of the mask it was found in: a capsule from
/// `from` (radius `from_radius_px`) to `to` (radius `to_radius_px`).
struct gap_bridge {
  point2f from{0, 0};  ///< where the end's piece of mask stops, on the bridge's line
  point2f to{0, 0};    ///< where the line meets the other piece: the other end or the body
  float from_radius_px = 0;
  float to_radius_px = 0;
  float gap_px = 0;  ///< background crossed between the two outlines along the bridge
  bridge_kind kind = bridge_kind::end_to_end;
};

/// The end of a limb at an end node of the skeleton graph, as a bridge sees it.
struct limb_end {
  point2f tip{0, 0};      ///< the end's pixel moved onto the fitted axis: where the limb stops
  point2f outward{0, 0};  ///< unit direction out of the limb
  float radius_px = 0;    ///< mean distance-map radius over the fit
  std::int32_t piece = -1;  ///< its piece of mask (`mask_pieces`)
  bool valid = false;
};

/// The pieces (8-connected components) of a mask, from its row runs: a union-find over the
/// runs, in which the runs of adjacent rows that touch are one set.
class mask_pieces {
 public:
  /// The pieces of the mask `runs` describe. Memory: one `int32` per run from `ws`.
  [[nodiscard]] static result<mask_pieces> find(const row_runs& runs, int height,
                                                workspace& ws) noexcept {
    mask_pieces out;
    out.runs_ = &runs;
    out.height_ = height;
    const std::size_t n = runs.size();
    auto parent = ws.allocate<std::int32_t>(std::max<std::size_t>(n, 1));
    PERCH_TRY(all_ok(parent));
    out.sets_ = detail::union_find{parent->data(), 0, static_cast<std::int32_t>(parent->size()) - 1};
    out.sets_.make_singletons(static_cast<std::int32_t>(n));
    for (int y = 1; y < height; ++y) out.join_rows(y);
    return out;
  }

  /// The piece of tree pixel `p` (the root of its run's set); -1 for a background pixel.
  [[nodiscard]] std::int32_t at(pixel p) const noexcept {
    if (p.y < 0 || p.y >= height_) return -1;
    const std::span<const row_run> row = runs_->row(p.y);
    const row_run* after = std::upper_bound(row.data(), row.data() + row.size(), p.x,
                                            [](int x, const row_run& r) { return x < r.begin; });
    if (after == row.data() || (after - 1)->end <= p.x) return -1;
    return sets_.find(static_cast<std::int32_t>((after - 1) - runs_->row(0).data()));
  }

  /// Joins the pieces of `a` and `b` into one (a bridge between them).
  void join(std::int32_t a, std::int32_t b) noexcept { sets_.merge(a, b); }
  /// Whether `a` and `b` are one piece.
  [[nodiscard]] bool joined(std::int32_t a, std::int32_t b) const noexcept {
    return sets_.find(a) == sets_.find(b);
  }

 private:
  /// Merges every run of row `y` with the runs of row `y − 1` it touches (8-connected:
  /// overlapping or meeting at a corner).
  void join_rows(int y) noexcept {
    const std::span<const row_run> above = runs_->row(y - 1);
    const std::span<const row_run> here = runs_->row(y);
    const row_run* first = runs_->row(0).data();
    std::size_t i = 0, j = 0;
    while (i < above.size() && j < here.size()) {
      const row_run a = above[i], b = here[j];
      if (a.begin <= b.end && b.begin <= a.end)
        sets_.merge(static_cast<std::int32_t>(&above[i] - first),
                    static_cast<std::int32_t>(&here[j] - first));
      if (a.end < b.end) ++i; else ++j;
    }
  }

  const row_runs* runs_ = nullptr;
  int height_ = 0;
  detail::union_find sets_{};
};

namespace detail {

/// Samples a bridge's line every this many pixels.
inline constexpr float bridge_step_px = 0.5f;

/// The points of the branch at end node `n`, walked from the end: `at(k)`, `radius(k)`.
struct end_walk {
  skeleton_branch branch;
  bool from_end = true;  ///< the end is the branch's `from` node (index 0)
  [[nodiscard]] std::size_t size() const noexcept { return branch.points.size(); }
  [[nodiscard]] std::size_t index(std::size_t k) const noexcept {
    return from_end ? k : branch.points.size() - 1 - k;
  }
  [[nodiscard]] pixel at(std::size_t k) const noexcept { return branch.points[index(k)]; }
  [[nodiscard]] float radius(std::size_t k) const noexcept { return branch.radius_px[index(k)]; }
};

/// A least-squares line through points (the principal axis of their scatter), summed one at a
/// time.
struct line_fit {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  void add(pixel p) noexcept {
    const double x = p.x, y = p.y;
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  [[nodiscard]] point2f centroid() const noexcept {
    return {static_cast<float>(sx / n), static_cast<float>(sy / n)};
  }
  /// The unit direction of the largest spread (`principal_axis`); zero when the points do not
  /// spread.
  [[nodiscard]] point2f direction() const noexcept {
    return principal_axis(sxx / n - (sx / n) * (sx / n), sxy / n - (sx / n) * (sy / n),
                          syy / n - (sy / n) * (sy / n));
  }
};

/// Cross product (signed area) of two vectors.
[[nodiscard]] inline float cross(point2f a, point2f b) noexcept {
  return a.x() * b.y() - a.y() * b.x();
}

/// The pixel a point lies in.
[[nodiscard]] inline pixel pixel_at(point2f p) noexcept {
  return {static_cast<std::int32_t>(std::lround(p.x())), static_cast<std::int32_t>(std::lround(p.y()))};
}

/// Whether pixel `p` of `mask` is tree (outside it: background).
[[nodiscard]] inline bool tree_at(image_view<const std::uint8_t> mask, pixel p) noexcept {
  return p.x >= 0 && p.y >= 0 && p.x < mask.width() && p.y < mask.height() && mask(p.x, p.y) != 0;
}

/// Distance from `p` to the segment `a`–`b`, and where along it (0 at `a`, 1 at `b`).
[[nodiscard]] inline float segment_distance(point2f p, point2f a, point2f b, float& t) noexcept {
  const float dx = b.x() - a.x(), dy = b.y() - a.y();
  const float length2 = dx * dx + dy * dy;
  t = length2 > 0 ? std::clamp(((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / length2, 0.0f, 1.0f)
                  : 0.0f;
  const float ex = p.x() - (a.x() + t * dx), ey = p.y() - (a.y() + t * dy);
  return std::sqrt(ex * ex + ey * ey);
}

}  // namespace detail

/// The end of the limb at end node `n` of `graph` (degree 1): its axis from a least-squares
/// line through the centreline between 1.5 and 3.5 radii (+ 2 px) from the end, beyond the
/// tip's cap, where the medial axis bends to a round tip's centre or a cut's corner; its
/// radius the mean over those points. Not `valid` when the branch is too short for that (a
/// stub no longer than its own width has no direction), or bends there by more than a straight
/// line's tolerance (`detail::straight_tolerance_px` + 10 % of the fit's length).
[[nodiscard]] inline limb_end end_of_limb(const skeleton_graph& graph, node_id n) noexcept {
  limb_end out;
  if (graph.topology().degree(n) != 1) return out;
  detail::end_walk walk{graph.branch(*graph.topology().incident_edges(n).begin()), true};
  walk.from_end = walk.branch.from == n;
  const std::size_t count = walk.size();
  if (count < 3) return out;
  // The cap: the largest radius within two of it (+ 2 px) of the end.
  float cap = walk.radius(0);
  float arc = 0;
  for (std::size_t k = 1; k < count; ++k) {
    arc += detail::pixel_step_px(walk.at(k), walk.at(k - 1));
    if (arc > 2.0f * cap + 2.0f) break;
    cap = std::max(cap, walk.radius(k));
  }
  const float near = 1.5f * cap, far = 3.5f * cap + 2.0f;
  detail::line_fit fit;
  float radius_sum = 0, first_arc = -1, last_arc = 0;
  arc = 0;
  for (std::size_t k = 0; k < count; ++k) {
    if (k > 0) arc += detail::pixel_step_px(walk.at(k), walk.at(k - 1));
    if (arc > far) break;
    if (arc < near) continue;
    fit.add(walk.at(k));
    radius_sum += walk.radius(k);
    if (first_arc < 0) first_arc = arc;
    last_arc = arc;
  }
  const float span = last_arc - first_arc;
  if (fit.n < 3 || !(span >= std::max(cap, 2.0f))) return out;
  const point2f centre = fit.centroid();
  point2f u = fit.direction();
  if (u.x() == 0 && u.y() == 0) return out;
  const point2f end = to_point(walk.at(0));
  if ((end - centre).dot(u) < 0) u = -u;
  // Straight over the fit: every point within a digital line's tolerance of the axis.
  const float tolerance = detail::straight_tolerance_px + 0.1f * span;
  arc = 0;
  for (std::size_t k = 0; k < count; ++k) {
    if (k > 0) arc += detail::pixel_step_px(walk.at(k), walk.at(k - 1));
    if (arc > far) break;
    if (arc >= near && std::abs(detail::cross(u, to_point(walk.at(k)) - centre)) > tolerance)
      return out;
  }
  out.tip = centre + u * u.dot(end - centre);
  out.outward = u;
  out.radius_px = radius_sum / static_cast<float>(fit.n);
  out.valid = true;
  return out;
}

namespace detail {

/// A bridge found but not yet chosen: between ends `a` and `b` (b < 0: end to body).
struct bridge_candidate {
  gap_bridge bridge;
  std::int32_t a = -1, b = -1;
  std::int32_t piece_a = -1, piece_b = -1;
};

/// The search's rules in the analysed mask's pixels.
struct gap_rules {
  float max_gap_px = 0;
  float max_gap_diameters = 0;
  float tan_turn = 0;  ///< tan of `limb_options::max_turn_deg`
  float thickness_ratio_min = 0;

  /// The widest gap an end of radius `r` may bridge.
  [[nodiscard]] float widest_gap(float r) const noexcept {
    return std::min(max_gap_px, max_gap_diameters * diameter_from_radius(r));
  }
  /// Whether `from`'s axis points at `to`: `to` within the turn angle of it, give or take the
  /// outline's pixel.
  [[nodiscard]] bool faces(const limb_end& from, point2f to) const noexcept {
    const point2f v = to - from.tip;
    const float along = from.outward.dot(v);
    return along > 0 && std::abs(cross(from.outward, v)) <= along * tan_turn + outline_uncertainty_px;
  }
  /// Whether a limb of radius `thin` may be one with (or grow from) one of radius `thick`.
  [[nodiscard]] bool alike(float thin, float thick) const noexcept {
    return thin >= thickness_ratio_min * thick;
  }
};

/// Where a line leaves one piece of mask and meets another, and the background between.
struct gap_crossing {
  point2f leaves{0, 0};  ///< the line's last point on the first piece
  point2f meets{0, 0};   ///< its first point on the other
  float gap_px = 0;      ///< background between them along the line
  bool found = false;
};

/// The crossing of the gap between `a`'s piece and `b`'s along the line from tip `a` to tip
/// `b`, the line carried on `reach_a` back into `a`'s piece and `reach_b` into `b`'s (a tip
/// may lie at or past its outline). Not `found` when the line runs through a third piece or
/// never meets `b`'s.
[[nodiscard]] inline gap_crossing gap_along(image_view<const std::uint8_t> mask,
                                            const mask_pieces& pieces, point2f tip_a,
                                            point2f tip_b, float reach_a, float reach_b,
                                            std::int32_t piece_a, std::int32_t piece_b) noexcept {
  gap_crossing out;
  const point2f u = (tip_b - tip_a).normalized();
  const point2f a = tip_a - u * reach_a;
  const point2f v = tip_b + u * reach_b - a;
  const int steps = std::max(1, static_cast<int>(std::ceil(v.norm() / bridge_step_px)));
  const float step = v.norm() / static_cast<float>(steps);
  out.leaves = a;
  for (int i = 0; i <= steps; ++i) {
    const point2f q = a + v * (static_cast<float>(i) / static_cast<float>(steps));
    const pixel p = pixel_at(q);
    if (!tree_at(mask, p)) {
      out.gap_px += step;
      continue;
    }
    const std::int32_t piece = pieces.at(p);
    if (pieces.joined(piece, piece_b)) {
      out.meets = q;
      out.found = true;
      return out;
    }
    if (!pieces.joined(piece, piece_a)) return out;
    out.leaves = q;
    out.gap_px = 0;
  }
  return out;
}

/// Where the axis of end `e` meets the side of another piece of mask across a gap the rules
/// allow, as a bridge from the end to there; `kind` stays end to end when there is none. The
/// axis meeting the tip of another end that faces this one (one of `ends`) is no side: such
/// ends are bridged end to end or not at all.
[[nodiscard]] inline bridge_candidate axis_to_body(image_view<const std::uint8_t> mask,
                                                   image_view<const std::uint32_t> dist2,
                                                   const mask_pieces& pieces, const limb_end& e,
                                                   std::span<const limb_end> ends,
                                                   const gap_rules& rules) noexcept {
  bridge_candidate out;
  const float widest = rules.widest_gap(e.radius_px);
  // From a radius back inside the end's piece (a cut across a leaning limb leaves the tip,
  // the end pixel carried onto the axis, at or past the outline), out of it, across the gap.
  const point2f start = e.tip - e.outward * e.radius_px;
  auto at = [&](float t) { return pixel_at(start + e.outward * t); };
  auto own = [&](pixel p) { return tree_at(mask, p) && pieces.joined(pieces.at(p), e.piece); };
  float t = 0;
  const float own_reach = 2.0f * e.radius_px + outline_uncertainty_px;
  while (t <= own_reach && own(at(t))) t += bridge_step_px;
  if (t > own_reach || t == 0) return out;
  const point2f leaves = start + e.outward * (t - bridge_step_px);
  float gap = 0;
  while (!tree_at(mask, at(t))) {
    gap += bridge_step_px;
    t += bridge_step_px;
    if (gap > widest + bridge_step_px) return out;
  }
  const point2f hit = start + e.outward * t;
  const std::int32_t body = pieces.at(pixel_at(hit));
  if (body < 0 || pieces.joined(body, e.piece)) return out;
  for (const limb_end& other : ends)
    if (pieces.joined(other.piece, body) && rules.faces(other, e.tip) &&
        (hit - other.tip).norm() <= other.radius_px + outline_uncertainty_px)
      return out;
  // The body at least about as thick as the end (a child is no thicker than its parent): its
  // distance map along the axis, into the body, reaches that share of the end's radius.
  const float needed = rules.thickness_ratio_min * e.radius_px;
  float deepest = 0;
  for (float depth = 0; depth <= 4.0f * e.radius_px + 2.0f && deepest < needed;
       depth += bridge_step_px) {
    const pixel p = pixel_at(hit + e.outward * depth);
    if (!tree_at(mask, p)) break;
    deepest = std::max(deepest, std::sqrt(static_cast<float>(dist2(p.x, p.y))));
  }
  if (deepest < needed) return out;
  out.bridge = gap_bridge{leaves, hit, e.radius_px, e.radius_px, gap, bridge_kind::end_to_body};
  out.piece_a = e.piece;
  out.piece_b = body;
  return out;
}

}  // namespace detail

/// Bytes of workspace `find_gap_bridges` takes at most for a graph of `nodes` nodes and a mask
/// of `runs` runs (released when it returns).
[[nodiscard]] constexpr std::size_t gap_bridge_search_bytes(std::size_t nodes, std::size_t runs) noexcept {
  return workspace::footprint<std::int32_t>(runs > 1 ? runs : 1) +
         workspace::footprint<limb_end>(nodes) + workspace::footprint<std::int32_t>(nodes) +
         workspace::footprint<detail::bridge_candidate>(2 * nodes) +
         workspace::footprint<std::uint8_t>(nodes);
}

namespace detail {

/// One `find_gap_bridges` search: the mask, its pieces and the rules; the ends found and the
/// candidate bridges between them, in workspace spans.
struct bridge_search {
  image_view<const std::uint8_t> mask;
  image_view<const std::uint32_t> dist2;
  mask_pieces& pieces;
  gap_rules rules;
  std::span<limb_end> ends;  ///< the first `end_count` hold the graph's readable ends
  std::span<bridge_candidate> candidates;  ///< the first `count` are found
  std::size_t end_count = 0;
  std::size_t count = 0;

  void add(const bridge_candidate& c) noexcept {
    if (count < candidates.size()) candidates[count++] = c;
  }

  /// Every end node of `graph` whose axis can be read, with its piece.
  void collect_ends(const skeleton_graph& graph) noexcept {
    graph.for_each_node([&](const skeleton_node& node) {
      if (node.kind != node_kind::end || end_count == ends.size()) return;
      limb_end e = end_of_limb(graph, node.id);
      e.piece = pieces.at(node.position);
      if (e.valid && e.piece >= 0) ends[end_count++] = e;
    });
  }

  /// End to end: the pairs of ends on different pieces that face each other, alike, across a
  /// gap the rules allow. The ends are visited sorted by x (`order`: scratch, one per end), each
  /// against those within reach: a tip lies up to its radius inside its outline (a round tip's
  /// axis ends at the cap's centre).
  void add_end_to_end(std::span<std::int32_t> order) noexcept {
    float widest = 0;
    for (std::size_t i = 0; i < end_count; ++i) {
      order[i] = static_cast<std::int32_t>(i);
      widest = std::max(widest, ends[i].radius_px);
    }
    const auto end_at = [&](std::size_t k) -> const limb_end& {
      return ends[static_cast<std::size_t>(order[k])];
    };
    std::sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(end_count),
              [&](std::int32_t a, std::int32_t b) {
                const float xa = ends[static_cast<std::size_t>(a)].tip.x();
                const float xb = ends[static_cast<std::size_t>(b)].tip.x();
                return xa < xb || (xa == xb && a < b);
              });
    const auto reach = [&](float ra, float rb) {
      return rules.max_gap_px + ra + rb + 2.0f * outline_uncertainty_px;
    };
    for (std::size_t i = 0; i < end_count; ++i) {
      const limb_end& a = end_at(i);
      for (std::size_t j = i + 1; j < end_count; ++j) {
        const limb_end& b = end_at(j);
        if (b.tip.x() - a.tip.x() > reach(a.radius_px, widest)) break;
        if ((b.tip - a.tip).norm() > reach(a.radius_px, b.radius_px)) continue;
        const gap_crossing gap = end_to_end(a, b);
        if (gap.found)
          add({gap_bridge{gap.leaves, gap.meets, a.radius_px, b.radius_px, gap.gap_px,
                          bridge_kind::end_to_end},
               order[i], order[j], a.piece, b.piece});
      }
    }
  }

  /// The gap between ends `a` and `b` when they may be bridged end to end (else not `found`).
  [[nodiscard]] gap_crossing end_to_end(const limb_end& a, const limb_end& b) const noexcept {
    const float thin = std::min(a.radius_px, b.radius_px);
    if (pieces.joined(a.piece, b.piece) || !rules.faces(a, b.tip) || !rules.faces(b, a.tip) ||
        !rules.alike(thin, std::max(a.radius_px, b.radius_px)))
      return {};
    gap_crossing gap = gap_along(mask, pieces, a.tip, b.tip, a.radius_px, b.radius_px, a.piece, b.piece);
    gap.found = gap.found && gap.gap_px <= rules.widest_gap(thin);
    return gap;
  }

  /// End to body: each end's axis carried on to the side of another piece.
  void add_end_to_body() noexcept {
    const std::span<const limb_end> found = ends.first(end_count);
    for (std::size_t i = 0; i < end_count; ++i) {
      bridge_candidate c = axis_to_body(mask, dist2, pieces, found[i], found, rules);
      if (c.bridge.kind != bridge_kind::end_to_body) continue;
      c.a = static_cast<std::int32_t>(i);
      add(c);
    }
  }

  /// The candidates taken into `out`, shortest gaps first (end to end before end to body at a
  /// tie): each whose ends are free (`used`: scratch, one per end, zeroed) and whose pieces are
  /// still apart, which it then joins.
  void choose(std::span<std::uint8_t> used, bounded_vector<gap_bridge>& out) noexcept {
    const std::span<bridge_candidate> found = candidates.first(count);
    std::sort(found.begin(), found.end(), [](const bridge_candidate& x, const bridge_candidate& y) {
      if (x.bridge.gap_px != y.bridge.gap_px) return x.bridge.gap_px < y.bridge.gap_px;
      if (x.bridge.kind != y.bridge.kind) return x.bridge.kind == bridge_kind::end_to_end;
      return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
    const auto free = [&](std::int32_t end) { return end < 0 || used[static_cast<std::size_t>(end)] == 0; };
    for (const bridge_candidate& c : found) {
      if (out.size() == out.capacity()) break;
      if (!free(c.a) || !free(c.b) || pieces.joined(c.piece_a, c.piece_b)) continue;
      for (const std::int32_t end : {c.a, c.b})
        if (end >= 0) used[static_cast<std::size_t>(end)] = 1;
      pieces.join(c.piece_a, c.piece_b);
      (void)out.push_back(c.bridge);
    }
  }
};

}  // namespace detail

/// Finds the gaps to bridge in `mask` (1 = tree, its `runs`, squared distances `dist2` on its
/// tree pixels) from the ends of its pruned skeleton graph `graph`, into `out` (cleared first;
/// at most its capacity, the shortest gaps first). `max_gap_px` is in the mask's pixels;
/// `limbs` says when two ends are one limb.
///
/// Every end node of the graph is a candidate, with its axis, radius and piece of mask
/// (`end_of_limb`). Two ends on different pieces are bridged end to end when each one's axis
/// points at the other's tip (within `limbs.max_turn_deg`, give or take the outline's pixel),
/// the thinner is at least `limbs.through_thickness_ratio_min` of the thicker, and the
/// background between them, along the line from tip to tip, is at most
/// `options.max_gap_diameters` diameters of the thinner end and `max_gap_px` (the line
/// crossing no third piece). An end is bridged to a body when its axis, carried on out of its
/// piece, meets the side of another piece within that much background (`max_gap_diameters`
/// of its own diameter), and that piece is at least that share of the end's thickness there
/// (its distance map along the axis). Then, shortest gaps first, each candidate is taken whose
/// ends are free and whose two pieces are still apart: every bridge joins two pieces, and no
/// bridge closes a loop.
/// A mask with a single piece has nothing to bridge, and costs nothing. Needs `runs` that
/// describe `mask` (a speckled mask whose runs were not listed is left as it is).
/// Errors: `workspace_too_small` / `out_of_memory` (`gap_bridge_search_bytes`).
/// Complexity: O(ends log ends + runs + ends × (gap + radius)).
[[nodiscard]] inline status find_gap_bridges(image_view<const std::uint8_t> mask,
                                             image_view<const std::uint32_t> dist2,
                                             const row_runs& runs, const skeleton_graph& graph,
                                             float max_gap_px, const bridge_options& options,
                                             const limb_options& limbs, workspace& ws,
                                             bounded_vector<gap_bridge>& out) noexcept {
  out.clear();
  if (graph.component_count() < 2 || !runs.describes(mask) || out.capacity() == 0) return {};
  const workspace::checkpoint scratch = ws.mark();
  auto finish = [&](status s) {
    ws.rewind(scratch);
    return s;
  };
  auto pieces = mask_pieces::find(runs, mask.height(), ws);
  if (!pieces) return finish(unexpected{pieces.error()});
  const std::size_t nodes = graph.node_count();
  auto ends = ws.allocate<limb_end>(nodes);
  auto order = ws.allocate<std::int32_t>(nodes);
  auto candidates = ws.allocate<detail::bridge_candidate>(2 * nodes);
  auto used = ws.allocate_zeroed<std::uint8_t>(nodes);
  if (auto ok = all_ok(ends, order, candidates, used); !ok) return finish(ok);
  // A turn of 90° or more would face sideways: the angle is held just under it. (tan from cos,
  // which the limbs' rule already takes: no tangent's code in a firmware image.)
  const float turn_cos =
      std::cos(std::min(limbs.max_turn_deg, 89.0f) * std::numbers::pi_v<float> / 180.0f);
  detail::bridge_search search{mask, dist2, *pieces,
                            {max_gap_px, options.max_gap_diameters, std::sqrt(1.0f - turn_cos * turn_cos) / turn_cos,
                             limbs.through_thickness_ratio_min},
                            *ends, *candidates};
  search.collect_ends(graph);
  search.add_end_to_end(*order);
  search.add_end_to_body();
  search.choose(*used, out);
  return finish({});
}

/// Draws each bridge into `mask` (set to 1): the pixels whose centres lie within the capsule
/// from `from` to `to`, its radius going linearly from `from_radius_px` to `to_radius_px`
/// less half a pixel (a distance-map radius reaches the nearest background pixel's centre, half
/// a pixel beyond the outline). The mask's outermost rows and columns are left as they are (the
/// prepared mask's background border). Returns the pixels set that were background.
/// Complexity: O(pixels of the capsules' boxes).
inline std::int64_t draw_gap_bridges(image_view<std::uint8_t> mask,
                                     std::span<const gap_bridge> bridges) noexcept {
  std::int64_t added = 0;
  for (const gap_bridge& b : bridges) {
    const float r = std::max(b.from_radius_px, b.to_radius_px);
    const int x0 = std::max(1, static_cast<int>(std::floor(std::min(b.from.x(), b.to.x()) - r)));
    const int x1 = std::min(mask.width() - 2, static_cast<int>(std::ceil(std::max(b.from.x(), b.to.x()) + r)));
    const int y0 = std::max(1, static_cast<int>(std::floor(std::min(b.from.y(), b.to.y()) - r)));
    const int y1 = std::min(mask.height() - 2, static_cast<int>(std::ceil(std::max(b.from.y(), b.to.y()) + r)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        float t = 0;
        const float d = detail::segment_distance(to_point({x, y}), b.from, b.to, t);
        if (d > b.from_radius_px + t * (b.to_radius_px - b.from_radius_px) - 0.5f) continue;
        added += mask(x, y) == 0 ? 1 : 0;
        mask(x, y) = 1;
      }
  }
  return added;
}

/// Whether point `p` lies on one of `bridges` (within its capsule's larger radius): a stretch of
/// centreline there was drawn, not seen.
[[nodiscard]] inline bool on_gap_bridge(point2f p, std::span<const gap_bridge> bridges) noexcept {
  for (const gap_bridge& b : bridges) {
    float t = 0;
    if (detail::segment_distance(p, b.from, b.to, t) <= std::max(b.from_radius_px, b.to_radius_px))
      return true;
  }
  return false;
}

}  // namespace perch
