/// \file
/// Synthetic tree masks with ground truth, for tests, benchmarks and `perch synth`.
///
/// A tree seen from the side, as in the segmentation masks of the PLI paper (Perch Location
/// Identification): a trunk rising from the bottom edge of the image and tapering, forking
/// recursively into limbs whose diameters follow the pipe model (Leonardo da Vinci's rule,
/// d_parent² ≈ Σ d_child², at each fork and for side limbs leaving a limb along its length),
/// limbs of varied slope (near-horizontal side limbs, steep leaders), each limb one circular arc
/// (gentle, constant curvature), some leaving the image. Optional noise adds what real
/// segmentation masks carry: bumps and spurs on the outline (which grow spurious skeleton
/// branches), thin clutter twigs, and occlusion holes (loops in the skeleton).
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

/// What a truth limb is: the trunk (limb 0), a limb of the branching structure, or a thin
/// clutter twig (noise geometry, still real tree pixels).
enum class limb_kind : std::uint8_t { trunk, limb, twig };

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
  float curvature_per_px = 0.0f;  ///< signed, constant: d(heading)/d(arc), + turns clockwise
  int tree = 0;                   ///< which tree it belongs to: 0 the first, 1 the second
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

/// The unit tangent (base → tip) at arc position `s`, from the limb's arc (heading + κ·s).
[[nodiscard]] inline Eigen::Vector2f truth_tangent_at(const limb_truth& limb, float s) noexcept {
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

/// The magnitude of the limb's curvature, 1/px (constant along a limb).
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
    limb.tree = seed.tree;
    double step = std::max(1.5, std::min(0.375 * d_tip, std::max(32.0, 0.1 * d_tip)));
    if (std::abs(kappa) > 0.0) step = std::min(step, 1.5 * deg / std::abs(kappa));
    sample_arc(seed, kappa, step, limb);
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
        side.heading = side_sign * rng.uniform(58.0, 84.0) * deg;
      } else {
        // Diverge by 35–70° from the parent. Near a horizontal parent the clamp can take most
        // of that away (a limb heading 95° turned +50° clamps to 105°: 10° of divergence), and
        // the child then hugs its parent for its whole length, fused with it in the mask: no
        // tree grows so, so such a limb leaves on the other side instead.
        const double divergence = rng.uniform(35.0, 70.0) * deg;
        side.heading = clamp_heading(here + side_sign * divergence);
        if (std::abs(side.heading - here) < 35.0 * deg) {
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
    const double tip_heading = seed.heading + kappa * seed.length;
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

/// Makes a synthetic tree (see the file comment). Limb 0 is the trunk; its bottom row is full
/// width (the trunk's base cap lies below the image). Limbs are grown breadth-first, so a
/// parent's index is below its children's. Order: the first tree, the second tree (`tree == 1`,
/// its trunk has parent -1, one level fewer), crossing limbs, twigs (`limb_kind::twig`) last.
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
  for (const limb_truth& limb : tree.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    draw_polyline(tree.mask, limb.centreline, radii);
  }
  detail::add_outline_noise(options, tree.limbs, tree.mask);
  detail::add_holes(options, tree.limbs, tree.mask);
  return tree;
}

/// The options of `benchmark_tree`: a fixed seed (1), the trunk 4.5 % of the image width
/// (180 mm trunk, mm_per_px = 180 / (0.045·width)); `noisy` adds outline noise of
/// 1 + 0.0016·width px, 24 twigs and 3 holes to the same tree.
[[nodiscard]] inline tree_options benchmark_tree_options(int width, int height, tree_noise noise) {
  tree_options o;
  o.width = width;
  o.height = height;
  o.seed = 1;
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
/// grasping 30–110 mm, on branches at most 35° from horizontal, bends no tighter than a 150 mm
/// radius; 1.5 kg, eq. 4 stress at most 27 MPa / 2; at most 15 % other tree within 60 mm.
struct claw_spec {
  float drone_width_mm = 180.0f;   ///< window length along the limb (arc length)
  float claw_mm = 70.0f;           ///< central region whose mean diameter the claw grasps
  float diameter_min_mm = 30.0f;
  float diameter_max_mm = 110.0f;
  float max_slope_deg = 35.0f;     ///< chord of the window to the horizontal, folded [0, 90]
  float max_curvature_per_mm = 1.0f / 150.0f;
  float clearance_margin_mm = 60.0f;  ///< band beyond the limb's surface on each side
  float clearance_max_share = 0.15f;  ///< share of other tree allowed in that band
  float mass_kg = 1.5f;               ///< for the bending stress (paper eq. 4)
  float max_stress_mpa = 13.5f;       ///< modulus of rupture 27 MPa / safety factor 2
  float junction_gap_px = 2.0f;  ///< limbs closer than this (surface to surface) meet
  float image_margin_px = 2.0f;  ///< the window's limb stays this far inside the image
  float step_px = 1.0f;          ///< spacing of the window centres examined
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
enum class window_verdict : std::uint8_t {
  feasible,
  twig,           ///< twigs are clutter, never perches
  off_limb,       ///< the window runs past the limb's base or tip
  outside_image,  ///< part of the limb under the window is outside the image (or its margin)
  junction,       ///< another limb meets this one under the window
  diameter,       ///< claw-region mean diameter out of range
  slope,
  curvature,
  bending,
  clearance,
};

[[nodiscard]] constexpr const char* to_string(window_verdict v) noexcept {
  switch (v) {
    case window_verdict::feasible: return "feasible";
    case window_verdict::twig: return "twig";
    case window_verdict::off_limb: return "off_limb";
    case window_verdict::outside_image: return "outside_image";
    case window_verdict::junction: return "junction";
    case window_verdict::diameter: return "diameter";
    case window_verdict::slope: return "slope";
    case window_verdict::curvature: return "curvature";
    case window_verdict::bending: return "bending";
    case window_verdict::clearance: return "clearance";
  }
  return "unknown";
}

/// The truth about one window (measures are filled even when an earlier rule fails, except
/// `clearance_share`, computed only for windows that pass every other rule; -1 otherwise).
struct window_truth {
  window_verdict verdict = window_verdict::off_limb;
  int limb = -1;
  float centre_arc_px = 0.0f;
  float claw_diameter_mm = 0.0f;  ///< mean truth diameter over the central claw region
  float slope_deg = 0.0f;         ///< chord between the window's ends, folded into [0, 90]
  float curvature_per_mm = 0.0f;  ///< |κ| of the limb
  float stress_mpa = 0.0f;        ///< eq. 4 with the claw radius and the lever from the limb base
  float clearance_share = -1.0f;  ///< other tree in the band (see `perch_truth`)
};

/// The nearest feasible window centre to a point.
struct site_match {
  int limb = -1;  ///< -1: the tree has no feasible stretch
  float arc_px = 0.0f;
  float distance_px = std::numeric_limits<float>::infinity();
};

/// Where a claw could perch on a synthetic tree, from its truth geometry.
///
/// A window is `drone_width_mm` of arc along a non-twig limb's truth centreline, centred at arc
/// position c. It is feasible when all of these hold:
///  1. it lies on the limb: [c − w/2, c + w/2] ⊂ [0, length];
///  2. inside the image: every centreline point under it is at least its radius +
///     `image_margin_px` from every image edge (a limb cut by the edge has no true end there);
///  3. away from junctions, in two parts: (a) the drone's body: no centreline point under the
///     window lies inside another non-twig limb or within `junction_gap_px` of its surface (the
///     window must not start inside its parent, nor straddle a limb leaving it, a fork or a
///     crossing limb); (b) the claw: over the central `claw_mm` no other non-twig limb comes
///     within `junction_gap_px` of this limb's surface (the claw wraps around the limb). This
///     covers forks at the tip, side limbs leaving it, its own base inside its parent, siblings
///     at a fork, crossing limbs and the other tree. Twigs are not junctions: they are clutter,
///     judged by clearance. (A first version asked (b) over the whole window; that forbade
///     windows whose ends merely touch a sibling's or the parent's surface, which the drone can
///     use: the body of the drone is above the limb, only the claw wraps around it.)
///  4. claw-region diameter: the mean truth diameter over the central `claw_mm` within
///     [diameter_min_mm, diameter_max_mm];
///  5. slope of the chord between the window's end points, folded into [0°, 90°], at most
///     `max_slope_deg` (the image's rows are horizontal);
///  6. curvature: the limb's |κ| (constant per limb) at most `max_curvature_per_mm`;
///  7. bending (paper eq. 4): σ = 4·m·g·L/(π·r³) ≤ `max_stress_mpa`, r the claw-region radius,
///     L the horizontal distance from the limb's base (where it leaves its parent: the real
///     cantilever root) to the window centre;
///  8. clearance: in the band along the window's chord (its end points), the limb's radius at
///     the centre + 0.5 px (the distance-map radius of a centreline pixel) + `clearance_margin_mm`
///     to each side, at most `clearance_max_share` of the pixels outside the own strip
///     (radius + 0.5 + 1.5 px each side of the chord) are tree pixels of the mask. This is the
///     definition `perch::clearance` applies, evaluated on the true chord and radius and on the
///     real mask (twigs, crossing limbs, noise, the other tree all count), clipped to the image.
/// Monotonicity always holds (each limb is one gentle circular arc) and is not checked.
///
/// Windows are examined every `step_px` of arc; consecutive feasible centres form a
/// `feasible_stretch`. A site p (a pixel the pipeline reports as a window centre) is feasible
/// when it lies within a tolerance of the centreline of a stretch trimmed by w/2 at each end,
/// i.e. of a feasible window centre.
///
/// Keeps a pointer to `tree`: the tree must outlive this object. Host code; allocates.
/// Complexity: O(limb pairs with overlapping boxes × samples × segments) for the junctions,
/// O(Σ limb length / step × window) for the windows: a few ms for a 960×720 tree.
class perch_truth {
 public:
  explicit perch_truth(const synthetic_tree& tree, const claw_spec& spec = {})
      : tree_(&tree), spec_(spec) {
    const float mmpp = tree.mm_per_px > 0.0f ? tree.mm_per_px : 1.0f;
    window_px_ = spec.drone_width_mm / mmpp;
    claw_half_px_ = 0.5f * spec.claw_mm / mmpp;
    build_prefix();
    build_junctions();
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
  /// Arc intervals of `limb` whose centreline lies inside (or within the gap of) another limb
  /// (rule 3a), merged, ascending.
  [[nodiscard]] const std::vector<std::pair<float, float>>& junctions(int limb) const {
    return junctions_[static_cast<std::size_t>(limb)];
  }
  /// Arc intervals of `limb` whose surface touches another limb (rule 3b), merged, ascending.
  [[nodiscard]] const std::vector<std::pair<float, float>>& contacts(int limb) const {
    return contacts_[static_cast<std::size_t>(limb)];
  }

  /// The window of `limb` centred at arc `centre_arc_px`, judged by the rules above.
  [[nodiscard]] window_truth window(int limb, float centre_arc_px) const {
    window_truth out;
    out.limb = limb;
    out.centre_arc_px = centre_arc_px;
    if (limb < 0 || static_cast<std::size_t>(limb) >= tree_->limbs.size()) return out;
    const limb_truth& L = tree_->limbs[static_cast<std::size_t>(limb)];
    const float mmpp = tree_->mm_per_px;
    const float half = 0.5f * window_px_;
    const float s0 = centre_arc_px - half, s1 = centre_arc_px + half;
    // Measures (clamped to the limb for windows that run off it).
    double dsum = 0.0;
    int dn = 0;
    for (float u = -claw_half_px_; u <= claw_half_px_ + 1e-3f; u += 0.5f, ++dn)
      dsum += static_cast<double>(truth_diameter_at(L, centre_arc_px + u));
    out.claw_diameter_mm = static_cast<float>(dsum / std::max(dn, 1)) * mmpp;
    const Eigen::Vector2f a = truth_point_at(L, s0), b = truth_point_at(L, s1);
    out.slope_deg = static_cast<float>(
        std::atan2(std::abs(static_cast<double>(b.y() - a.y())),
                   std::abs(static_cast<double>(b.x() - a.x()))) *
        (180.0 / detail::pi));
    out.curvature_per_mm = std::abs(L.curvature_per_px) / mmpp;
    const float lever_mm =
        std::abs(truth_point_at(L, centre_arc_px).x() - L.centreline.front().x()) * mmpp;
    const float r_m = 0.5f * out.claw_diameter_mm / 1000.0f;
    out.stress_mpa = r_m > 0.0f ? 4.0f * spec_.mass_kg * 9.80665f * (lever_mm / 1000.0f) /
                                      (static_cast<float>(detail::pi) * r_m * r_m * r_m) / 1.0e6f
                                : std::numeric_limits<float>::infinity();
    // Rules, in order.
    auto verdict = [&]() {
      if (L.kind == limb_kind::twig) return window_verdict::twig;
      if (s0 < 0.0f || s1 > length_px(L)) return window_verdict::off_limb;
      if (!inside_image(L, s0, s1)) return window_verdict::outside_image;
      for (const auto& j : junctions(limb))
        if (j.first <= s1 && j.second >= s0) return window_verdict::junction;
      for (const auto& j : contacts(limb))
        if (j.first <= centre_arc_px + claw_half_px_ && j.second >= centre_arc_px - claw_half_px_)
          return window_verdict::junction;
      if (out.claw_diameter_mm < spec_.diameter_min_mm ||
          out.claw_diameter_mm > spec_.diameter_max_mm)
        return window_verdict::diameter;
      if (out.slope_deg > spec_.max_slope_deg) return window_verdict::slope;
      if (out.curvature_per_mm > spec_.max_curvature_per_mm) return window_verdict::curvature;
      if (out.stress_mpa > spec_.max_stress_mpa) return window_verdict::bending;
      out.clearance_share = clearance_share(a, b, 0.5f * truth_diameter_at(L, centre_arc_px));
      if (out.clearance_share > spec_.clearance_max_share) return window_verdict::clearance;
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
  void build_prefix() {
    const int w = tree_->mask.width(), h = tree_->mask.height();
    prefix_.assign(static_cast<std::size_t>(w + 1) * static_cast<std::size_t>(h), 0u);
    for (int y = 0; y < h; ++y) {
      std::uint32_t* row = prefix_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w + 1);
      const auto in = tree_->mask.row(y);
      for (int x = 0; x < w; ++x) row[x + 1] = row[x] + (in[static_cast<std::size_t>(x)] != 0 ? 1u : 0u);
    }
  }

  /// Tree pixels of row y in columns [x0, x1] (clipped).
  [[nodiscard]] std::uint32_t count_row(int y, int x0, int x1) const noexcept {
    const int w = tree_->mask.width();
    x0 = std::max(x0, 0);
    x1 = std::min(x1, w - 1);
    if (y < 0 || y >= tree_->mask.height() || x1 < x0) return 0;
    const std::uint32_t* row = prefix_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w + 1);
    return row[x1 + 1] - row[x0];
  }

  /// Rule 8: the share of tree pixels in the band along chord a–b outside the own strip.
  [[nodiscard]] float clearance_share(Eigen::Vector2f a, Eigen::Vector2f b, float radius_px) const {
    const float mmpp = tree_->mm_per_px;
    const Eigen::Vector2f chord = b - a;
    const float len = chord.norm();
    if (!(len > 0.0f)) return 1.0f;
    const Eigen::Vector2f along = chord / len;
    const Eigen::Vector2f across(-along.y(), along.x());
    const Eigen::Vector2f c = 0.5f * (a + b);
    const float own = radius_px + 0.5f;
    const float half_len = 0.5f * len;
    const float half_w = own + spec_.clearance_margin_mm / mmpp;
    const float strip = own + 1.5f;
    // Columns x of row y with |n·(p − c)| ≤ r for a unit normal n: an interval (or all / none).
    auto slab = [](const Eigen::Vector2f& n, float centre, float r, float y, float& x0, float& x1) {
      const float lo = centre - r - n.y() * y, hi = centre + r - n.y() * y;
      if (std::abs(n.x()) < 1e-6f) {
        if (lo > 0.0f || hi < 0.0f) return false;
        return true;
      }
      float u = lo / n.x(), v = hi / n.x();
      if (u > v) std::swap(u, v);
      x0 = std::max(x0, u);
      x1 = std::min(x1, v);
      return x0 <= x1;
    };
    const float reach = half_len + half_w;
    const int h = tree_->mask.height(), w = tree_->mask.width();
    const int y0 = std::max(0, static_cast<int>(std::floor(c.y() - reach)));
    const int y1 = std::min(h - 1, static_cast<int>(std::ceil(c.y() + reach)));
    std::uint64_t tree = 0, total = 0;
    for (int y = y0; y <= y1; ++y) {
      const auto fy = static_cast<float>(y);
      float x0 = -1e30f, x1 = 1e30f;
      if (!slab(along, along.dot(c), half_len, fy, x0, x1)) continue;
      if (!slab(across, across.dot(c), half_w, fy, x0, x1)) continue;
      const int ix0 = std::max(0, static_cast<int>(std::ceil(x0)));
      const int ix1 = std::min(w - 1, static_cast<int>(std::floor(x1)));
      if (ix1 < ix0) continue;
      std::uint64_t row_tree = count_row(y, ix0, ix1);
      auto row_total = static_cast<std::uint64_t>(ix1 - ix0 + 1);
      float s0 = -1e30f, s1 = 1e30f;
      if (slab(across, across.dot(c), strip, fy, s0, s1)) {
        const int o0 = std::max(ix0, static_cast<int>(std::ceil(s0)));
        const int o1 = std::min(ix1, static_cast<int>(std::floor(s1)));
        if (o0 <= o1) {
          row_tree -= count_row(y, o0, o1);
          row_total -= static_cast<std::uint64_t>(o1 - o0 + 1);
        }
      }
      tree += row_tree;
      total += row_total;
    }
    return total == 0 ? 0.0f : static_cast<float>(static_cast<double>(tree) / static_cast<double>(total));
  }

  /// Rule 2 for arcs [s0, s1] of L.
  [[nodiscard]] bool inside_image(const limb_truth& L, float s0, float s1) const {
    const float m = spec_.image_margin_px;
    const auto W = static_cast<float>(tree_->mask.width() - 1);
    const auto H = static_cast<float>(tree_->mask.height() - 1);
    const int n = std::max(1, static_cast<int>(std::ceil((s1 - s0) / 2.0f)));
    for (int i = 0; i <= n; ++i) {
      const float s = s0 + (s1 - s0) * static_cast<float>(i) / static_cast<float>(n);
      const Eigen::Vector2f q = truth_point_at(L, s);
      const float r = 0.5f * truth_diameter_at(L, s) + m;
      if (q.x() < r || q.y() < r || q.x() > W - r || q.y() > H - r) return false;
    }
    return true;
  }

  /// Rule 3: per limb, the arc positions where another non-twig limb's surface comes within the
  /// gap (3a) or the limb's radius + gap (3b) of its centreline, sampled every 0.5 px, merged
  /// into intervals.
  void build_junctions() {
    const auto& limbs = tree_->limbs;
    junctions_.assign(limbs.size(), {});
    contacts_.assign(limbs.size(), {});
    struct box {
      float x0, y0, x1, y1;
    };
    std::vector<box> boxes(limbs.size());
    for (std::size_t i = 0; i < limbs.size(); ++i) {
      box bx{1e30f, 1e30f, -1e30f, -1e30f};
      const limb_truth& L = limbs[i];
      for (std::size_t k = 0; k < L.centreline.size(); ++k) {
        const float r = 0.5f * L.diameter_px[k];
        bx.x0 = std::min(bx.x0, L.centreline[k].x() - r);
        bx.y0 = std::min(bx.y0, L.centreline[k].y() - r);
        bx.x1 = std::max(bx.x1, L.centreline[k].x() + r);
        bx.y1 = std::max(bx.y1, L.centreline[k].y() + r);
      }
      boxes[i] = bx;
    }
    const float gap = spec_.junction_gap_px;
    // A limb whose every disc lies inside one other limb (within half a pixel, the mask's
    // rasterisation) is not in the mask at all: it adds no pixel, so there is nothing to grasp
    // around or to avoid, and it makes no junction. (The generator can grow a thin side limb
    // almost along its parent; it then stays hidden inside it.)
    std::vector<std::uint8_t> hidden(limbs.size(), 0);
    for (std::size_t bi = 0; bi < limbs.size(); ++bi) {
      const limb_truth& B = limbs[bi];
      if (B.kind == limb_kind::twig || B.centreline.size() < 2) continue;
      const float len = length_px(B);
      const int n = std::max(1, static_cast<int>(std::ceil(len)));
      for (std::size_t ci = 0; ci < limbs.size() && hidden[bi] == 0; ++ci) {
        const limb_truth& C = limbs[ci];
        if (ci == bi || C.kind == limb_kind::twig || C.centreline.size() < 2) continue;
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
        hidden[bi] = inside ? 1 : 0;
      }
    }
    for (std::size_t ai = 0; ai < limbs.size(); ++ai) {
      const limb_truth& A = limbs[ai];
      if (A.kind == limb_kind::twig || A.centreline.size() < 2) continue;
      const float len = length_px(A);
      const int n = std::max(1, static_cast<int>(std::ceil(len / 0.5f)));
      std::vector<std::uint8_t> hit(static_cast<std::size_t>(n) + 1, 0);  // 1 contact, 2 body
      for (std::size_t bi = 0; bi < limbs.size(); ++bi) {
        const limb_truth& B = limbs[bi];
        if (bi == ai || B.kind == limb_kind::twig || B.centreline.size() < 2 || hidden[bi] != 0)
          continue;
        const box& ba = boxes[ai];
        const box& bb = boxes[bi];
        if (ba.x1 + gap < bb.x0 || bb.x1 + gap < ba.x0 || ba.y1 + gap < bb.y0 ||
            bb.y1 + gap < ba.y0)
          continue;
        for (int i = 0; i <= n; ++i) {
          if (hit[static_cast<std::size_t>(i)] == 2) continue;
          const float s = len * static_cast<float>(i) / static_cast<float>(n);
          const Eigen::Vector2f p = truth_point_at(A, s);
          const float reach = 0.5f * truth_diameter_at(A, s) + gap;
          if (p.x() + reach < bb.x0 || p.x() - reach > bb.x1 || p.y() + reach < bb.y0 ||
              p.y() - reach > bb.y1)
            continue;
          for (std::size_t k = 0; k + 1 < B.centreline.size(); ++k) {
            const Eigen::Vector2f q0 = B.centreline[k];
            const Eigen::Vector2f d = B.centreline[k + 1] - q0;
            const float len2 = d.squaredNorm();
            const float t = len2 > 0.0f ? std::clamp((p - q0).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
            const float rb =
                0.5f * (B.diameter_px[k] + t * (B.diameter_px[k + 1] - B.diameter_px[k]));
            const float surface = (p - (q0 + t * d)).norm() - rb;
            std::uint8_t& h = hit[static_cast<std::size_t>(i)];
            if (surface <= gap) {
              h = 2;
              break;
            }
            if (surface <= reach) h = 1;
          }
        }
      }
      auto runs = [&](std::uint8_t level, std::vector<std::pair<float, float>>& out) {
        for (int i = 0; i <= n;) {
          if (hit[static_cast<std::size_t>(i)] < level) {
            ++i;
            continue;
          }
          int j = i;
          while (j + 1 <= n && hit[static_cast<std::size_t>(j + 1)] >= level) ++j;
          // Widen by one sample on each side: the contact may begin between samples.
          const float lo = len * static_cast<float>(std::max(i - 1, 0)) / static_cast<float>(n);
          const float hi = len * static_cast<float>(std::min(j + 1, n)) / static_cast<float>(n);
          out.emplace_back(lo, hi);
          i = j + 1;
        }
      };
      runs(2, junctions_[ai]);
      runs(1, contacts_[ai]);
    }
  }

  void build_stretches() {
    const float half = 0.5f * window_px_;
    const float step = spec_.step_px > 0.05f ? spec_.step_px : 0.05f;
    for (std::size_t li = 0; li < tree_->limbs.size(); ++li) {
      const limb_truth& L = tree_->limbs[li];
      if (L.kind == limb_kind::twig || L.centreline.size() < 2) continue;
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
  float window_px_ = 0.0f;
  float claw_half_px_ = 0.0f;
  std::vector<std::uint32_t> prefix_;
  std::vector<std::vector<std::pair<float, float>>> junctions_;
  std::vector<std::vector<std::pair<float, float>>> contacts_;
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
