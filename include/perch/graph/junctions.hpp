// SPDX-License-Identifier: BSL-1.0
/// \file
/// Stage "junctions": where a limb is clear of the junctions at its ends. A skeleton runs on
/// into the body of the limb it meets, and at a narrow fork splits only where the limbs'
/// surfaces part; windows must start where the limb is its own. `outside_junctions` trims one
/// branch, `limb_stretch` a limb (a chain of branches from `trace_limbs`), with
/// `limb_at_junction` modelling each other limb at a junction as a straight limb whose base
/// lies on this one's axis.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>

#include "perch/core/geometry.hpp"
#include "perch/graph/limbs.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

/// Which ends of a branch `outside_junctions` trims.
enum class trimmed_ends : std::uint8_t {
  both,  ///< both ends
  from,  ///< the end at its `from` node only
  to,    ///< the end at its `to` node only
};

/// Room (px) a claw needs between the branch and another limb's surface: the distance-map
/// radius already reaches half a pixel beyond the true surface, so 1.5 px more gives the 2 px
/// gap within which two limbs touch.
inline constexpr float junction_gap_px = 1.5f;

/// How far (px) the smoothed radius at a narrow fork's waist lies below the radii on both sides
/// of it (`outside_junctions`). The distance map's radii are square roots of integers, and the
/// mean over three points steadies them: half a pixel is above their rounding noise (a quarter
/// finds waists in outline noise) and below a real fork's waist.
inline constexpr float waist_drop_px = 0.5f;

/// Another branch at a junction, as the trimming of `outside_junctions` sees it: a straight limb
/// of radius `radius_px` that leaves along `direction` from `base` (the point where its axis,
/// extended back through the junction, meets the trimmed branch's centreline).
struct junction_limb {
  point2f base{0, 0};
  point2f direction{0, 0};
  float radius_px = 0;
  bool valid = false;
};

/// The limb of branch `other` (walked from node `n` by `in`) as seen from branch `own`, whose
/// points are walked from `n` by `own_points` (index 0 next to the node).
/// Its axis is `other`'s chord just beyond the node (`leaving_axis_of`); its base is the
/// first of `own`'s points (within `reach_px` of the node) that lies on that axis (within 1 px)
/// or where the axis crosses `own`'s centreline; when there is none (a limb continuing this one
/// at a slight offset), the point next to the node.
template <class OwnAt>
[[nodiscard]] inline junction_limb limb_at_junction(const skeleton_branch& other, traversal dir,
                                                    const skeleton_node& node, OwnAt&& own_at,
                                                    std::size_t own_count,
                                                    float reach_px) noexcept {
  junction_limb out;
  const detail::leaving_axis axis = detail::leaving_axis_of(other, dir, node);
  if (!axis.valid) return out;
  const point2f centre = to_point(node.position);
  const point2f a = axis.start;
  const point2f u = axis.direction;
  auto signed_distance = [&](point2f p) {
    const point2f v = p - a;
    return u.x() * v.y() - u.y() * v.x();
  };
  // The base: where own's centreline meets or crosses the axis, else next to the node.
  std::size_t best = 0;
  float previous = 0;
  for (std::size_t k = 0; k < own_count; ++k) {
    const point2f p = to_point(own_at(k));
    if ((p - centre).norm() > reach_px) break;
    const float d = signed_distance(p);
    if (std::abs(d) <= 1.0f) {  // on the axis: a limb continuing this one, or its base
      best = k;
      break;
    }
    if (k > 0 && ((previous < 0) != (d < 0))) {
      best = std::abs(previous) < std::abs(d) ? k - 1 : k;
      break;
    }
    previous = d;
  }
  if (own_count == 0) return out;
  const point2f p = to_point(own_at(best));
  out.base = a + u * u.dot(p - a);
  out.direction = u;
  // The limb's radius at the junction: where its stretch starts, but no more than the stretch's
  // mean, which the crotch of a fork inflates near the node. A limb that thickens away from the
  // junction (the parent below a side limb) is read at its near end, not down where it is wider.
  out.radius_px = std::min(axis.radius_near_px, axis.radius_px);
  out.valid = true;
  return out;
}

namespace detail {

/// Squared distance (px²) between two pixels.
[[nodiscard]] inline float distance2_px(pixel a, pixel c) noexcept {
  const float dx = static_cast<float>(a.x - c.x);
  const float dy = static_cast<float>(a.y - c.y);
  return dx * dx + dy * dy;
}

/// A branch's points walked from one end, as `outside_junctions` trims them: `at(k)` is the
/// k-th point walked from the node there (point `index(k)`), `limit` the points it may trim.
template <class Index>
struct walked_points {
  const skeleton_branch& b;
  Index index;
  std::size_t limit;
  [[nodiscard]] pixel at(std::size_t k) const noexcept { return b.points[index(k)]; }
  [[nodiscard]] float radius(std::size_t k) const noexcept { return b.radius_px[index(k)]; }
};
template <class Index>
walked_points(const skeleton_branch&, Index, std::size_t) -> walked_points<Index>;

/// The other limbs at a junction (`limb_at_junction`), at most eight.
struct junction_limbs {
  static constexpr std::size_t max_limbs = 8;
  junction_limb limbs[max_limbs];
  std::size_t count = 0;
};

/// Points trimmed at a tip: the round cap, the points within their own radius (arc length) of
/// the end.
template <class Index>
[[nodiscard]] std::size_t trim_tip_cap(const walked_points<Index>& w) noexcept {
  std::size_t k = 0;
  float arc = 0;
  while (k < w.limit && arc < w.radius(k)) {
    ++k;
    if (k < w.limit) arc += std::sqrt(distance2_px(w.at(k), w.at(k - 1)));
  }
  return k;
}

/// The other limbs at junction `id` (`node`) as seen from the walked branch, based within
/// `reach` of the node.
template <class Index>
[[nodiscard]] junction_limbs limbs_around(const skeleton_graph& graph, node_id id,
                                          const skeleton_node& node, const walked_points<Index>& w,
                                          float reach) noexcept {
  junction_limbs out;
  auto at = [&](std::size_t k) { return w.at(k); };
  for (const incidence in : graph.topology().incidences(id)) {
    if (in.edge == w.b.id || out.count == junction_limbs::max_limbs) continue;
    out.limbs[out.count++] =
        limb_at_junction(graph.branch(in.edge), in.direction, node, at, w.limit, reach);
  }
  return out;
}

/// Whether point `p` of branch `own` lies inside junction `id` (`node`): inside the node's disc,
/// within radius + `junction_gap_px` of another limb there extended straight back (`limbs`), or
/// inside the inscribed disc of a point of another branch there.
[[nodiscard]] inline bool inside_junction(const skeleton_graph& graph, edge_id own, node_id id,
                                          const skeleton_node& node, const junction_limbs& limbs,
                                          pixel p) noexcept {
  const float to_node2 = distance2_px(p, node.position);
  if (to_node2 < node.radius_px * node.radius_px) return true;
  const point2f q = to_point(p);
  for (std::size_t l = 0; l < limbs.count; ++l) {
    const junction_limb& L = limbs.limbs[l];
    if (!L.valid) continue;
    const float t = std::max(0.0f, L.direction.dot(q - L.base));
    const float r = L.radius_px + junction_gap_px;
    if ((q - (L.base + t * L.direction)).squaredNorm() < r * r) return true;
  }
  // Points of the other branches within reach of p, walked from the junction outward.
  const float near = std::sqrt(to_node2) + 2.0f * node.radius_px + 1.0f;
  for (const incidence in : graph.topology().incidences(id)) {
    if (in.edge == own) continue;
    const skeleton_branch other = graph.branch(in.edge);
    const std::size_t count = other.points.size();
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = in.direction == traversal::forward ? k : count - 1 - k;
      const pixel o = other.points[i];
      if (distance2_px(o, node.position) > near * near) break;
      if (distance2_px(p, o) < other.radius_px[i] * other.radius_px[i]) return true;
    }
  }
  return false;
}

/// Points trimmed at a narrow fork, `k` (< `w.limit`) points already clear of the junction:
/// walked back from the node, the radius falls to a waist where the thinner limbs meet the
/// parent (the true fork) and rises to the parent's again. So when this branch is the parent (no
/// other limb there is thicker) and such a waist (a smoothed radius `waist_drop_px` below the
/// trimmed end's and the mean of the 8 points beyond it) lies within reach, the branch is
/// trimmed to it and on by the waist's radius + `junction_gap_px`, where the limbs' surfaces
/// are. (On a thinner branch, the radius noise near a wide node looks like a waist and would
/// cut good centreline.) Otherwise `k`.
template <class Index>
[[nodiscard]] std::size_t trim_to_waist(const walked_points<Index>& w, const skeleton_node& node,
                                        const junction_limbs& limbs, float reach,
                                        std::size_t k) noexcept {
  const std::size_t limit = w.limit;
  auto smoothed = [&](std::size_t j) {  // mean radius of points j - 1 … j + 1
    const std::size_t lo = j > 0 ? j - 1 : 0, hi = std::min(j + 1, limit - 1);
    float sum = 0;
    for (std::size_t q = lo; q <= hi; ++q) sum += w.radius(q);
    return sum / static_cast<float>(hi - lo + 1);
  };
  float widest = 0;  // the thickest other limb at the junction
  for (std::size_t l = 0; l < limbs.count; ++l)
    if (limbs.limbs[l].valid) widest = std::max(widest, limbs.limbs[l].radius_px);
  if (smoothed(k) < widest) return k;
  std::size_t waist = k;
  for (std::size_t j = k; j < limit && distance2_px(w.at(j), node.position) <= reach * reach; ++j)
    if (smoothed(j) <= smoothed(waist)) waist = j;
  float beyond = 0;
  std::size_t count = 0;
  for (std::size_t j = waist + 2; j < limit && j < waist + 10; ++j, ++count)
    beyond += w.radius(j);
  const float rim = smoothed(waist) + waist_drop_px;
  if (count < 4 || beyond < rim * static_cast<float>(count) || smoothed(k) < rim) return k;
  const float clear = w.radius(waist) + junction_gap_px;
  float arc = 0;
  while (waist + 1 < limit && arc < clear) {
    ++waist;
    arc += std::sqrt(distance2_px(w.at(waist), w.at(waist - 1)));
  }
  return waist;
}

/// Trims one end of a branch, at node `id` (see `outside_junctions`); returns points trimmed.
template <class Index>
[[nodiscard]] std::size_t trim_end(const skeleton_graph& graph, node_id id,
                                   const walked_points<Index>& w) noexcept {
  const skeleton_node node = graph.node(id);
  if (node.kind == node_kind::end) return trim_tip_cap(w);
  if (node.kind != node_kind::junction) return 0;
  const float reach = 2.5f * node.radius_px + 4.0f;
  const junction_limbs limbs = limbs_around(graph, id, node, w, reach);
  std::size_t k = 0;
  while (k < w.limit && inside_junction(graph, w.b.id, id, node, limbs, w.at(k))) ++k;
  if (k >= w.limit) return k;
  return trim_to_waist(w, node, limbs, reach, k);
}

}  // namespace detail
/// A branch's skeleton runs on into its parent up to the junction node, inside the parent's
/// body, where it bends toward the node: a window there measures the parent, not the branch.
/// And the medial axis of a narrow fork splits only where the two limbs' surfaces part, well
/// beyond where the thinner limb leaves the other (until then it runs hidden inside it).
/// Leading and trailing points are left out while they lie inside the junction node's disc,
/// inside the inscribed disc of a point of another branch at that junction (|p − q| < r(q)), or
/// within that branch's radius + `junction_gap_px` of its limb extended straight back through
/// the junction to where its axis meets this branch (`limb_at_junction`: a limb is modelled as
/// starting on its parent's axis, so the part of it hidden inside the parent counts too). The
/// window then starts where the branch is clear of every limb at the junction, however oblique
/// the fork. At a narrow fork the node itself sits up to a few radii beyond the true fork (the
/// medial axis splits only where the limbs' surfaces part), and the trimming reaches back to
/// the fork's waist (see `waist_drop_px` and the code). At a tip, the points within their own
/// radius (arc length) of the end are left out: the medial axis runs on into the tip's round
/// cap, past where the limb's axis ends. Loops keep all their points. `ends`: which ends to
/// trim (a limb runs through its inner junctions untrimmed).
/// Complexity: O(points of the branches at the junction within a few node radii).
[[nodiscard]] inline branch_stretch outside_junctions(
    const skeleton_graph& graph, const skeleton_branch& b,
    trimmed_ends ends = trimmed_ends::both) noexcept {
  const bool at_from = ends != trimmed_ends::to;
  const bool at_to = ends != trimmed_ends::from;
  const std::size_t n = b.points.size();
  auto forward = [](std::size_t k) { return k; };
  auto backward = [n](std::size_t k) { return n - 1 - k; };
  const std::size_t front =
      at_from ? detail::trim_end(graph, b.from, detail::walked_points{b, forward, n}) : 0;
  const std::size_t back =
      at_to ? detail::trim_end(graph, b.to, detail::walked_points{b, backward, n - front}) : 0;
  return {front, n - front - back};
}

/// The part of a limb's polyline outside the junctions at its two ends (`outside_junctions` of
/// its first and last edges there; a limb runs through its inner junctions untrimmed: only
/// side twigs leave there). A closed limb keeps all its points.
[[nodiscard]] inline branch_stretch limb_stretch(const skeleton_graph& graph,
                                                 const edge_continuations& next,
                                                 const skeleton_limb& limb) noexcept {
  const std::size_t n = limb.points.size();
  if (next.joined(limb.first_end)) return {0, n};  // closed
  const skeleton_branch first = graph.branch(edge_of_end(limb.first_end));
  const bool first_at_from = is_from_end(limb.first_end);
  // Points trimmed at edge end `end` of edge `b` (`b`'s other end untrimmed unless `both`).
  auto trimmed = [&](const skeleton_branch& b, bool at_from,
                     bool both) -> std::pair<std::size_t, std::size_t> {
    const trimmed_ends ends =
        both ? trimmed_ends::both : (at_from ? trimmed_ends::from : trimmed_ends::to);
    const branch_stretch s = outside_junctions(graph, b, ends);
    const std::size_t from_side = s.first;
    const std::size_t to_side = b.points.size() - s.first - s.count;
    return at_from ? std::pair{from_side, to_side} : std::pair{to_side, from_side};
  };
  if (edge_of_end(limb.first_end) == edge_of_end(limb.last_end)) {  // one edge
    const auto [front, back] = trimmed(first, first_at_from, true);
    return {front, n - front - back};
  }
  const std::size_t front = trimmed(first, first_at_from, false).first;
  const std::size_t back = trimmed(graph.branch(edge_of_end(limb.last_end)),
                                   is_from_end(limb.last_end), false)
                               .first;
  return {front, n - front - back};
}

}  // namespace perch
