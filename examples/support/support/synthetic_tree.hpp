// SPDX-License-Identifier: BSL-1.0
/// \file
/// Synthetic tree masks with ground truth, for tests, benchmarks and `perch synth`.
///
/// A tree seen from the side, as in the segmentation masks of the PLI paper (Perch Location
/// Identification): a trunk rising from the bottom edge of the image and tapering, forking
/// recursively into limbs whose diameters follow the pipe model (Leonardo da Vinci's rule,
/// d_parent² ≈ Σ d_child², at each fork and for side limbs leaving a limb along its length),
/// limbs of varied slope (near-horizontal side limbs, steep leaders), each limb one circular arc
/// (gentle, constant curvature) unless `bending` or `kinks` ask for wandering or kinked limbs,
/// some leaving the image. Optional noise adds what real segmentation masks carry: bumps and
/// spurs on the outline (which grow spurious skeleton branches), thin clutter twigs, occlusion
/// holes (loops in the skeleton) and detached fragments. `perch_truth` says where a claw could
/// perch, from the drawn geometry.
///
/// The mask is the union of tapered capsules, one per centreline segment: a pixel (x, y) is tree
/// when its centre, the point (x, y) (pixel centres sit at integer coordinates, as
/// `perch::to_point`), lies within `r(t)` of the segment, where t is the clamped projection
/// parameter and `r(t)` the linearly interpolated radius. The truth (`limb_truth`) holds exactly
/// those centrelines and radii, so `locate` answers from the same geometry the mask was drawn from.
///
/// Determinism: the random stream is `std::mt19937` (its output is specified by the standard);
/// floats are derived from its output here, never through the implementation-defined
/// `<random>` distributions; sines and cosines come from a fixed series, not libm. The same
/// options give the same mask bytes on every IEEE-754 platform (a compiler that contracts
/// `a * b + c` into FMA may move a boundary pixel whose centre lies within an ulp of a capsule).
///
/// Host code: allocates, no exceptions. Not part of the library.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/core/image_view.hpp"

namespace perch::support {

// ------------------------------------------------------------------------------------------------
// Drawing primitives
// ------------------------------------------------------------------------------------------------

/// Sets to `value` every pixel of `img` whose centre lies within the tapered capsule from `a`
/// (radius `radius_a`) to `b` (radius `radius_b`): distance to the segment ≤ r(t) with t the
/// clamped projection parameter and r linear in t. Only the segment's bounding box is visited;
/// parts outside the image are clipped. Radii < 0 draw nothing.
inline void draw_capsule(image_view<std::uint8_t> img, Eigen::Vector2f a, Eigen::Vector2f b,
                         float radius_a, float radius_b, std::uint8_t value = 1) {
  if (img.empty() || !(radius_a >= 0.0f) || !(radius_b >= 0.0f)) return;
  if (!a.allFinite() || !b.allFinite()) return;
  const float r_max = std::max(radius_a, radius_b);
  const float fx0 = std::floor(std::min(a.x(), b.x()) - r_max);
  const float fx1 = std::ceil(std::max(a.x(), b.x()) + r_max);
  const float fy0 = std::floor(std::min(a.y(), b.y()) - r_max);
  const float fy1 = std::ceil(std::max(a.y(), b.y()) + r_max);
  const float w = static_cast<float>(img.width() - 1);
  const float h = static_cast<float>(img.height() - 1);
  if (fx1 < 0.0f || fy1 < 0.0f || fx0 > w || fy0 > h) return;
  const int x0 = static_cast<int>(std::max(fx0, 0.0f));
  const int x1 = static_cast<int>(std::min(fx1, w));
  const int y0 = static_cast<int>(std::max(fy0, 0.0f));
  const int y1 = static_cast<int>(std::min(fy1, h));
  const Eigen::Vector2f ab = b - a;
  const float len2 = ab.squaredNorm();
  const float inv_len2 = len2 > 0.0f ? 1.0f / len2 : 0.0f;
  const float dr = radius_b - radius_a;
  for (int y = y0; y <= y1; ++y) {
    const auto row = img.row(y);
    const float py = static_cast<float>(y) - a.y();
    for (int x = x0; x <= x1; ++x) {
      const float px = static_cast<float>(x) - a.x();
      float t = (px * ab.x() + py * ab.y()) * inv_len2;
      t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
      const float dx = px - t * ab.x();
      const float dy = py - t * ab.y();
      const float r = radius_a + t * dr;
      if (dx * dx + dy * dy <= r * r) row[static_cast<std::size_t>(x)] = value;
    }
  }
}

/// `draw_capsule` with one radius: the pixels within `radius` of segment `a`–`b`.
inline void draw_capsule(image_view<std::uint8_t> img, Eigen::Vector2f a, Eigen::Vector2f b,
                         float radius, std::uint8_t value = 1) {
  draw_capsule(img, a, b, radius, radius, value);
}

/// The pixels within `radius` of `centre`.
inline void draw_disc(image_view<std::uint8_t> img, Eigen::Vector2f centre, float radius,
                      std::uint8_t value = 1) {
  draw_capsule(img, centre, centre, radius, radius, value);
}

/// A stroked polyline with per-vertex radius: the union of the tapered capsules between
/// consecutive `points` (radius `radii[i]` at `points[i]`). Draws nothing when the sizes differ
/// or fewer than one point is given (one point draws a disc).
inline void draw_polyline(image_view<std::uint8_t> img, const std::vector<Eigen::Vector2f>& points,
                          const std::vector<float>& radii, std::uint8_t value = 1) {
  if (points.empty() || points.size() != radii.size()) return;
  if (points.size() == 1) {
    draw_disc(img, points[0], radii[0], value);
    return;
  }
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
    draw_capsule(img, points[i], points[i + 1], radii[i], radii[i + 1], value);
}

namespace detail {

inline constexpr double pi = 3.14159265358979323846;

/// sin and cos from a fixed Taylor series after reduction to [-π, π], so every platform computes
/// the same bits (libm's last ulp differs between implementations). |error| < 1e-14.
inline void sin_cos(double angle, double& s, double& c) noexcept {
  const double two_pi = 2.0 * pi;
  double x = angle - two_pi * std::floor(angle / two_pi + 0.5);  // [-π, π]
  const double x2 = x * x;
  double term_s = x;    // x^(2k+1) / (2k+1)!
  double term_c = 1.0;  // x^(2k) / (2k)!
  s = 0.0;
  c = 0.0;
  for (int k = 0; k < 16; ++k) {
    s += term_s;
    c += term_c;
    const double n = static_cast<double>(2 * k);
    term_s *= -x2 / ((n + 2.0) * (n + 3.0));
    term_c *= -x2 / ((n + 1.0) * (n + 2.0));
  }
}

}  // namespace detail

/// The points of the circular arc around `centre` with radius `arc_radius`, from angle
/// `start_rad` to `end_rad` (angle a ↦ centre + R·(cos a, sin a); y is down, so growing angles
/// turn clockwise on screen), at most `max_step_px` apart (at least 2 points).
inline std::vector<Eigen::Vector2f> arc_points(Eigen::Vector2f centre, float arc_radius,
                                               float start_rad, float end_rad,
                                               float max_step_px = 2.0f) {
  const double sweep = static_cast<double>(end_rad) - static_cast<double>(start_rad);
  const double length = std::abs(sweep) * static_cast<double>(std::abs(arc_radius));
  const double step = max_step_px > 0.25f ? static_cast<double>(max_step_px) : 0.25;
  const int n = std::clamp(static_cast<int>(std::ceil(length / step)), 1, 1 << 20);
  std::vector<Eigen::Vector2f> points;
  points.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    double s = 0.0, c = 0.0;
    detail::sin_cos(static_cast<double>(start_rad) + sweep * i / n, s, c);
    points.emplace_back(
        static_cast<float>(static_cast<double>(centre.x()) + static_cast<double>(arc_radius) * c),
        static_cast<float>(static_cast<double>(centre.y()) + static_cast<double>(arc_radius) * s));
  }
  return points;
}

/// A stroked circular arc of constant `stroke_radius` (see `arc_points`).
inline void draw_arc(image_view<std::uint8_t> img, Eigen::Vector2f centre, float arc_radius,
                     float start_rad, float end_rad, float stroke_radius, std::uint8_t value = 1) {
  const auto points =
      arc_points(centre, arc_radius, start_rad, end_rad, std::max(1.0f, 0.5f * stroke_radius));
  draw_polyline(img, points, std::vector<float>(points.size(), stroke_radius), value);
}

// ------------------------------------------------------------------------------------------------
// Trees and their truth
// ------------------------------------------------------------------------------------------------

/// What a truth limb is: the trunk (limb 0), a limb of the branching structure, a thin
/// clutter twig (noise geometry, still real tree pixels), or a fragment: a piece of mask
/// detached from every tree (a segmenter's gap, foliage), which holds nothing up.
enum class limb_kind : std::uint8_t { trunk, limb, twig, fragment };

/// Which limbs `locate` considers.
enum class limb_set : std::uint8_t { all, without_twigs };

/// How much segmentation noise `benchmark_tree` adds.
enum class tree_noise : std::uint8_t { clean, noisy };

/// Whether a tree offers perches to the tendon-driven claw (`claw_spec`).
///  - `natural`: limbs grow as they will; some stretches usually suit the claw.
///  - `none`: a tree with no feasible perch by construction. Every limb of the branching
///    structure (forks, leaders) stays within 30° of vertical along its whole arc (slope ≥ 60°
///    to the horizontal, 25° beyond the claw's 35°); the side limbs are near-horizontal decoys
///    that are either thin (12–18 mm, below the claw's 30 mm) or, on the trunk when it is thick
///    enough, thick (≥ 132 mm without taper, above the claw's 110 mm); crossing limbs are thin
///    decoys; twigs stay under 18 mm. `feasible_stretches` of such a tree is empty (the tests
///    check it), whatever the noise.
enum class perch_supply : std::uint8_t { natural, none };

/// Options of `make_tree`. Lengths in px unless the name says mm.
struct tree_options {
  int width = 1920;                  ///< image width, px (≥ 1)
  int height = 1080;                 ///< image height, px (≥ 1)
  std::uint32_t seed = 1;            ///< the tree's seed; same options, same mask
  float mm_per_px = 2.0f;            ///< scale; the trunk is trunk_diameter_mm / mm_per_px wide
  float trunk_diameter_mm = 180.0f;  ///< trunk diameter at the bottom edge
  int levels = 3;                    ///< fork generations above the trunk (0: a bare trunk)
  int branches_per_node = 3;         ///< children per fork: 2 … this (≥ 2)
  int side_limbs = 1;                ///< side limbs leaving each limb along its length: 0 … this
                                     ///< (the trunk gets exactly this many, near-horizontal)
  float min_diameter_mm = 12.0f;     ///< limbs thinner than this are not grown
  float noise = 0.0f;                ///< outline roughness, px: bumps and spurs this big (0: none)
  int twigs = 0;                     ///< thin clutter twigs (1.5–3.5 px diameter) on the limbs
  int holes = 0;                     ///< occlusion holes inside thick limbs (loops in the skeleton)
  int crossings = 0;   ///< extra limbs that leave one limb and cross another (loops in the skeleton)
  float second_tree = 0.0f;  ///< a second, smaller tree beside the first, its size relative to
                             ///< the first's in (0, 1] (trunk diameter and height); 0: none
  perch_supply perches = perch_supply::natural;  ///< `none`: a tree with no feasible perch
  /// Random low-frequency bending along the limbs of the branching structure, 0 … 1: the
  /// heading varies smoothly along the arc, the sum of 1–3 sinusoids of 0.3–1.5 periods per limb
  /// length (a fifth of the image height for shorter limbs, so short limbs do not wiggle), each
  /// of amplitude `bending` × 4–12°, on top of the limb's arc, so limbs are no
  /// longer single circular arcs (`limb_truth::exact_arc` false; `curvature_per_px` holds the
  /// mean). Real limbs wander so; a truth that assumes arcs misjudges them. 0: none.
  float bending = 0.0f;
  /// Sharp kinks: each limb of the branching structure but the trunk gets 0 … `kinks` of them
  /// (drawn per limb), at 20–80 % of its length, where its heading jumps by ±20–60° (a limb
  /// that lost its leader and turned). 0: none.
  int kinks = 0;
  /// Detached pieces of mask near the crown (`limb_kind::fragment`, parent -1, `tree` the
  /// nearest tree's): short thick stubs (25–90 mm), thin sticks (2–6 px) or blobs, each at least
  /// 4 px (plus room for the outline noise) from every limb, twig and other fragment, so it is
  /// its own component of the mask: a segmenter's gap or foliage, which holds nothing up.
  int fragments = 0;
  /// Side limbs of every limb leave at 20–80° from it (instead of 35–70°; the trunk's at
  /// 20–80° from the trunk instead of 58–84° from vertical): steep side limbs beside near-level
  /// ones, and side limbs that hug their parent for a while.
  bool wide_side_angles = false;
};

/// The ground truth of one limb: a centreline from base to tip with a diameter per vertex.
/// Between vertices the limb is the tapered capsule of `draw_capsule`.
struct limb_truth {
  std::vector<Eigen::Vector2f> centreline;  ///< px, base → tip, ≥ 2 points (may leave the image)
  std::vector<float> diameter_px;           ///< per centreline vertex
  std::vector<float> arc_px;   ///< cumulative polyline length per vertex, arc_px[0] = 0
  int parent = -1;             ///< index of the limb it leaves; -1 for the trunk
  float parent_arc_px = 0.0f;  ///< where on the parent's centreline it starts
  int level = 0;               ///< 0 trunk, 1 its children, …
  limb_kind kind = limb_kind::limb;
  float base_heading_rad = 0.0f;  ///< direction at the base, from vertical-up, + towards +x
  float curvature_per_px = 0.0f;  ///< signed d(heading)/d(arc), + turns clockwise: constant
                                  ///< for an exact arc, else the mean (tip − base heading)/length
  int tree = 0;                   ///< which tree it belongs to: 0 the first, 1 the second
  /// The centreline samples one circular arc of `base_heading_rad` and `curvature_per_px`
  /// (the generator's limbs without bending or kinks): `truth_tangent_at` then answers from
  /// the exact arc. Otherwise (bent or kinked limbs, hand-built or imported ones) it answers
  /// from the polyline, and the heading and curvature are only informative.
  bool exact_arc = false;
};

/// A synthetic tree: the mask (1 = tree, 0 = sky), its limbs, and its scale.
struct synthetic_tree {
  image<std::uint8_t> mask;
  std::vector<limb_truth> limbs;  ///< limbs[0] is the trunk; parents come before children; the
                                  ///< second tree's trunk (if any) has parent -1 too
  float mm_per_px = 1.0f;
};

/// Length of a limb's centreline, px.
[[nodiscard]] inline float length_px(const limb_truth& limb) noexcept {
  return limb.arc_px.empty() ? 0.0f : limb.arc_px.back();
}

namespace detail {

/// Index i of the segment [i, i+1] holding arc position s (clamped), and t ∈ [0, 1] in it.
inline std::size_t segment_at(const limb_truth& limb, float s, float& t) noexcept {
  const auto& arc = limb.arc_px;
  t = 0.0f;
  if (arc.size() < 2) return 0;
  s = std::clamp(s, 0.0f, arc.back());
  auto it = std::upper_bound(arc.begin(), arc.end(), s);
  std::size_t i = it == arc.begin() ? 0 : static_cast<std::size_t>(it - arc.begin()) - 1;
  if (i + 1 >= arc.size()) i = arc.size() - 2;
  const float len = arc[i + 1] - arc[i];
  t = len > 0.0f ? std::clamp((s - arc[i]) / len, 0.0f, 1.0f) : 0.0f;
  return i;
}

}  // namespace detail

/// The centreline point at arc position `s` (px from the base, clamped to the limb).
[[nodiscard]] inline Eigen::Vector2f truth_point_at(const limb_truth& limb, float s) noexcept {
  if (limb.centreline.empty()) return Eigen::Vector2f::Zero();
  if (limb.centreline.size() < 2) return limb.centreline[0];
  float t = 0.0f;
  const std::size_t i = detail::segment_at(limb, s, t);
  return limb.centreline[i] + t * (limb.centreline[i + 1] - limb.centreline[i]);
}

/// The limb's diameter at arc position `s`, px (linear between vertices, as drawn).
[[nodiscard]] inline float truth_diameter_at(const limb_truth& limb, float s) noexcept {
  if (limb.diameter_px.empty()) return 0.0f;
  if (limb.diameter_px.size() < 2) return limb.diameter_px[0];
  float t = 0.0f;
  const std::size_t i = detail::segment_at(limb, s, t);
  return limb.diameter_px[i] + t * (limb.diameter_px[i + 1] - limb.diameter_px[i]);
}

/// The unit tangent (base → tip) at arc position `s`: for an `exact_arc` limb from the arc
/// (heading + κ·s), otherwise the direction of the polyline segment holding `s` (the first
/// non-degenerate one from there; straight up for a degenerate limb).
[[nodiscard]] inline Eigen::Vector2f truth_tangent_at(const limb_truth& limb, float s) noexcept {
  if (!limb.exact_arc) {
    if (limb.centreline.size() < 2 || limb.arc_px.size() != limb.centreline.size())
      return {0.0f, -1.0f};
    float t = 0.0f;
    for (std::size_t i = detail::segment_at(limb, s, t); i + 1 < limb.centreline.size(); ++i) {
      const Eigen::Vector2f d = limb.centreline[i + 1] - limb.centreline[i];
      const float n = d.norm();
      if (n > 0.0f) return d / n;
    }
    return {0.0f, -1.0f};
  }
  const float sc = std::clamp(s, 0.0f, length_px(limb));
  double sn = 0.0, cs = 0.0;
  detail::sin_cos(static_cast<double>(limb.base_heading_rad) +
                      static_cast<double>(limb.curvature_per_px) * static_cast<double>(sc),
                  sn, cs);
  return {static_cast<float>(sn), static_cast<float>(-cs)};
}

/// The slope to the horizontal at arc position `s`, degrees, folded into [0, 90]
/// (0 horizontal, 90 vertical, direction-free), as the PLI paper's window slope.
[[nodiscard]] inline float truth_slope_deg_at(const limb_truth& limb, float s) noexcept {
  const Eigen::Vector2f d = truth_tangent_at(limb, s);
  return static_cast<float>(
      std::atan2(std::abs(static_cast<double>(d.y())), std::abs(static_cast<double>(d.x()))) *
      (180.0 / detail::pi));
}

/// The magnitude of the limb's curvature, 1/px: constant along an `exact_arc` limb, else its
/// mean (`curvature_per_px`).
[[nodiscard]] inline float truth_curvature_at(const limb_truth& limb, float /*s*/) noexcept {
  return std::abs(limb.curvature_per_px);
}

/// Where a point sits relative to the truth: see `locate`.
struct limb_location {
  int limb = -1;                  ///< index into the limbs; -1 when there are none
  float arc_px = 0.0f;            ///< arc position of the closest centreline point
  float distance_px = 0.0f;       ///< distance from the point to that centreline point
  float diameter_px = 0.0f;       ///< truth diameter there
  float slope_deg = 0.0f;         ///< truth slope there, [0, 90]
  float curvature_per_px = 0.0f;  ///< |curvature| of the limb
  Eigen::Vector2f closest = Eigen::Vector2f::Zero();  ///< the closest centreline point
  [[nodiscard]] bool inside() const noexcept {
    return limb >= 0 && distance_px <= 0.5f * diameter_px;
  }
};

/// The limb a point belongs to, and where on it. The chosen limb is the one whose surface the
/// point is deepest inside (smallest distance-to-centreline minus local radius), so a point in a
/// junction belongs to the thicker limb, a point on a thin limb's centreline outside its parent
/// to the thin limb; ties go to the lower index. Complexity: O(total centreline vertices).
[[nodiscard]] inline limb_location locate(const std::vector<limb_truth>& limbs, Eigen::Vector2f p,
                                          limb_set which = limb_set::all) noexcept {
  limb_location best;
  float best_depth = std::numeric_limits<float>::infinity();
  for (std::size_t li = 0; li < limbs.size(); ++li) {
    const limb_truth& limb = limbs[li];
    if (which == limb_set::without_twigs && limb.kind == limb_kind::twig) continue;
    const auto& c = limb.centreline;
    if (c.size() < 2 || limb.diameter_px.size() != c.size() || limb.arc_px.size() != c.size())
      continue;
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const Eigen::Vector2f ab = c[i + 1] - c[i];
      const float len2 = ab.squaredNorm();
      float t = len2 > 0.0f ? (p - c[i]).dot(ab) / len2 : 0.0f;
      t = std::clamp(t, 0.0f, 1.0f);
      const Eigen::Vector2f q = c[i] + t * ab;
      const float dist = (p - q).norm();
      const float diameter =
          limb.diameter_px[i] + t * (limb.diameter_px[i + 1] - limb.diameter_px[i]);
      const float depth = dist - 0.5f * diameter;
      if (depth < best_depth) {
        best_depth = depth;
        best.limb = static_cast<int>(li);
        best.arc_px = limb.arc_px[i] + t * (limb.arc_px[i + 1] - limb.arc_px[i]);
        best.distance_px = dist;
        best.diameter_px = diameter;
        best.closest = q;
      }
    }
  }
  if (best.limb >= 0) {
    const limb_truth& limb = limbs[static_cast<std::size_t>(best.limb)];
    best.slope_deg = truth_slope_deg_at(limb, best.arc_px);
    best.curvature_per_px = truth_curvature_at(limb, best.arc_px);
  }
  return best;
}

/// `locate` over a tree's limbs.
[[nodiscard]] inline limb_location locate(const synthetic_tree& tree, Eigen::Vector2f p,
                                          limb_set which = limb_set::all) noexcept {
  return locate(tree.limbs, p, which);
}

namespace detail {

/// Uniform numbers from mt19937's specified 32-bit output (no implementation-defined
/// distributions).
class tree_random {
 public:
  explicit tree_random(std::uint32_t seed) : engine_(seed) {}
  /// [0, 1)
  double uniform() { return static_cast<double>(engine_() & 0xffffffffu) * (1.0 / 4294967296.0); }
  /// [lo, hi)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// lo … hi inclusive (hi ≥ lo)
  int integer(int lo, int hi) {
    if (hi <= lo) return lo;
    const auto span = static_cast<std::uint64_t>(hi - lo) + 1u;
    return lo +
           static_cast<int>((static_cast<std::uint64_t>(engine_() & 0xffffffffu) * span) >> 32);
  }
  /// -1 or +1
  double sign() { return (engine_() & 1u) != 0u ? 1.0 : -1.0; }

 private:
  std::mt19937 engine_;
};

inline constexpr double deg = pi / 180.0;

/// A limb waiting to be grown.
struct limb_seed {
  int parent = -1;
  double parent_arc = 0.0;
  Eigen::Vector2d base{0.0, 0.0};
  double heading = 0.0;   ///< rad from vertical-up, + towards +x
  double diameter = 0.0;  ///< px at the base
  double length = 0.0;    ///< px
  int level = 0;
  limb_kind kind = limb_kind::limb;
  bool decoy = false;  ///< `perch_supply::none`: a side limb that never forks
  int tree = 0;
};

/// Where and how big `grow_tree` grows a tree (the defaults grow the first tree).
struct tree_plan {
  double base_x_lo = 0.4, base_x_hi = 0.6;  ///< trunk base, fraction of the width
  double size = 1.0;                        ///< trunk diameter and height factor
  std::uint32_t seed_mix = 0;               ///< xor-ed into the seed
  int tree = 0;
};

/// `perch_supply::none`: structural limbs stay within this of vertical.
inline constexpr double steep_heading_max = 30.0 * (pi / 180.0);

/// The centreline of a circular arc of `length` from `base` with initial `heading` and
/// curvature `kappa`, as points at most `step` apart, with arc lengths.
inline void sample_arc(const limb_seed& seed, double kappa, double step, limb_truth& limb) {
  const int n = std::clamp(static_cast<int>(std::ceil(seed.length / step)), 1, 4096);
  limb.centreline.clear();
  limb.arc_px.clear();
  limb.centreline.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    const double s = seed.length * i / n;
    // Exact arc: p(s) = base + chord(s)·(sin, -cos)(heading + κs/2), chord = 2 sin(κs/2)/κ.
    double chord = s;
    if (std::abs(kappa * s) > 1e-9) {
      double hs = 0.0, hc = 0.0;
      sin_cos(0.5 * kappa * s, hs, hc);
      chord = 2.0 * hs / kappa;
    }
    double ms = 0.0, mc = 0.0;
    sin_cos(seed.heading + 0.5 * kappa * s, ms, mc);
    limb.centreline.emplace_back(static_cast<float>(seed.base.x() + chord * ms),
                                 static_cast<float>(seed.base.y() - chord * mc));
  }
  limb.arc_px.assign(limb.centreline.size(), 0.0f);
  double acc = 0.0;
  for (std::size_t i = 1; i < limb.centreline.size(); ++i) {
    acc += static_cast<double>((limb.centreline[i] - limb.centreline[i - 1]).norm());
    limb.arc_px[i] = static_cast<float>(acc);
  }
}

/// A limb's heading away from its arc: low-frequency sinusoids (`tree_options::bending`) and
/// kinks (`tree_options::kinks`). Zero everywhere when both are off.
struct heading_wander {
  struct wave {
    double amplitude, omega, phase;
  };
  std::vector<wave> waves;
  std::vector<std::pair<double, double>> kinks;  ///< (arc, heading jump), ascending arc
  [[nodiscard]] bool empty() const noexcept { return waves.empty() && kinks.empty(); }
  /// The heading offset at arc u (0 at the base: each wave starts at its phase's sine).
  [[nodiscard]] double at(double u) const noexcept {
    double h = 0.0;
    for (const wave& w : waves) {
      double s1 = 0.0, c1 = 0.0, s0 = 0.0, c0 = 0.0;
      sin_cos(w.omega * u + w.phase, s1, c1);
      sin_cos(w.phase, s0, c0);
      h += w.amplitude * (s1 - s0);
    }
    for (const auto& k : kinks)
      if (u >= k.first) h += k.second;
    return h;
  }
};

/// Draws the wander of a limb of `length` (a stream of its own, so the options off leave every
/// other draw, and the tree, as before).
inline heading_wander draw_wander(const tree_options& o, std::uint32_t stream, double length,
                                  bool trunk) {
  heading_wander w;
  const double bending = std::clamp(static_cast<double>(o.bending), 0.0, 1.0);
  const int kinks = trunk ? 0 : std::clamp(o.kinks, 0, 8);
  if (!(bending > 0.0) && kinks == 0) return w;
  tree_random rng(stream);
  if (bending > 0.0) {
    const int n = rng.integer(1, 3);
    for (int j = 0; j < n; ++j) {
      const double amplitude = bending * rng.uniform(4.0, 12.0) * deg * rng.sign();
      const double periods = rng.uniform(0.3, 1.5);
      const double phase = rng.uniform(0.0, 2.0 * pi);
      const double span = std::max({length, 0.2 * static_cast<double>(o.height), 1.0});
      w.waves.push_back({amplitude, 2.0 * pi * periods / span, phase});
    }
  }
  const int count = rng.integer(0, kinks);
  for (int k = 0; k < count; ++k)
    w.kinks.emplace_back(length * rng.uniform(0.2, 0.8),
                         rng.sign() * rng.uniform(20.0, 60.0) * deg);
  std::sort(w.kinks.begin(), w.kinks.end());
  return w;
}

/// The centreline of a limb whose heading is heading + κ·u + wander(u), clamped to ±`clamp`
/// (rad; ≥ π: none), integrated at the midpoint of steps at most `step` long, with a vertex at
/// every kink. Returns the heading at the tip.
inline double sample_wandering(const limb_seed& seed, double kappa, const heading_wander& w,
                               double clamp, double step, limb_truth& limb) {
  auto heading = [&](double u) {
    return std::clamp(seed.heading + kappa * u + w.at(u), -clamp, clamp);
  };
  std::vector<double> arcs;
  const int n = std::clamp(static_cast<int>(std::ceil(seed.length / step)), 1, 8192);
  for (int i = 0; i <= n; ++i) arcs.push_back(seed.length * i / n);
  for (const auto& k : w.kinks) arcs.push_back(k.first);
  std::sort(arcs.begin(), arcs.end());
  arcs.erase(std::unique(arcs.begin(), arcs.end(), [](double a, double b) { return b - a < 1e-6; }),
             arcs.end());
  limb.centreline.clear();
  limb.arc_px.clear();
  Eigen::Vector2d p = seed.base;
  limb.centreline.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  for (std::size_t i = 1; i < arcs.size(); ++i) {
    const double ds = arcs[i] - arcs[i - 1];
    double hs = 0.0, hc = 0.0;
    sin_cos(heading(0.5 * (arcs[i] + arcs[i - 1])), hs, hc);
    p += ds * Eigen::Vector2d(hs, -hc);
    limb.centreline.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  limb.arc_px.assign(limb.centreline.size(), 0.0f);
  double acc = 0.0;
  for (std::size_t i = 1; i < limb.centreline.size(); ++i) {
    acc += static_cast<double>((limb.centreline[i] - limb.centreline[i - 1]).norm());
    limb.arc_px[i] = static_cast<float>(acc);
  }
  return heading(seed.length);
}

/// Grows the branching structure (no noise) into `limbs` (appended: indices continue).
inline void grow_tree(const tree_options& o, std::vector<limb_truth>& limbs,
                      const tree_plan& plan = {}) {
  tree_random rng(o.seed ^ plan.seed_mix);
  const bool none = o.perches == perch_supply::none;
  const double W = o.width, H = o.height;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d0 = static_cast<double>(o.trunk_diameter_mm) * px_per_mm * plan.size;
  const double d_min = static_cast<double>(o.min_diameter_mm) * px_per_mm;
  const int max_children = std::max(2, o.branches_per_node);
  const int levels = std::clamp(o.levels, 0, 12);
  const int side_max = std::clamp(o.side_limbs, 0, 8);
  constexpr std::size_t max_limbs = 4000;

  std::vector<limb_seed> queue;
  limb_seed trunk;
  trunk.base = {W * rng.uniform(plan.base_x_lo, plan.base_x_hi),
                H - 1.0 + 0.5 * d0};  // cap below the image
  trunk.heading = rng.uniform(-5.0, 5.0) * deg;
  trunk.diameter = d0;
  trunk.length = std::max(H * plan.size * rng.uniform(0.36, 0.46), 3.0 * d0) + 0.5 * d0;
  trunk.level = 0;
  trunk.kind = limb_kind::trunk;
  trunk.tree = plan.tree;
  queue.push_back(trunk);

  for (std::size_t qi = 0; qi < queue.size() && limbs.size() < max_limbs; ++qi) {
    limb_seed seed = queue[qi];
    if (none && !seed.decoy)
      seed.heading = std::clamp(seed.heading, -steep_heading_max, steep_heading_max);
    const int index = static_cast<int>(limbs.size());
    // Curvature: limbs leaning out bend back up towards the light; steep ones wander a little.
    double turn = 0.0;
    if (seed.kind == limb_kind::trunk)
      turn = rng.uniform(-6.0, 6.0) * deg;
    else if (std::abs(seed.heading) > 40.0 * deg)
      turn = -(seed.heading > 0.0 ? 1.0 : -1.0) * rng.uniform(4.0, 28.0) * deg;
    else
      turn = rng.uniform(-14.0, 14.0) * deg;
    if (none && !seed.decoy)  // the whole arc stays steep
      turn = std::clamp(seed.heading + turn, -steep_heading_max, steep_heading_max) - seed.heading;
    const double kappa = turn / seed.length;

    // Side limbs along the length (decided first: they take their share of the pipe).
    const int level_next = seed.level + 1;
    int sides = 0;
    if (level_next <= levels && side_max > 0 && !seed.decoy)
      sides = seed.kind == limb_kind::trunk ? side_max : rng.integer(0, side_max);
    const double taper = rng.uniform(0.86, 0.95);
    const double d_tip_free = taper * seed.diameter;
    struct side_plan {
      double s, d;
    };
    std::vector<side_plan> plans;
    double side_area = 0.0;
    double side_sign = rng.sign();
    for (int k = 0; k < sides; ++k) {
      const double s = seed.length * rng.uniform(0.3, 0.8);
      const double d_here = seed.diameter + (d_tip_free - seed.diameter) * s / seed.length;
      double d = d_here * rng.uniform(0.36, 0.55);
      if (none) {  // decoys: thick (> 130 mm) on a thick enough trunk, else thin (< 20 mm)
        const double thick = rng.uniform(135.0, 150.0) * px_per_mm;
        const double thin = rng.uniform(12.0, 18.0) * px_per_mm;
        d = seed.kind == limb_kind::trunk && std::min(thick, 0.95 * d_here) >= 132.0 * px_per_mm
                ? std::min(thick, 0.95 * d_here)
                : std::min(thin, 0.8 * d_here);
      }
      if (d < d_min) continue;
      plans.push_back({s, d});
      side_area += d * d;
    }
    double d_tip =
        std::sqrt(std::max(d_tip_free * d_tip_free - side_area, 0.36 * d_tip_free * d_tip_free));
    if (seed.decoy && seed.diameter >= 132.0 * px_per_mm) d_tip = seed.diameter;  // stays thick

    limb_truth limb;
    limb.parent = seed.parent;
    limb.parent_arc_px = static_cast<float>(seed.parent_arc);
    limb.level = seed.level;
    limb.kind = seed.kind;
    limb.base_heading_rad = static_cast<float>(seed.heading);
    limb.curvature_per_px = static_cast<float>(kappa);
    limb.exact_arc = true;
    limb.tree = seed.tree;
    double step = std::max(1.5, std::min(0.375 * d_tip, std::max(32.0, 0.1 * d_tip)));
    if (std::abs(kappa) > 0.0) step = std::min(step, 1.5 * deg / std::abs(kappa));
    const heading_wander wander = draw_wander(
        o, o.seed ^ plan.seed_mix ^ 0x68e31da4u ^ (static_cast<std::uint32_t>(index) * 0x9e3779b1u),
        seed.length, seed.kind == limb_kind::trunk);
    double tip_heading = seed.heading + kappa * seed.length;
    if (wander.empty()) {
      sample_arc(seed, kappa, step, limb);
    } else {
      // `none`: structural limbs stay steep all along, however they wander.
      const double clamp = none && !seed.decoy ? steep_heading_max : 4.0 * pi;
      tip_heading = sample_wandering(seed, kappa, wander, clamp, std::min(step, 2.0), limb);
      limb.exact_arc = false;
      limb.curvature_per_px = static_cast<float>((tip_heading - seed.heading) / seed.length);
    }
    limb.diameter_px.resize(limb.centreline.size());
    for (std::size_t i = 0; i < limb.centreline.size(); ++i) {
      const double u =
          static_cast<double>(limb.arc_px[i]) / static_cast<double>(limb.arc_px.back());
      limb.diameter_px[i] = static_cast<float>(seed.diameter + (d_tip - seed.diameter) * u);
    }
    const float length = length_px(limb);
    const Eigen::Vector2f tip = limb.centreline.back();
    limbs.push_back(std::move(limb));
    const limb_truth& grown = limbs.back();

    auto inside_image = [&](Eigen::Vector2f p) {
      return p.x() >= 0.0f && p.y() >= 0.0f && p.x() <= static_cast<float>(W - 1) &&
             p.y() <= static_cast<float>(H - 1);
    };
    auto clamp_heading = [](double h) { return std::clamp(h, -105.0 * deg, 105.0 * deg); };

    // Side limbs: near-horizontal for the trunk, diverging for limbs.
    for (const side_plan& side_at : plans) {
      const auto s = static_cast<float>(side_at.s * static_cast<double>(length) / seed.length);
      const Eigen::Vector2f at = truth_point_at(grown, s);
      if (!inside_image(at)) continue;
      const Eigen::Vector2f t = truth_tangent_at(grown, s);
      const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y()));
      limb_seed side;
      side.parent = index;
      side.parent_arc = static_cast<double>(s);
      side.base = {static_cast<double>(at.x()), static_cast<double>(at.y())};
      if (seed.kind == limb_kind::trunk) {
        side.heading = o.wide_side_angles ? here + side_sign * rng.uniform(20.0, 80.0) * deg
                                          : side_sign * rng.uniform(58.0, 84.0) * deg;
      } else {
        // Diverge by 35–70° from the parent. Near a horizontal parent the clamp can take most
        // of that away (a limb heading 95° turned +50° clamps to 105°: 10° of divergence), and
        // the child then hugs its parent for its whole length, fused with it in the mask: no
        // tree grows so, so such a limb leaves on the other side instead.
        const double lo = o.wide_side_angles ? 20.0 : 35.0, hi = o.wide_side_angles ? 80.0 : 70.0;
        const double divergence = rng.uniform(lo, hi) * deg;
        side.heading = clamp_heading(here + side_sign * divergence);
        if (std::abs(side.heading - here) < lo * deg) {
          side_sign = -side_sign;
          side.heading = clamp_heading(here + side_sign * divergence);
        }
      }
      if (none) side.heading = side_sign * rng.uniform(62.0, 88.0) * deg;  // near-horizontal
      side_sign = -side_sign;
      side.diameter = side_at.d;
      side.length = std::max(seed.length * rng.uniform(0.45, 0.75), 4.0 * side_at.d);
      side.level = level_next;
      side.kind = limb_kind::limb;
      side.decoy = none;
      side.tree = seed.tree;
      queue.push_back(side);
    }

    // The fork at the tip: a leader close to the parent's direction and diverging others.
    if (level_next > levels || !inside_image(tip) || seed.decoy) continue;
    const int children = rng.integer(2, max_children);
    std::vector<double> share(static_cast<std::size_t>(children));
    double total = 0.0;
    for (int k = 0; k < children; ++k) {
      share[static_cast<std::size_t>(k)] = k == 0 ? rng.uniform(1.3, 1.8) : rng.uniform(0.5, 1.0);
      total += share[static_cast<std::size_t>(k)];
    }
    const double lean = rng.sign();
    for (int k = 0; k < children; ++k) {
      const double d = d_tip * std::sqrt(share[static_cast<std::size_t>(k)] / total);
      double heading = tip_heading;
      if (k == 0)
        heading += (children == 2 ? lean * rng.uniform(5.0, 22.0) : rng.uniform(-12.0, 12.0)) * deg;
      else if (children == 2)
        heading -= lean * rng.uniform(30.0, 62.0) * deg;
      else
        heading += (k % 2 == 1 ? lean : -lean) * rng.uniform(28.0, 62.0) * deg;
      const double child_length = std::max(seed.length * rng.uniform(0.58, 0.78), 4.0 * d);
      if (d < d_min) continue;
      limb_seed child;
      child.parent = index;
      child.parent_arc = static_cast<double>(length);
      child.base = {static_cast<double>(tip.x()), static_cast<double>(tip.y())};
      child.heading = clamp_heading(heading);
      child.diameter = d;
      child.length = child_length;
      child.level = level_next;
      child.kind = limb_kind::limb;
      child.tree = seed.tree;
      queue.push_back(child);
    }
  }
}

/// Adds `o.crossings` limbs that leave a random limb P and cross another limb Q of the same
/// tree (aimed at a point of Q's centreline, then running on past Q), so the mask gets loops.
/// A crossing limb is a limb of P (parent P, level + 1), 0.4–0.6 of P's diameter there
/// (`perch_supply::none`: a thin decoy of 12–18 mm), nearly straight (a turn of ±8°), leaving P
/// and crossing Q at 30° or more. Pairs are drawn until one fits (at most 40 draws per crossing).
inline void add_crossings(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.crossings <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x27d4eb2fu);
  const std::size_t structural = limbs.size();
  const double W = o.width, H = o.height;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d_min = static_cast<double>(o.min_diameter_mm) * px_per_mm;
  auto inside_image = [&](Eigen::Vector2f p) {
    return p.x() >= 0.0f && p.y() >= 0.0f && p.x() <= static_cast<float>(W - 1) &&
           p.y() <= static_cast<float>(H - 1);
  };
  const int wanted = std::min(o.crossings, 64);
  for (int k = 0, draws = 0; k < wanted && draws < 40 * wanted; ++draws) {
    const auto p_index = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const auto q_index = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const double u_p = rng.uniform(0.2, 0.8);
    const double u_q = rng.uniform(0.2, 0.8);
    const double turn = rng.uniform(-8.0, 8.0) * deg;
    const double share = rng.uniform(0.4, 0.6);
    const double thin = rng.uniform(12.0, 18.0) * px_per_mm;
    const double overshoot = rng.uniform(0.3, 0.8);
    if (p_index == q_index) continue;
    const limb_truth& P = limbs[p_index];
    const limb_truth& Q = limbs[q_index];
    if (P.kind == limb_kind::twig || Q.kind == limb_kind::twig || P.tree != Q.tree) continue;
    if (static_cast<int>(q_index) == P.parent || Q.parent == static_cast<int>(p_index)) continue;
    const auto s_p = static_cast<float>(u_p * static_cast<double>(length_px(P)));
    const auto s_q = static_cast<float>(u_q * static_cast<double>(length_px(Q)));
    const Eigen::Vector2f a = truth_point_at(P, s_p);
    const Eigen::Vector2f b = truth_point_at(Q, s_q);
    if (!inside_image(a) || !inside_image(b)) continue;
    const double r_p = 0.5 * static_cast<double>(truth_diameter_at(P, s_p));
    const double r_q = 0.5 * static_cast<double>(truth_diameter_at(Q, s_q));
    const Eigen::Vector2f ab = b - a;
    const double dist = static_cast<double>(ab.norm());
    if (dist < std::max(2.0 * (r_p + r_q), 0.08 * H) || dist > 0.4 * H) continue;
    const Eigen::Vector2f dir = ab / ab.norm();
    const double cross = std::abs(static_cast<double>(
        dir.x() * truth_tangent_at(Q, s_q).y() - dir.y() * truth_tangent_at(Q, s_q).x()));
    if (cross < 0.5) continue;  // crosses Q at 30° or more
    const Eigen::Vector2f tp = truth_tangent_at(P, s_p);
    if (std::abs(static_cast<double>(dir.x() * tp.y() - dir.y() * tp.x())) < 0.5)
      continue;  // and leaves P at 30° or more (not running along it)
    double d = share * 2.0 * r_p;
    if (o.perches == perch_supply::none) d = std::min(thin, 1.6 * r_p);
    if (d < d_min) continue;
    limb_seed seed;
    seed.parent = static_cast<int>(p_index);
    seed.parent_arc = static_cast<double>(s_p);
    seed.base = {static_cast<double>(a.x()), static_cast<double>(a.y())};
    seed.length = dist * (1.0 + overshoot) + r_q;
    const double kappa = turn / seed.length;
    // The chord to arc length `dist` points along heading + κ·dist/2: aim it at b.
    seed.heading = std::atan2(static_cast<double>(dir.x()), -static_cast<double>(dir.y())) -
                   0.5 * kappa * dist;
    seed.diameter = d;
    seed.level = P.level + 1;
    seed.kind = limb_kind::limb;
    seed.tree = P.tree;
    limb_truth limb;
    limb.parent = seed.parent;
    limb.parent_arc_px = s_p;
    limb.level = seed.level;
    limb.kind = limb_kind::limb;
    limb.base_heading_rad = static_cast<float>(seed.heading);
    limb.curvature_per_px = static_cast<float>(kappa);
    limb.exact_arc = true;
    limb.tree = seed.tree;
    double step = std::max(1.5, std::min(0.375 * d, 32.0));
    if (std::abs(kappa) > 0.0) step = std::min(step, 1.5 * deg / std::abs(kappa));
    sample_arc(seed, kappa, step, limb);
    const double d_tip = 0.85 * d;
    limb.diameter_px.resize(limb.centreline.size());
    for (std::size_t i = 0; i < limb.centreline.size(); ++i) {
      const double u =
          static_cast<double>(limb.arc_px[i]) / static_cast<double>(limb.arc_px.back());
      limb.diameter_px[i] = static_cast<float>(d + (d_tip - d) * u);
    }
    limbs.push_back(std::move(limb));
    ++k;
  }
}

/// Adds a second, smaller tree (`o.second_tree` × the first's trunk diameter and height) on the
/// side of the image away from the first trunk.
inline void add_second_tree(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (!(o.second_tree > 0.0f) || limbs.empty()) return;
  tree_plan plan;
  plan.size = std::min(static_cast<double>(o.second_tree), 1.0);
  const double first_x = static_cast<double>(limbs[0].centreline[0].x()) / o.width;
  if (first_x < 0.5) {
    plan.base_x_lo = 0.8;
    plan.base_x_hi = 0.92;
  } else {
    plan.base_x_lo = 0.08;
    plan.base_x_hi = 0.2;
  }
  plan.seed_mix = 0x5bd1e995u;
  plan.tree = 1;
  tree_options second = o;
  second.levels = std::max(0, o.levels - 1);
  grow_tree(second, limbs, plan);
}

/// Adds `count` thin twigs leaving random limbs (drawn and recorded as `limb_kind::twig`).
inline void add_twigs(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.twigs <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x9e3779b9u);
  const std::size_t structural = limbs.size();
  const double H = o.height;
  for (int k = 0; k < o.twigs; ++k) {
    const auto li = static_cast<std::size_t>(rng.integer(0, static_cast<int>(structural) - 1));
    const limb_truth& parent = limbs[li];
    const auto s =
        static_cast<float>(rng.uniform(0.1, 0.95) * static_cast<double>(length_px(parent)));
    const Eigen::Vector2f at = truth_point_at(parent, s);
    const Eigen::Vector2f t = truth_tangent_at(parent, s);
    const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y()));
    limb_seed seed;
    seed.parent = static_cast<int>(li);
    seed.parent_arc = static_cast<double>(s);
    seed.base = {static_cast<double>(at.x()), static_cast<double>(at.y())};
    seed.heading =
        std::clamp(here + rng.sign() * rng.uniform(30.0, 80.0) * deg, -120.0 * deg, 120.0 * deg);
    seed.diameter = rng.uniform(1.5, 3.5);
    if (o.perches == perch_supply::none)  // twigs stay under 18 mm
      seed.diameter = std::min(seed.diameter, 18.0 / static_cast<double>(o.mm_per_px));
    seed.length =
        0.5 * static_cast<double>(truth_diameter_at(parent, s)) + H * rng.uniform(0.03, 0.1);
    seed.level = parent.level + 1;
    seed.kind = limb_kind::twig;
    const double kappa = rng.uniform(-20.0, 20.0) * deg / seed.length;
    limb_truth twig;
    twig.parent = seed.parent;
    twig.parent_arc_px = s;
    twig.level = seed.level;
    twig.kind = limb_kind::twig;
    twig.tree = parent.tree;
    twig.base_heading_rad = static_cast<float>(seed.heading);
    twig.curvature_per_px = static_cast<float>(kappa);
    twig.exact_arc = true;
    sample_arc(seed, kappa, std::min(4.0, 1.5 * deg / std::max(std::abs(kappa), 1e-9)), twig);
    const double d_tip = std::max(1.0, 0.6 * seed.diameter);
    twig.diameter_px.resize(twig.centreline.size());
    for (std::size_t i = 0; i < twig.centreline.size(); ++i) {
      const double u =
          static_cast<double>(twig.arc_px[i]) / static_cast<double>(twig.arc_px.back());
      twig.diameter_px[i] = static_cast<float>(seed.diameter + (d_tip - seed.diameter) * u);
    }
    limbs.push_back(std::move(twig));
  }
}

/// The smallest distance from the surface of the tapered capsule chain `limb` to point p, px
/// (negative inside).
inline float surface_distance(const limb_truth& limb, Eigen::Vector2f p) noexcept {
  float best = std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k + 1 < limb.centreline.size(); ++k) {
    const Eigen::Vector2f q0 = limb.centreline[k];
    const Eigen::Vector2f d = limb.centreline[k + 1] - q0;
    const float len2 = d.squaredNorm();
    const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
    const float r =
        0.5f * (limb.diameter_px[k] + t * (limb.diameter_px[k + 1] - limb.diameter_px[k]));
    best = std::min(best, (p - (q0 + t * d)).norm() - r);
  }
  return best;
}

/// Adds `o.fragments` detached pieces of mask (`limb_kind::fragment`) near the crown: a point
/// drawn in the box of the first tree's limbs above the trunk (the trunk's top third when it
/// has none), then a short thick stub (25–90 mm, 1–4 diameters long), a thin stick (2–6 px,
/// 3–8 % of the height) or a blob (a stub 0.3 diameters long, 30–80 px), straight, at any
/// heading. It is kept only when its surface stays at least 4 px + 2 × (3.2 × noise + 1.5)
/// (room for both sides' outline spurs and bumps) from every limb, twig and earlier fragment,
/// so it is its own 8-connected component of the mask whatever the noise. At most 40 draws per
/// fragment; `tree` is that of the nearest limb.
inline void add_fragments(const tree_options& o, std::vector<limb_truth>& limbs) {
  if (o.fragments <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x165667b1u);
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  float x0 = std::numeric_limits<float>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const limb_truth& L : limbs) {
    if (L.kind == limb_kind::trunk || L.kind == limb_kind::twig || L.tree != 0) continue;
    for (const Eigen::Vector2f& p : L.centreline) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
  }
  if (!(x1 >= x0)) {  // a bare trunk: its top third
    const limb_truth& T = limbs[0];
    const Eigen::Vector2f a = truth_point_at(T, 0.67f * length_px(T)), b = T.centreline.back();
    x0 = std::min(a.x(), b.x()) - 0.5f * T.diameter_px.back() - 20.0f;
    x1 = std::max(a.x(), b.x()) + 0.5f * T.diameter_px.back() + 20.0f;
    y0 = std::min(a.y(), b.y());
    y1 = std::max(a.y(), b.y());
  }
  x0 = std::max(x0, 0.0f);
  y0 = std::max(y0, 0.0f);
  x1 = std::min(x1, static_cast<float>(o.width - 1));
  y1 = std::min(y1, static_cast<float>(o.height - 1));
  if (!(x1 >= x0 && y1 >= y0)) return;
  const float gap = 4.0f + 2.0f * (3.2f * std::max(o.noise, 0.0f) + 1.5f);
  const int wanted = std::min(o.fragments, 64);
  for (int k = 0, draws = 0; k < wanted && draws < 40 * wanted; ++draws) {
    const double cx = rng.uniform(static_cast<double>(x0), static_cast<double>(x1));
    const double cy = rng.uniform(static_cast<double>(y0), static_cast<double>(y1));
    const double shape = rng.uniform();
    const double heading = rng.uniform(-pi, pi);
    double d = 0.0, length = 0.0;
    if (shape < 0.45) {  // a stub
      d = rng.uniform(25.0, 90.0) * px_per_mm;
      length = d * rng.uniform(1.0, 4.0);
    } else if (shape < 0.8) {  // a stick
      d = rng.uniform(2.0, 6.0);
      length = static_cast<double>(o.height) * rng.uniform(0.03, 0.08);
    } else {  // a blob
      d = rng.uniform(30.0, 80.0);
      length = 0.3 * d;
    }
    double hs = 0.0, hc = 0.0;
    sin_cos(heading, hs, hc);
    limb_seed seed;
    seed.base = {cx - 0.5 * length * hs, cy + 0.5 * length * hc};
    seed.heading = heading;
    seed.length = std::max(length, 1.0);
    limb_truth f;
    f.parent = -1;
    f.kind = limb_kind::fragment;
    f.base_heading_rad = static_cast<float>(heading);
    f.exact_arc = true;
    sample_arc(seed, 0.0, std::max(1.0, std::min(0.375 * d, 16.0)), f);
    f.diameter_px.resize(f.centreline.size());
    for (std::size_t i = 0; i < f.centreline.size(); ++i)
      f.diameter_px[i] = static_cast<float>(d * (1.0 - 0.15 * static_cast<double>(f.arc_px[i]) /
                                                           static_cast<double>(f.arc_px.back())));
    // Detached: every point of its surface (its centreline every px, minus its radius) clears
    // every other piece by the gap.
    bool clear = true;
    float nearest = std::numeric_limits<float>::infinity();
    const float len = length_px(f);
    const int n = std::max(1, static_cast<int>(std::ceil(len)));
    for (std::size_t li = 0; li < limbs.size() && clear; ++li) {
      for (int i = 0; i <= n && clear; ++i) {
        const float s = len * static_cast<float>(i) / static_cast<float>(n);
        const float dist =
            surface_distance(limbs[li], truth_point_at(f, s)) - 0.5f * truth_diameter_at(f, s);
        clear = dist >= gap;
        if (dist < nearest && limbs[li].kind != limb_kind::fragment) {
          nearest = dist;
          f.tree = limbs[li].tree;
        }
      }
    }
    if (!clear) continue;
    limbs.push_back(std::move(f));
    ++k;
  }
}

/// Boundary noise: bumps (discs straddling the outline) and spurs (thin capsules sticking out).
inline void add_outline_noise(const tree_options& o, const std::vector<limb_truth>& limbs,
                              image_view<std::uint8_t> mask) {
  if (!(o.noise > 0.0f) || limbs.empty()) return;
  tree_random rng(o.seed ^ 0x85ebca6bu);
  const double a = static_cast<double>(o.noise);
  double outline = 0.0;
  std::vector<double> cumulative;
  for (const limb_truth& limb : limbs) {
    outline += limb.kind == limb_kind::twig ? 0.0 : 2.0 * static_cast<double>(length_px(limb));
    cumulative.push_back(outline);
  }
  const int count = static_cast<int>(outline / (6.0 * a + 10.0));
  for (int k = 0; k < count; ++k) {
    const double pick = rng.uniform() * outline;
    const auto li = static_cast<std::size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin());
    if (li >= limbs.size()) continue;
    const limb_truth& limb = limbs[li];
    const auto s = static_cast<float>(rng.uniform() * static_cast<double>(length_px(limb)));
    const Eigen::Vector2f c = truth_point_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const float side = static_cast<float>(rng.sign());
    const Eigen::Vector2f n(-t.y() * side, t.x() * side);
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f surface = c + r * n;
    const double kind = rng.uniform();
    if (kind < 0.75) {
      const auto rho = static_cast<float>(a * rng.uniform(0.5, 1.0));
      draw_disc(mask, surface + n * (rho * static_cast<float>(rng.uniform(0.0, 0.6))), rho);
    } else {
      const auto len = static_cast<float>(a * rng.uniform(1.5, 3.0));
      const Eigen::Vector2f dir = (n + t * static_cast<float>(rng.uniform(-0.6, 0.6))).normalized();
      draw_capsule(mask, surface - dir, surface + len * dir,
                   static_cast<float>(rng.uniform(0.8, 1.3)), 0.6f);
    }
  }
}

/// Occlusion holes: discs erased well inside thick limbs (the limb stays connected around them).
inline void add_holes(const tree_options& o, const std::vector<limb_truth>& limbs,
                      image_view<std::uint8_t> mask) {
  if (o.holes <= 0 || limbs.empty()) return;
  tree_random rng(o.seed ^ 0xc2b2ae35u);
  std::vector<std::size_t> thick;
  for (std::size_t i = 0; i < limbs.size(); ++i)
    if (limbs[i].kind != limb_kind::twig && limbs[i].diameter_px.back() >= 16.0f)
      thick.push_back(i);
  if (thick.empty()) return;
  for (int k = 0; k < o.holes; ++k) {
    const limb_truth& limb =
        limbs[thick[static_cast<std::size_t>(rng.integer(0, static_cast<int>(thick.size()) - 1))]];
    const auto s =
        static_cast<float>(rng.uniform(0.15, 0.85) * static_cast<double>(length_px(limb)));
    const float r = 0.5f * truth_diameter_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const Eigen::Vector2f n(-t.y(), t.x());
    const auto rho = static_cast<float>(rng.uniform(0.12, 0.25)) * r;
    const auto offset = static_cast<float>(rng.uniform(-0.3, 0.3)) * r;
    draw_disc(mask, truth_point_at(limb, s) + offset * n, rho, 0);
  }
}

}  // namespace detail

/// A segmenter's bias: every outline of `mask` moved out by `px` pixels (`px` > 0: the tree
/// grows by a disc of that radius, as an over-segmenting network draws it; `px` < 0: it shrinks,
/// as an under-segmenting one does). The truth stays the drawn geometry, so `perch eval
/// --outline-bias` asks how a rule's margins stand a mask whose widths are off by 2·`px`.
/// Complexity: O(pixels · px²).
inline void shift_outline(image<std::uint8_t>& mask, int px) {
  if (px == 0 || mask.width() <= 0 || mask.height() <= 0) return;
  const int w = mask.width(), h = mask.height(), r = std::abs(px);
  const std::uint8_t grown = px > 0 ? 255 : 0;  // the value a pixel takes near the other kind
  image<std::uint8_t> out = mask;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if ((mask(x, y) != 0) == (px > 0)) continue;  // already what the shift makes
      bool near = false;
      for (int dy = -r; dy <= r && !near; ++dy)
        for (int dx = -r; dx <= r && !near; ++dx) {
          const int u = x + dx, v = y + dy;
          if (dx * dx + dy * dy > r * r || u < 0 || v < 0 || u >= w || v >= h) continue;
          near = (mask(u, v) != 0) == (px > 0);
        }
      if (near) out(x, y) = grown;
    }
  mask = std::move(out);
}

/// A generator that rasterises limbs another way: every limb of `tree` (twigs and fragments
/// too) drawn with its radius `px` larger (`px` > 0, e.g. 0.5: a pixel counts when any of it is
/// covered rather than its centre) or smaller (`px` < 0), sub-pixel amounts included. The
/// outline noise, holes and the truth stay as they are: only the limbs' own outlines move (a
/// shell `|px|` thick is added to or removed from each; a piece thinner than `2·|px|` goes). Where `shift_outline` models a
/// segmenter's whole-pixel bias, this models the half-pixel ones of another drawing rule.
/// Complexity: O(Σ segment bounding boxes), three drawings of the tree.
inline void bias_radii(synthetic_tree& tree, float px) {
  if (px == 0.0f || !std::isfinite(px) || tree.mask.width() <= 0 || tree.mask.height() <= 0) return;
  auto draw_all = [&](image_view<std::uint8_t> into, float extra) {
    std::vector<float> radii;
    for (const limb_truth& limb : tree.limbs) {
      if (limb.centreline.empty() || limb.diameter_px.size() != limb.centreline.size()) continue;
      radii.resize(limb.diameter_px.size());
      for (std::size_t i = 0; i < radii.size(); ++i)
        radii[i] = 0.5f * limb.diameter_px[i] + extra;  // < 0: that piece is not drawn
      draw_polyline(into, limb.centreline, radii);
    }
  };
  if (px > 0.0f) {
    draw_all(tree.mask.view(), px);
    return;
  }
  image<std::uint8_t> drawn(tree.mask.width(), tree.mask.height(), 0);
  image<std::uint8_t> kept(tree.mask.width(), tree.mask.height(), 0);
  draw_all(drawn.view(), 0.0f);
  draw_all(kept.view(), px);
  for (int y = 0; y < tree.mask.height(); ++y)
    for (int x = 0; x < tree.mask.width(); ++x)
      if (drawn(x, y) != 0 && kept(x, y) == 0) tree.mask(x, y) = 0;
}

/// A segmenter's gaps: `count` breaks cut into the mask of `tree`, each across a limb of the
/// branching structure (trunk or limb, not a twig or fragment; at least 6 px wide at its base
/// and 4 px where it is cut) and 1–8 px long along it (drawn per gap): every other one at a random point of the limb's
/// middle three fifths (a leaf in front, a thin stretch lost), the others at a child's base,
/// where its whole width has just left its parent's outline (a child cut off at the
/// junction). The band erased is the limb's width and 4 px more on each side (the outline's
/// bumps), but no pixel inside another limb's drawn outline. The truth stays the drawn
/// geometry: the limb is still there and its pieces attached. Deterministic in `seed`.
/// Complexity: O(count × band pixels × nearby limbs' segments).
inline void cut_gaps(synthetic_tree& tree, int count, std::uint32_t seed) {
  std::vector<std::size_t> cut;  // limbs a gap may cross
  for (std::size_t i = 0; i < tree.limbs.size(); ++i) {
    const limb_truth& L = tree.limbs[i];
    if ((L.kind == limb_kind::trunk || L.kind == limb_kind::limb) && L.centreline.size() >= 2 &&
        L.diameter_px.size() == L.centreline.size() && L.diameter_px.front() >= 6.0f)
      cut.push_back(i);
  }
  if (count <= 0 || cut.empty()) return;
  detail::tree_random rng(seed ^ 0x9e3779b9u);
  for (int k = 0; k < count; ++k) {
    const limb_truth& L = tree.limbs[cut[static_cast<std::size_t>(rng.integer(0, static_cast<int>(cut.size()) - 1))]];
    const float length = length_px(L);
    const float gap = static_cast<float>(rng.integer(1, 8));
    float s = static_cast<float>(rng.uniform(0.2, 0.8)) * length;
    const bool at_base = k % 2 == 1 && L.parent >= 0;
    if (at_base) {  // where the child's whole width has left the parent's outline
      const limb_truth& P = tree.limbs[static_cast<std::size_t>(L.parent)];
      for (s = 0; s < length && detail::surface_distance(P, truth_point_at(L, s)) <
                                    0.5f * truth_diameter_at(L, s);
           s += 0.5f) {
      }
    }
    if (s + gap > length || truth_diameter_at(L, s) < 4.0f) continue;
    const Eigen::Vector2f c = truth_point_at(L, s + 0.5f * gap), t = truth_tangent_at(L, s);
    const float half_width = 0.5f * truth_diameter_at(L, s) + 4.0f;
    const float reach = std::hypot(0.5f * gap, half_width);
    const int x0 = std::max(0, static_cast<int>(std::floor(c.x() - reach)));
    const int x1 = std::min(tree.mask.width() - 1, static_cast<int>(std::ceil(c.x() + reach)));
    const int y0 = std::max(0, static_cast<int>(std::floor(c.y() - reach)));
    const int y1 = std::min(tree.mask.height() - 1, static_cast<int>(std::ceil(c.y() + reach)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2f d = Eigen::Vector2f(static_cast<float>(x), static_cast<float>(y)) - c;
        if (tree.mask(x, y) == 0 || std::abs(d.dot(t)) > 0.5f * gap ||
            std::abs(d.x() * t.y() - d.y() * t.x()) > half_width)
          continue;
        bool other = false;
        for (std::size_t j = 0; j < tree.limbs.size() && !other; ++j)
          other = &tree.limbs[j] != &L && !tree.limbs[j].centreline.empty() &&
                  detail::surface_distance(tree.limbs[j], c + d) <= 0.5f;
        if (!other) tree.mask(x, y) = 0;
      }
  }
}

/// Makes a synthetic tree (see the file comment). Limb 0 is the trunk; its bottom row is full
/// width (the trunk's base cap lies below the image). Limbs are grown breadth-first, so a
/// parent's index is below its children's. Order: the first tree, the second tree (`tree == 1`,
/// its trunk has parent -1, one level fewer), crossing limbs, twigs (`limb_kind::twig`), then
/// fragments (`limb_kind::fragment`, parent -1) last.
/// With `noise == 0`, `twigs == 0`, `holes == 0` each tree is one 8-connected component (every
/// limb starts on its parent's centreline, and only limbs whose base is inside the image are
/// grown); the two trees are separate components unless their limbs happen to touch. The new
/// options (`crossings`, `second_tree`, `perches`) off, the mask and truth are those of the
/// generator before they existed (pinned by the tests).
/// Invalid options (size < 1, scale or trunk diameter not positive and finite) give an empty
/// tree. Complexity: O(Σ segment bounding boxes); a 4000×3000 tree takes a few tens of ms.
[[nodiscard]] inline synthetic_tree make_tree(const tree_options& options) {
  synthetic_tree tree;
  tree.mm_per_px = options.mm_per_px;
  const bool valid =
      options.width >= 1 && options.height >= 1 &&
      static_cast<std::int64_t>(options.width) * options.height <= max_image_pixels &&
      std::isfinite(options.mm_per_px) && options.mm_per_px > 0.0f &&
      std::isfinite(options.trunk_diameter_mm) && options.trunk_diameter_mm > 0.0f &&
      std::isfinite(options.min_diameter_mm) && std::isfinite(options.noise) &&
      std::isfinite(options.second_tree);
  if (!valid) return tree;
  tree.mask = image<std::uint8_t>(options.width, options.height, 0);
  detail::grow_tree(options, tree.limbs);
  detail::add_second_tree(options, tree.limbs);
  detail::add_crossings(options, tree.limbs);
  detail::add_twigs(options, tree.limbs);
  detail::add_fragments(options, tree.limbs);
  for (const limb_truth& limb : tree.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    draw_polyline(tree.mask, limb.centreline, radii);
  }
  detail::add_outline_noise(options, tree.limbs, tree.mask);
  detail::add_holes(options, tree.limbs, tree.mask);
  return tree;
}

/// The options of `benchmark_tree`: a fixed seed (23: a tree that offers the tendon claw safe
/// perches at most sizes, so that a benchmark times the clearance queries of the ranking too),
/// the trunk 4.5 % of the image width (180 mm trunk, mm_per_px = 180 / (0.045·width)); `noisy`
/// adds outline noise of 1 + 0.0016·width px, 24 twigs and 3 holes to the same tree.
[[nodiscard]] inline tree_options benchmark_tree_options(int width, int height, tree_noise noise) {
  tree_options o;
  o.width = width;
  o.height = height;
  o.seed = 23;
  o.trunk_diameter_mm = 180.0f;
  o.mm_per_px = width > 0 ? 180.0f / (0.045f * static_cast<float>(width)) : 1.0f;
  if (noise == tree_noise::noisy) {
    o.noise = 1.0f + 0.0016f * static_cast<float>(width);
    o.twigs = 24;
    o.holes = 3;
  }
  return o;
}

/// The benchmark masks of issue 8 (640×480, 1920×1080, 4000×3000, clean and noisy): see
/// `benchmark_tree_options`. The clean and noisy trees share their limbs.
[[nodiscard]] inline synthetic_tree benchmark_tree(int width, int height, tree_noise noise) {
  return make_tree(benchmark_tree_options(width, height, noise));
}


// ------------------------------------------------------------------------------------------------
// Where a claw could perch: the truth
// ------------------------------------------------------------------------------------------------

/// The perching mechanism the truth is computed for. Defaults: the tendon-driven claw of Li et
/// al. 2025 as the PLI paper uses it (`perch::tendon_claw`): a 180 mm wide drone, a 70 mm claw
/// grasping 30–110 mm, on branches at most 35° from horizontal that bend by at most 20° over the
/// drone's width, with 70 mm of free space around the limb for the claw's fingers and the
/// drone's body; 1.5 kg, eq. 4 stress at most 27 MPa / 2.
struct claw_spec {
  float drone_width_mm = 180.0f;   ///< window length along the limb (arc length)
  float claw_mm = 70.0f;           ///< central region whose mean diameter the claw grasps
  float diameter_min_mm = 30.0f;   ///< the claw closes no tighter
  float diameter_max_mm = 110.0f;  ///< the claw opens no wider
  /// The claw diameter, in px, may be off by this much (a segmenter's or the distance map's
  /// one-pixel error) and must still be in range: a limb at the edge of the range, a few px
  /// wide, is no safe grasp however its truth diameter falls.
  float resolution_px = 1.0f;
  /// The local tangent at every point under the window, to the horizontal (image rows),
  /// folded into [0, 90]: the claw slides off steeper limbs.
  float max_slope_deg = 35.0f;
  /// The tangents one window length apart, anywhere under the window, differ by at most this:
  /// the drone's body and the claw's fingers need a limb that is straight over the drone's
  /// width (a kink or a tight bend under it tilts the drone or opens the grasp).
  float max_bend_deg = 20.0f;
  /// Limbs thinner than this everywhere are twigs (never perches: they would not hold the
  /// drone); the parts of other limbs thinner than this are no obstacle to the claw (leaves and
  /// twigs give way).
  float twig_max_mm = 20.0f;
  /// The free space the claw's fingers and the drone need around the grasped limb: surface to
  /// surface, to every other limb at least `twig_max_mm` thick there.
  float clearance_mm = 70.0f;
  /// The limb's surface under the window stays this far inside the image: a limb cut by the
  /// edge (or touching it) may go on beyond it, out of sight.
  float border_margin_px = 3.0f;
  float mass_kg = 1.5f;          ///< for the bending stress (paper eq. 4)
  float max_stress_mpa = 13.5f;  ///< modulus of rupture 27 MPa / safety factor 2
  float step_px = 1.0f;          ///< spacing of the window centres examined
  /// The camera's roll, degrees, as `perch::attitude::roll_deg` (the true horizon runs this far
  /// from the image's +x toward +y): rule 7's slopes and rule 9's lever are measured against
  /// the true horizontal. 0: image rows are horizontal.
  float roll_deg = 0.0f;
};

/// A stretch of a limb where the claw can perch: every window of one drone width whose centre
/// lies in [arc_begin_px + w/2, arc_end_px − w/2] (w = drone width in px) is feasible, so the
/// stretch itself spans those windows, end to end. Arc positions along `limb`'s centreline.
struct feasible_stretch {
  int limb = -1;
  float arc_begin_px = 0.0f;
  float arc_end_px = 0.0f;
};

/// Why a window is not a perch (the first rule it breaks, in this order), or that it is one.
/// See `perch_truth` for the rules.
enum class window_verdict : std::uint8_t {
  feasible,
  twig,           ///< rule 1: a twig (by kind, or thinner than `twig_max_mm` everywhere)
  off_limb,       ///< rule 0: the window runs past the limb's base or tip
  unsupported,    ///< rule 2: a fragment, or a limb of one: not attached to a grounded tree
  outside_image,  ///< rule 3: the limb under the window is outside the image or its margin
  clearance,      ///< rule 4: another limb's surface is nearer than `clearance_mm`
  diameter,       ///< rule 5: claw-region mean diameter out of range
  resolution,     ///< rule 6: that diameter ± `resolution_px` leaves the range
  slope,          ///< rule 7: the limb is steeper than `max_slope_deg` somewhere under it
  bend,           ///< rule 8: the limb bends more than `max_bend_deg` over a window length
  bending,        ///< rule 9: bending stress (eq. 4) above `max_stress_mpa`
};

[[nodiscard]] constexpr const char* to_string(window_verdict v) noexcept {
  switch (v) {
    case window_verdict::feasible: return "feasible";
    case window_verdict::twig: return "twig";
    case window_verdict::off_limb: return "off_limb";
    case window_verdict::unsupported:
      return "unsupported";
    case window_verdict::outside_image: return "outside_image";
    case window_verdict::clearance:
      return "clearance";
    case window_verdict::diameter: return "diameter";
    case window_verdict::resolution:
      return "resolution";
    case window_verdict::slope: return "slope";
    case window_verdict::bend:
      return "bend";
    case window_verdict::bending: return "bending";
  }
  return "unknown";
}

/// The truth about one window. Every measure is filled whatever the verdict (for a window that
/// runs off its limb, over the part on the limb).
struct window_truth {
  window_verdict verdict = window_verdict::off_limb;
  int limb = -1;
  float centre_arc_px = 0.0f;
  float claw_diameter_mm = 0.0f;  ///< mean truth diameter over the central claw region
  float slope_deg = 0.0f;         ///< steepest local tangent under the window, folded [0, 90]
  float bend_deg = 0.0f;          ///< largest tangent change over one window length under it
  /// The smallest surface-to-surface gap, mm, between this limb under the window and another
  /// obstacle limb (rule 4: |p − q| − r_B(q) − r(p)); negative inside another limb (the window
  /// reaches into its parent or over a child's base). Exact below 2 × `clearance_mm`; farther
  /// limbs are not searched: +∞ when none is that near.
  float clearance_mm = std::numeric_limits<float>::infinity();
  /// The smallest distance, px, from the limb's surface under the window to an image edge.
  float border_px = 0.0f;
  float curvature_per_mm = 0.0f;  ///< information: the limb's mean |κ| (`curvature_per_px`)
  float stress_mpa = 0.0f;        ///< eq. 4 with the claw radius and the lever from the limb base
};

/// The nearest feasible window centre to a point.
struct site_match {
  int limb = -1;  ///< -1: the tree has no feasible stretch
  float arc_px = 0.0f;
  float distance_px = std::numeric_limits<float>::infinity();
};

/// Where a claw could perch on a synthetic tree, from its drawn geometry (the limbs'
/// centrelines, per-vertex diameters and the scale; never from the mask, so noise, holes and
/// rasterisation do not move it): the physical definition the pipeline is judged by.
///
/// A window is `drone_width_mm` of arc (W px) along a limb's truth centreline, centred at arc
/// position c, spanning [s0, s1] = [c − W/2, c + W/2]. "Every point under the window" means the
/// centreline points at arcs in [s0, s1], sampled at most 0.5 px apart with both ends included;
/// r(p) is the limb's radius there (linear between vertices, as drawn). It is feasible when all
/// of these hold (the first rule broken names the verdict, in the order twig, off_limb,
/// unsupported, outside_image, clearance, diameter, resolution, slope, bend, bending):
///  0. `off_limb`: it lies on the limb, [s0, s1] ⊂ [0, length];
///  1. `twig`: the limb is no twig: not of kind `twig`, and at least `twig_max_mm` thick
///     somewhere;
///  2. `unsupported`: the limb is attached to a grounded tree: it is no `fragment`, nor is any
///     ancestor (via `parent`). Trunks (the second tree's too) are grounded;
///  3. `outside_image` (border): every point under the window is at least r(p) +
///     `border_margin_px` from every image edge (pixel centres at integer coordinates: the image
///     spans [0, w − 1] × [0, h − 1]). A limb cut by the edge may go on, out of sight;
///  4. `clearance`: every point p under the window is at least r(p) + `clearance_mm` (in px)
///     from the surface of every obstacle: every other limb B (of either tree, fragments too)
///     that is not a twig by kind and not hidden (see below), where B is at least
///     `twig_max_mm` thick. For each segment of B's tapered-capsule polyline (its part at least
///     that thick), the surface distance is |p − q| − r_B(q), q the closest point of the segment
///     and r_B interpolated there. A limb's base lies on its parent's axis (so it is drawn), so
///     this one rule covers what junction rules used to: a window near its own base is inside its
///     parent (negative distance), a window over a child's base, a fork, a sibling, a crossing
///     limb, the other tree or a fragment too close all fail. Twigs and thin limbs are clutter
///     the claw pushes aside. A hidden limb lies wholly inside one other limb (within half a
///     pixel), adds no pixel to the mask and is no obstacle (the generator can grow a thin side
///     limb almost along its parent);
///  5. `diameter`: the mean truth diameter over the central `claw_mm` in
///     [diameter_min_mm, diameter_max_mm];
///  6. `resolution`: that diameter d in px, d − `resolution_px` ≥ diameter_min_mm / mm_per_px
///     and d + `resolution_px` ≤ diameter_max_mm / mm_per_px: a pixel of error must not take
///     the grasp out of range;
///  7. `slope`: at every point under the window the local tangent of the centreline (the
///     direction of the polyline segment holding it; at a vertex both adjacent segments) is at
///     most `max_slope_deg` from horizontal (folded into [0°, 90°], image rows horizontal unless
///     `claw_spec::roll_deg` says otherwise);
///  8. `bend`: for every s in [s0, s1], the tangents at max(s − W/2, 0) and min(s + W/2,
///     length) differ by at most `max_bend_deg` (a tangent here is the chord over ±1 px of arc,
///     so a vertex of a finely sampled polyline is not a kink, a real kink is);
///  9. `bending` (paper eq. 4): σ = 4·m·g·L/(π·r³) ≤ `max_stress_mpa`, r the claw-region radius,
///     L the horizontal distance from the limb's base (where it leaves its parent: the real
///     cantilever root) to the window centre.
/// Curvature is reported (`curvature_per_mm`, the limb's mean) but not judged: the bend rule
/// bounds what matters over the drone's width. Monotonicity is not checked.
///
/// Windows are examined every `step_px` of arc; consecutive feasible centres form a
/// `feasible_stretch`. A site p (a pixel the pipeline reports as a window centre) is feasible
/// when it lies within a tolerance of the centreline of a stretch trimmed by W/2 at each end,
/// i.e. of a feasible window centre.
///
/// Keeps a pointer to `tree`: the tree must outlive this object. Host code; allocates.
/// Complexity: per limb, its points every 0.5 px against the obstacle segments whose boxes come
/// near it (clearance, border and bend precomputed there), then O(W) per window: a few ms for a
/// 960×720 tree.
class perch_truth {
 public:
  explicit perch_truth(const synthetic_tree& tree, const claw_spec& spec = {})
      : tree_(&tree), spec_(spec) {
    mmpp_ = tree.mm_per_px > 0.0f ? tree.mm_per_px : 1.0f;
    window_px_ = spec.drone_width_mm / mmpp_;
    claw_half_px_ = 0.5f * spec.claw_mm / mmpp_;
    clearance_px_ = spec.clearance_mm / mmpp_;
    thick_px_ = spec.twig_max_mm / mmpp_;
    build_support();
    build_obstacles();
    build_profiles();
    build_stretches();
  }

  [[nodiscard]] const claw_spec& spec() const noexcept { return spec_; }
  /// The window length, px of arc.
  [[nodiscard]] float window_px() const noexcept { return window_px_; }
  /// Every feasible stretch, by limb then arc.
  [[nodiscard]] const std::vector<feasible_stretch>& stretches() const noexcept {
    return stretches_;
  }
  /// Whether the claw can perch anywhere on the tree.
  [[nodiscard]] bool has_perch() const noexcept { return !stretches_.empty(); }

  /// The window of `limb` centred at arc `centre_arc_px`, judged by the rules above.
  [[nodiscard]] window_truth window(int limb, float centre_arc_px) const {
    window_truth out;
    out.limb = limb;
    out.centre_arc_px = centre_arc_px;
    if (limb < 0 || static_cast<std::size_t>(limb) >= tree_->limbs.size()) return out;
    const auto li = static_cast<std::size_t>(limb);
    const limb_truth& L = tree_->limbs[li];
    if (L.centreline.size() < 2 || L.diameter_px.size() != L.centreline.size() ||
        L.arc_px.size() != L.centreline.size())
      return out;
    const float len = length_px(L);
    const float half = 0.5f * window_px_;
    const float s0 = centre_arc_px - half, s1 = centre_arc_px + half;
    const float c0 = std::clamp(s0, 0.0f, len), c1 = std::clamp(s1, 0.0f, len);
    // Measures (over the part of the window on the limb).
    double dsum = 0.0;
    int dn = 0;
    for (float u = -claw_half_px_; u <= claw_half_px_ + 1e-3f; u += 0.5f, ++dn)
      dsum += static_cast<double>(truth_diameter_at(L, centre_arc_px + u));
    out.claw_diameter_mm = static_cast<float>(dsum / std::max(dn, 1)) * mmpp_;
    out.slope_deg = max_slope_deg(L, c0, c1);
    const profile& pr = profiles_[li];
    out.clearance_mm = clearance_gap_px(li, c0);
    out.border_px = border_px(L, c0);
    out.bend_deg = bend_deg(L, c0);
    out.clearance_mm = std::min(out.clearance_mm, clearance_gap_px(li, c1));
    out.border_px = std::min(out.border_px, border_px(L, c1));
    out.bend_deg = std::max(out.bend_deg, bend_deg(L, c1));
    if (pr.step > 0.0f) {
      const auto last = static_cast<std::ptrdiff_t>(pr.gap.size()) - 1;
      const auto k0 =
          std::max<std::ptrdiff_t>(0, static_cast<std::ptrdiff_t>(std::ceil(c0 / pr.step)));
      const auto k1 =
          std::min<std::ptrdiff_t>(last, static_cast<std::ptrdiff_t>(std::floor(c1 / pr.step)));
      for (std::ptrdiff_t k = k0; k <= k1; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        out.clearance_mm = std::min(out.clearance_mm, pr.gap[uk]);
        out.border_px = std::min(out.border_px, pr.border[uk]);
        out.bend_deg = std::max(out.bend_deg, pr.bend[uk]);
      }
    }
    out.clearance_mm *= mmpp_;  // px → mm (∞ stays ∞)
    out.curvature_per_mm = std::abs(L.curvature_per_px) / mmpp_;
    const float lever_mm =
        std::abs((truth_point_at(L, centre_arc_px) - L.centreline.front()).dot(horizon())) * mmpp_;
    const float r_m = 0.5f * out.claw_diameter_mm / 1000.0f;
    out.stress_mpa = r_m > 0.0f ? 4.0f * spec_.mass_kg * 9.80665f * (lever_mm / 1000.0f) /
                                      (static_cast<float>(detail::pi) * r_m * r_m * r_m) / 1.0e6f
                                : std::numeric_limits<float>::infinity();
    // Rules, in order.
    auto verdict = [&]() {
      if (is_twig_[li] != 0) return window_verdict::twig;
      if (s0 < 0.0f || s1 > len) return window_verdict::off_limb;
      if (supported_[li] == 0) return window_verdict::unsupported;
      if (!(out.border_px >= spec_.border_margin_px)) return window_verdict::outside_image;
      if (!(out.clearance_mm >= spec_.clearance_mm)) return window_verdict::clearance;
      if (!(out.claw_diameter_mm >= spec_.diameter_min_mm &&
            out.claw_diameter_mm <= spec_.diameter_max_mm))
        return window_verdict::diameter;
      const float d_px = out.claw_diameter_mm / mmpp_;
      if (!(d_px - spec_.resolution_px >= spec_.diameter_min_mm / mmpp_ &&
            d_px + spec_.resolution_px <= spec_.diameter_max_mm / mmpp_))
        return window_verdict::resolution;
      if (!(out.slope_deg <= spec_.max_slope_deg)) return window_verdict::slope;
      if (!(out.bend_deg <= spec_.max_bend_deg)) return window_verdict::bend;
      if (!(out.stress_mpa <= spec_.max_stress_mpa)) return window_verdict::bending;
      return window_verdict::feasible;
    };
    out.verdict = verdict();
    return out;
  }

  /// The feasible window centre nearest to `p` (over every stretch).
  [[nodiscard]] site_match nearest_site(Eigen::Vector2f p) const {
    site_match best;
    const float half = 0.5f * window_px_;
    for (const feasible_stretch& st : stretches_) {
      const limb_truth& L = tree_->limbs[static_cast<std::size_t>(st.limb)];
      const float lo = st.arc_begin_px + half, hi = st.arc_end_px - half;
      // Walk the centreline between lo and hi in steps ≤ 0.5 px, projecting on each piece.
      const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / 0.5f)));
      Eigen::Vector2f prev = truth_point_at(L, lo);
      float prev_s = lo;
      auto consider = [&](Eigen::Vector2f q0, Eigen::Vector2f q1, float a0, float a1) {
        const Eigen::Vector2f d = q1 - q0;
        const float len2 = d.squaredNorm();
        const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
        const float dist = (p - (q0 + t * d)).norm();
        if (dist < best.distance_px) {
          best.distance_px = dist;
          best.limb = st.limb;
          best.arc_px = a0 + t * (a1 - a0);
        }
      };
      consider(prev, prev, lo, lo);
      for (int i = 1; i <= n; ++i) {
        const float s = lo + (hi - lo) * static_cast<float>(i) / static_cast<float>(n);
        const Eigen::Vector2f q = truth_point_at(L, s);
        consider(prev, q, prev_s, s);
        prev = q;
        prev_s = s;
      }
    }
    return best;
  }

  /// Whether `p` is within `tolerance_px` of a feasible window centre.
  [[nodiscard]] bool is_feasible_site(Eigen::Vector2f p, float tolerance_px) const {
    return nearest_site(p).distance_px <= tolerance_px;
  }

 private:
  struct box {
    float x0 = std::numeric_limits<float>::infinity(), y0 = x0;
    float x1 = -std::numeric_limits<float>::infinity(), y1 = x1;
    void add(Eigen::Vector2f p, float r) noexcept {
      x0 = std::min(x0, p.x() - r);
      y0 = std::min(y0, p.y() - r);
      x1 = std::max(x1, p.x() + r);
      y1 = std::max(y1, p.y() + r);
    }
    /// Whether the box comes within `reach` of point p (in x and in y).
    [[nodiscard]] bool near(Eigen::Vector2f p, float reach) const noexcept {
      return p.x() + reach >= x0 && p.x() - reach <= x1 && p.y() + reach >= y0 &&
             p.y() - reach <= y1;
    }
    [[nodiscard]] bool overlaps(const box& o, float reach) const noexcept {
      return x1 + reach >= o.x0 && o.x1 + reach >= x0 && y1 + reach >= o.y0 && o.y1 + reach >= y0;
    }
  };

  /// The part of an obstacle segment at least `twig_max_mm` thick: a tapered capsule.
  struct obstacle {
    Eigen::Vector2f a, b;
    float ra, rb;
    std::size_t limb;
    box bounds;
  };

  /// Per limb, on a grid of arcs k·step (k = 0 … n, step ≤ 0.5 px): the clearance gap and the
  /// border distance (px) and the bend (deg) there.
  struct profile {
    float step = 0.0f;
    std::vector<float> gap, border, bend;
    std::vector<std::size_t> near;  ///< obstacles whose boxes come within reach of the limb
    /// Per run of `run_points` points (from point 0): the obstacles of `near` within reach of
    /// the run's box grown by a pixel, so of any arc position within a step of the run.
    std::vector<std::vector<std::size_t>> near_run;
    static constexpr int run_points = 32;
  };

  [[nodiscard]] static bool well_formed(const limb_truth& L) noexcept {
    return L.centreline.size() >= 2 && L.diameter_px.size() == L.centreline.size() &&
           L.arc_px.size() == L.centreline.size();
  }

  /// Rules 1 and 2 per limb.
  void build_support() {
    const auto& limbs = tree_->limbs;
    is_twig_.assign(limbs.size(), 0);
    supported_.assign(limbs.size(), 1);
    for (std::size_t i = 0; i < limbs.size(); ++i) {
      const limb_truth& L = limbs[i];
      float d_max = 0.0f;
      for (const float d : L.diameter_px) d_max = std::max(d_max, d);
      is_twig_[i] = L.kind == limb_kind::twig || !(d_max >= thick_px_) ? 1 : 0;
      // Walk up the parents (at most limbs.size() steps: a malformed cycle ends the walk).
      int at = static_cast<int>(i);
      for (std::size_t steps = 0;
           at >= 0 && static_cast<std::size_t>(at) < limbs.size() && steps <= limbs.size();
           ++steps) {
        if (limbs[static_cast<std::size_t>(at)].kind == limb_kind::fragment) {
          supported_[i] = 0;
          break;
        }
        at = limbs[static_cast<std::size_t>(at)].parent;
      }
    }
  }

  /// Whether limb `bi` lies wholly inside another limb (within half a pixel): it is not in the
  /// mask at all, adds no pixel, and is no obstacle.
  [[nodiscard]] bool hidden(std::size_t bi, const std::vector<box>& boxes) const {
    const auto& limbs = tree_->limbs;
    const limb_truth& B = limbs[bi];
    const float len = length_px(B);
    const int n = std::max(1, static_cast<int>(std::ceil(len)));
    for (std::size_t ci = 0; ci < limbs.size(); ++ci) {
      const limb_truth& C = limbs[ci];
      if (ci == bi || C.kind == limb_kind::twig || !well_formed(C)) continue;
      if (boxes[ci].x0 > boxes[bi].x0 + 0.5f || boxes[ci].y0 > boxes[bi].y0 + 0.5f ||
          boxes[ci].x1 < boxes[bi].x1 - 0.5f || boxes[ci].y1 < boxes[bi].y1 - 0.5f)
        continue;  // B's box is not inside C's: B cannot be inside C
      bool inside = true;
      for (int i = 0; i <= n && inside; ++i) {
        const float s = len * static_cast<float>(i) / static_cast<float>(n);
        const Eigen::Vector2f p = truth_point_at(B, s);
        const float rb = 0.5f * truth_diameter_at(B, s);
        bool in = false;
        for (std::size_t k = 0; k + 1 < C.centreline.size() && !in; ++k) {
          const Eigen::Vector2f q0 = C.centreline[k];
          const Eigen::Vector2f d = C.centreline[k + 1] - q0;
          const float len2 = d.squaredNorm();
          const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
          const float rc =
              0.5f * (C.diameter_px[k] + t * (C.diameter_px[k + 1] - C.diameter_px[k]));
          in = (p - (q0 + t * d)).norm() + rb <= rc + 0.5f;
        }
        inside = in;
      }
      if (inside) return true;
    }
    return false;
  }

  /// The obstacles of rule 4: the parts at least `twig_max_mm` thick of the segments of every
  /// limb that is not a twig by kind and not hidden.
  void build_obstacles() {
    const auto& limbs = tree_->limbs;
    boxes_.assign(limbs.size(), box{});
    for (std::size_t i = 0; i < limbs.size(); ++i)
      if (well_formed(limbs[i]))
        for (std::size_t k = 0; k < limbs[i].centreline.size(); ++k)
          boxes_[i].add(limbs[i].centreline[k], 0.5f * limbs[i].diameter_px[k]);
    for (std::size_t bi = 0; bi < limbs.size(); ++bi) {
      const limb_truth& B = limbs[bi];
      if (B.kind == limb_kind::twig || !well_formed(B) || hidden(bi, boxes_)) continue;
      for (std::size_t k = 0; k + 1 < B.centreline.size(); ++k) {
        float t0 = 0.0f, t1 = 1.0f;
        const float d0 = B.diameter_px[k], d1 = B.diameter_px[k + 1];
        if (!(d0 >= thick_px_) && !(d1 >= thick_px_)) continue;
        if (!(d0 >= thick_px_)) t0 = (thick_px_ - d0) / (d1 - d0);
        if (!(d1 >= thick_px_)) t1 = (thick_px_ - d0) / (d1 - d0);
        const Eigen::Vector2f p0 = B.centreline[k], dp = B.centreline[k + 1] - p0;
        obstacle ob;
        ob.a = p0 + t0 * dp;
        ob.b = p0 + t1 * dp;
        ob.ra = 0.5f * (d0 + t0 * (d1 - d0));
        ob.rb = 0.5f * (d0 + t1 * (d1 - d0));
        ob.limb = bi;
        ob.bounds.add(ob.a, ob.ra);
        ob.bounds.add(ob.b, ob.rb);
        obstacles_.push_back(ob);
      }
    }
  }

  /// Rule 4 at arc s of limb li: the smallest |p − q| − r_B(q) − r(p), px, over the obstacles
  /// of other limbs within reach (∞ when none).
  [[nodiscard]] float clearance_gap_px(std::size_t li, float s) const {
    const profile& pr = profiles_[li];
    if (pr.near_run.empty() || !(pr.step > 0.0f)) return clearance_gap_px(li, s, pr.near);
    const auto k = static_cast<std::ptrdiff_t>(std::floor(s / pr.step + 0.5f)) / profile::run_points;
    const auto last = static_cast<std::ptrdiff_t>(pr.near_run.size()) - 1;
    return clearance_gap_px(li, s, pr.near_run[static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k, 0, last))]);
  }
  /// The same, searching only `candidates` (obstacle indices that include every one in reach).
  [[nodiscard]] float clearance_gap_px(std::size_t li, float s,
                                       const std::vector<std::size_t>& candidates) const {
    const limb_truth& L = tree_->limbs[li];
    const Eigen::Vector2f p = truth_point_at(L, s);
    const float r = 0.5f * truth_diameter_at(L, s);
    const float reach = r + 2.0f * clearance_px_;
    float best = std::numeric_limits<float>::infinity();
    for (const std::size_t oi : candidates) {
      const obstacle& ob = obstacles_[oi];
      if (!ob.bounds.near(p, reach)) continue;
      const Eigen::Vector2f d = ob.b - ob.a;
      const float len2 = d.squaredNorm();
      const float t = len2 > 0.0f ? std::clamp((p - ob.a).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
      const float gap = (p - (ob.a + t * d)).norm() - (ob.ra + t * (ob.rb - ob.ra)) - r;
      best = std::min(best, gap);
    }
    return best;
  }

  /// Rule 3 at arc s: the distance from the limb's surface to the nearest image edge, px.
  [[nodiscard]] float border_px(const limb_truth& L, float s) const {
    const Eigen::Vector2f q = truth_point_at(L, s);
    const auto W = static_cast<float>(tree_->mask.width() - 1);
    const auto H = static_cast<float>(tree_->mask.height() - 1);
    return std::min({q.x(), q.y(), W - q.x(), H - q.y()}) - 0.5f * truth_diameter_at(L, s);
  }

  /// The tangent at arc s: the chord over ±1 px of arc (clamped to the limb).
  [[nodiscard]] static Eigen::Vector2d chord_tangent(const limb_truth& L, float s) {
    const float len = length_px(L);
    const Eigen::Vector2f d =
        truth_point_at(L, std::min(s + 1.0f, len)) - truth_point_at(L, std::max(s - 1.0f, 0.0f));
    return {static_cast<double>(d.x()), static_cast<double>(d.y())};
  }

  /// The angle between two directions, degrees (0 when one is degenerate).
  [[nodiscard]] static float angle_deg(const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    const double cross = u.x() * v.y() - u.y() * v.x();
    const double dot = u.dot(v);
    if (cross == 0.0 && dot == 0.0) return 0.0f;
    return static_cast<float>(std::atan2(std::abs(cross), dot) * (180.0 / detail::pi));
  }

  /// Rule 8 at arc s: the angle between the tangents at max(s − W/2, 0) and min(s + W/2, len).
  [[nodiscard]] float bend_deg(const limb_truth& L, float s) const {
    const float half = 0.5f * window_px_;
    return angle_deg(chord_tangent(L, std::max(s - half, 0.0f)),
                     chord_tangent(L, std::min(s + half, length_px(L))));
  }

  /// Rule 7 over arcs [a, b]: the steepest polyline segment overlapping it, deg in [0, 90].
  [[nodiscard]] float max_slope_deg(const limb_truth& L, float a, float b) const {
    const Eigen::Vector2f h = horizon();
    float t = 0.0f;
    std::size_t i = detail::segment_at(L, a, t);
    // At a vertex exactly at a, the segment before it counts too.
    if (i > 0 && L.arc_px[i] >= a) --i;
    float worst = 0.0f;
    for (; i + 1 < L.centreline.size() && L.arc_px[i] <= b; ++i) {
      const Eigen::Vector2f d = L.centreline[i + 1] - L.centreline[i];
      if (!(d.squaredNorm() > 0.0f)) continue;
      const double across = static_cast<double>(h.x() * d.y() - h.y() * d.x());
      const double along = static_cast<double>(h.x() * d.x() + h.y() * d.y());
      worst = std::max(worst, static_cast<float>(std::atan2(std::abs(across), std::abs(along)) *
                                                 (180.0 / detail::pi)));
    }
    return worst;
  }

  /// The true horizontal in the image (unit; (1, 0) without roll).
  [[nodiscard]] Eigen::Vector2f horizon() const noexcept {
    if (spec_.roll_deg == 0.0f) return {1.0f, 0.0f};
    double sn = 0.0, cs = 1.0;
    detail::sin_cos(static_cast<double>(spec_.roll_deg) * (detail::pi / 180.0), sn, cs);
    return {static_cast<float>(cs), static_cast<float>(sn)};
  }

  /// The per-limb grids of rules 3, 4 and 8.
  void build_profiles() {
    const auto& limbs = tree_->limbs;
    profiles_.assign(limbs.size(), profile{});
    for (std::size_t li = 0; li < limbs.size(); ++li) {
      const limb_truth& L = limbs[li];
      if (!well_formed(L)) continue;
      profile& pr = profiles_[li];
      float r_max = 0.0f;
      for (const float d : L.diameter_px) r_max = std::max(r_max, 0.5f * d);
      const float reach = r_max + 2.0f * clearance_px_;
      for (std::size_t oi = 0; oi < obstacles_.size(); ++oi)
        if (obstacles_[oi].limb != li && obstacles_[oi].bounds.overlaps(boxes_[li], reach))
          pr.near.push_back(oi);
      const float len = length_px(L);
      const int n = std::max(1, static_cast<int>(std::ceil(len / 0.5f)));
      pr.step = len / static_cast<float>(n);
      pr.gap.resize(static_cast<std::size_t>(n) + 1);
      pr.border.resize(pr.gap.size());
      pr.bend.resize(pr.gap.size());
      // The points in runs, each run searching only the obstacles near its box (the same gaps
      // as searching `near`, far fewer tests on a long limb in a dense crown).
      for (int k0 = 0; k0 <= n; k0 += profile::run_points) {
        const int k1 = std::min(n, k0 + profile::run_points - 1);
        box run;
        float run_r = 0.0f;
        for (int k = k0; k <= k1; ++k) {
          const float s = std::min(pr.step * static_cast<float>(k), len);
          const float r = 0.5f * truth_diameter_at(L, s);
          run.add(truth_point_at(L, s), r);
          run_r = std::max(run_r, r);
        }
        std::vector<std::size_t>& local = pr.near_run.emplace_back();
        for (const std::size_t oi : pr.near)
          if (obstacles_[oi].bounds.overlaps(run, run_r + 1.0f + 2.0f * clearance_px_))
            local.push_back(oi);
        for (int k = k0; k <= k1; ++k) {
          const float s = std::min(pr.step * static_cast<float>(k), len);
          const auto uk = static_cast<std::size_t>(k);
          pr.gap[uk] = clearance_gap_px(li, s, local);
          pr.border[uk] = border_px(L, s);
          pr.bend[uk] = bend_deg(L, s);
        }
      }
    }
  }

  void build_stretches() {
    const float half = 0.5f * window_px_;
    const float step = spec_.step_px > 0.05f ? spec_.step_px : 0.05f;
    for (std::size_t li = 0; li < tree_->limbs.size(); ++li) {
      const limb_truth& L = tree_->limbs[li];
      if (is_twig_[li] != 0 || supported_[li] == 0 || !well_formed(L)) continue;
      const float len = length_px(L);
      if (len < window_px_) continue;
      const int n = static_cast<int>(std::floor((len - window_px_) / step));
      float run_first = -1.0f, run_last = -1.0f;
      auto close_run = [&]() {
        if (run_first >= 0.0f)
          stretches_.push_back({static_cast<int>(li), run_first - half, run_last + half});
        run_first = run_last = -1.0f;
      };
      for (int i = 0; i <= n; ++i) {
        const float c = half + static_cast<float>(i) * step;
        if (window(static_cast<int>(li), c).verdict == window_verdict::feasible) {
          if (run_first < 0.0f) run_first = c;
          run_last = c;
        } else {
          close_run();
        }
      }
      close_run();
    }
  }

  const synthetic_tree* tree_;
  claw_spec spec_;
  float mmpp_ = 1.0f;
  float window_px_ = 0.0f;
  float claw_half_px_ = 0.0f;
  float clearance_px_ = 0.0f;
  float thick_px_ = 0.0f;
  std::vector<std::uint8_t> is_twig_;    ///< rule 1 per limb
  std::vector<std::uint8_t> supported_;  ///< rule 2 per limb
  std::vector<box> boxes_;               ///< per limb, with its radii
  std::vector<obstacle> obstacles_;
  std::vector<profile> profiles_;
  std::vector<feasible_stretch> stretches_;
};

/// The feasible stretches of `tree` for `spec` (see `perch_truth` for the rules).
[[nodiscard]] inline std::vector<feasible_stretch> feasible_stretches(const synthetic_tree& tree,
                                                                      const claw_spec& spec = {}) {
  return perch_truth(tree, spec).stretches();
}

/// Whether `p` is within `tolerance_px` of the centre of a feasible window of `tree` (a point of
/// a feasible stretch's centreline, the stretch trimmed by half a window at each end). Builds
/// the truth each call: for many queries on one tree, keep a `perch_truth`.
[[nodiscard]] inline bool is_feasible_site(const synthetic_tree& tree, const claw_spec& spec,
                                           Eigen::Vector2f p, float tolerance_px) {
  return perch_truth(tree, spec).is_feasible_site(p, tolerance_px);
}

}  // namespace perch::support
