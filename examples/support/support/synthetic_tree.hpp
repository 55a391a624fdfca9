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
void draw_capsule(image_view<std::uint8_t> img, Eigen::Vector2f a, Eigen::Vector2f b,
                  float radius_a, float radius_b, std::uint8_t value = 1);

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
void draw_polyline(image_view<std::uint8_t> img, const std::vector<Eigen::Vector2f>& points,
                   const std::vector<float>& radii, std::uint8_t value = 1);

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
std::vector<Eigen::Vector2f> arc_points(Eigen::Vector2f centre, float arc_radius, float start_rad,
                                        float end_rad, float max_step_px = 2.0f);

/// A stroked circular arc of constant `stroke_radius` (see `arc_points`).
void draw_arc(image_view<std::uint8_t> img, Eigen::Vector2f centre, float arc_radius,
              float start_rad, float end_rad, float stroke_radius, std::uint8_t value = 1);

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
[[nodiscard]] limb_location locate(const std::vector<limb_truth>& limbs, Eigen::Vector2f p,
                                   limb_set which = limb_set::all) noexcept;

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

/// The smallest distance from the surface of the tapered capsule chain `limb` to point p, px
/// (negative inside).
float surface_distance(const limb_truth& limb, Eigen::Vector2f p) noexcept;

/// Boundary noise: bumps (discs straddling the outline) and spurs (thin capsules sticking out).
void add_outline_noise(const tree_options& o, const std::vector<limb_truth>& limbs,
                       image_view<std::uint8_t> mask);

}  // namespace detail

/// A segmenter's bias: every outline of `mask` moved out by `px` pixels (`px` > 0: the tree
/// grows by a disc of that radius, as an over-segmenting network draws it; `px` < 0: it shrinks,
/// as an under-segmenting one does). The truth stays the drawn geometry, so `perch eval
/// --outline-bias` asks how a rule's margins stand a mask whose widths are off by 2·`px`.
/// Complexity: O(pixels · px²).
void shift_outline(image<std::uint8_t>& mask, int px);

/// A generator that rasterises limbs another way: every limb of `tree` (twigs and fragments
/// too) drawn with its radius `px` larger (`px` > 0, e.g. 0.5: a pixel counts when any of it is
/// covered rather than its centre) or smaller (`px` < 0), sub-pixel amounts included. The
/// outline noise, holes and the truth stay as they are: only the limbs' own outlines move (a
/// shell `|px|` thick is added to or removed from each; a piece thinner than `2·|px|` goes). Where `shift_outline` models a
/// segmenter's whole-pixel bias, this models the half-pixel ones of another drawing rule.
/// Complexity: O(Σ segment bounding boxes), three drawings of the tree.
void bias_radii(synthetic_tree& tree, float px);

/// A segmenter's gaps: `count` breaks cut into the mask of `tree`, each across a limb of the
/// branching structure (trunk or limb, not a twig or fragment; at least 6 px wide at its base
/// and 4 px where it is cut) and 1–8 px long along it (drawn per gap): every other one at a random point of the limb's
/// middle three fifths (a leaf in front, a thin stretch lost), the others at a child's base,
/// where its whole width has just left its parent's outline (a child cut off at the
/// junction). The band erased is the limb's width and 4 px more on each side (the outline's
/// bumps), but no pixel inside another limb's drawn outline. The truth stays the drawn
/// geometry: the limb is still there and its pieces attached. Deterministic in `seed`.
/// Complexity: O(count × band pixels × nearby limbs' segments).
void cut_gaps(synthetic_tree& tree, int count, std::uint32_t seed);

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
[[nodiscard]] synthetic_tree make_tree(const tree_options& options);

/// The options of `benchmark_tree`: a fixed seed (23: a tree that offers the tendon claw safe
/// perches at most sizes, so that a benchmark times the clearance queries of the ranking too),
/// the trunk 4.5 % of the image width (180 mm trunk, mm_per_px = 180 / (0.045·width)); `noisy`
/// adds outline noise of 1 + 0.0016·width px, 24 twigs and 3 holes to the same tree.
[[nodiscard]] tree_options benchmark_tree_options(int width, int height, tree_noise noise);

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
  explicit perch_truth(const synthetic_tree& tree, const claw_spec& spec = {});

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
  [[nodiscard]] window_truth window(int limb, float centre_arc_px) const;

  /// The feasible window centre nearest to `p` (over every stretch).
  [[nodiscard]] site_match nearest_site(Eigen::Vector2f p) const;

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
  void build_support();

  /// Whether limb `bi` lies wholly inside another limb (within half a pixel): it is not in the
  /// mask at all, adds no pixel, and is no obstacle.
  [[nodiscard]] bool hidden(std::size_t bi, const std::vector<box>& boxes) const;

  /// The obstacles of rule 4: the parts at least `twig_max_mm` thick of the segments of every
  /// limb that is not a twig by kind and not hidden.
  void build_obstacles();

  /// Rule 4 at arc s of limb li: the smallest |p − q| − r_B(q) − r(p), px, over the obstacles
  /// of other limbs within reach (∞ when none).
  [[nodiscard]] float clearance_gap_px(std::size_t li, float s) const;
  /// The same, searching only `candidates` (obstacle indices that include every one in reach).
  [[nodiscard]] float clearance_gap_px(std::size_t li, float s,
                                       const std::vector<std::size_t>& candidates) const;

  /// Rule 3 at arc s: the distance from the limb's surface to the nearest image edge, px.
  [[nodiscard]] float border_px(const limb_truth& L, float s) const;

  /// The tangent at arc s: the chord over ±1 px of arc (clamped to the limb).
  [[nodiscard]] static Eigen::Vector2d chord_tangent(const limb_truth& L, float s);

  /// The angle between two directions, degrees (0 when one is degenerate).
  [[nodiscard]] static float angle_deg(const Eigen::Vector2d& u, const Eigen::Vector2d& v);

  /// Rule 8 at arc s: the angle between the tangents at max(s − W/2, 0) and min(s + W/2, len).
  [[nodiscard]] float bend_deg(const limb_truth& L, float s) const;

  /// Rule 7 over arcs [a, b]: the steepest polyline segment overlapping it, deg in [0, 90].
  [[nodiscard]] float max_slope_deg(const limb_truth& L, float a, float b) const;

  /// The true horizontal in the image (unit; (1, 0) without roll).
  [[nodiscard]] Eigen::Vector2f horizon() const noexcept;

  /// The per-limb grids of rules 3, 4 and 8.
  void build_profiles();

  void build_stretches();

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
