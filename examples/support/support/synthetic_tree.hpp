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
};

/// A synthetic tree: the mask (1 = tree, 0 = sky), its limbs, and its scale.
struct synthetic_tree {
  image<std::uint8_t> mask;
  std::vector<limb_truth> limbs;  ///< limbs[0] is the trunk; parents come before children
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
};

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

/// Grows the branching structure (no noise) into `limbs`.
inline void grow_tree(const tree_options& o, std::vector<limb_truth>& limbs) {
  tree_random rng(o.seed);
  const double W = o.width, H = o.height;
  const double px_per_mm = 1.0 / static_cast<double>(o.mm_per_px);
  const double d0 = static_cast<double>(o.trunk_diameter_mm) * px_per_mm;
  const double d_min = static_cast<double>(o.min_diameter_mm) * px_per_mm;
  const int max_children = std::max(2, o.branches_per_node);
  const int levels = std::clamp(o.levels, 0, 12);
  const int side_max = std::clamp(o.side_limbs, 0, 8);
  constexpr std::size_t max_limbs = 4000;

  std::vector<limb_seed> queue;
  limb_seed trunk;
  trunk.base = {W * rng.uniform(0.4, 0.6), H - 1.0 + 0.5 * d0};  // cap below the image
  trunk.heading = rng.uniform(-5.0, 5.0) * deg;
  trunk.diameter = d0;
  trunk.length = std::max(H * rng.uniform(0.36, 0.46), 3.0 * d0) + 0.5 * d0;
  trunk.level = 0;
  trunk.kind = limb_kind::trunk;
  queue.push_back(trunk);

  for (std::size_t qi = 0; qi < queue.size() && limbs.size() < max_limbs; ++qi) {
    const limb_seed seed = queue[qi];
    const int index = static_cast<int>(limbs.size());
    // Curvature: limbs leaning out bend back up towards the light; steep ones wander a little.
    double turn = 0.0;
    if (seed.kind == limb_kind::trunk)
      turn = rng.uniform(-6.0, 6.0) * deg;
    else if (std::abs(seed.heading) > 40.0 * deg)
      turn = -(seed.heading > 0.0 ? 1.0 : -1.0) * rng.uniform(4.0, 28.0) * deg;
    else
      turn = rng.uniform(-14.0, 14.0) * deg;
    const double kappa = turn / seed.length;

    // Side limbs along the length (decided first: they take their share of the pipe).
    const int level_next = seed.level + 1;
    int sides = 0;
    if (level_next <= levels && side_max > 0)
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
      const double d = d_here * rng.uniform(0.36, 0.55);
      if (d < d_min) continue;
      plans.push_back({s, d});
      side_area += d * d;
    }
    const double d_tip =
        std::sqrt(std::max(d_tip_free * d_tip_free - side_area, 0.36 * d_tip_free * d_tip_free));

    limb_truth limb;
    limb.parent = seed.parent;
    limb.parent_arc_px = static_cast<float>(seed.parent_arc);
    limb.level = seed.level;
    limb.kind = seed.kind;
    limb.base_heading_rad = static_cast<float>(seed.heading);
    limb.curvature_per_px = static_cast<float>(kappa);
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
    for (const side_plan& plan : plans) {
      const auto s = static_cast<float>(plan.s * static_cast<double>(length) / seed.length);
      const Eigen::Vector2f at = truth_point_at(grown, s);
      if (!inside_image(at)) continue;
      const Eigen::Vector2f t = truth_tangent_at(grown, s);
      const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y()));
      limb_seed side;
      side.parent = index;
      side.parent_arc = static_cast<double>(s);
      side.base = {static_cast<double>(at.x()), static_cast<double>(at.y())};
      side.heading = seed.kind == limb_kind::trunk
                         ? side_sign * rng.uniform(58.0, 84.0) * deg
                         : clamp_heading(here + side_sign * rng.uniform(35.0, 70.0) * deg);
      side_sign = -side_sign;
      side.diameter = plan.d;
      side.length = std::max(seed.length * rng.uniform(0.45, 0.75), 4.0 * plan.d);
      side.level = level_next;
      side.kind = limb_kind::limb;
      queue.push_back(side);
    }

    // The fork at the tip: a leader close to the parent's direction and diverging others.
    if (level_next > levels || !inside_image(tip)) continue;
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
      queue.push_back(child);
    }
  }
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
/// parent's index is below its children's; twigs (`limb_kind::twig`) come last. With
/// `noise == 0`, `twigs == 0`, `holes == 0` the mask is one 8-connected component (every limb
/// starts on its parent's centreline, and only limbs whose base is inside the image are grown).
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
      std::isfinite(options.min_diameter_mm) && std::isfinite(options.noise);
  if (!valid) return tree;
  tree.mask = image<std::uint8_t>(options.width, options.height, 0);
  detail::grow_tree(options, tree.limbs);
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

}  // namespace perch::support
