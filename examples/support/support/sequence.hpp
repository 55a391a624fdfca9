// SPDX-License-Identifier: BSL-1.0
/// \file
/// Synthetic approach sequences with truth, for the tracker: one tree of the generator (its
/// drawn geometry: limb centrelines and radii) seen through a camera that approaches from
/// `start_distance` times to once the final distance (the picture scales up), drifts sideways,
/// rolls and shakes, re-rendered every frame with a segmenter's noise: outline bumps and spurs,
/// pinholes, a limb segment missing for 1–3 frames now and then, and a frame of heavy noise now
/// and then.
///
/// Each frame carries the tree as it appears in that frame (`frame.tree`: the world geometry
/// moved by the camera's similarity, scale changed with the distance) and the camera's roll,
/// so `perch_truth(frame.tree, spec_with(frame.roll_deg))` gives the frame's feasible stretches
/// under the same rules as single pictures (the border and resolution rules change with the
/// camera; the others are physical), and `frame.motion` is the true motion from the previous
/// frame (previous pixels → these), the tracker's reference.
///
/// The world's trunk is extended downward (a straight limb of the trunk's base diameter) so
/// that the tree stands on the frame's bottom edge when seen from afar.
///
/// Deterministic: every random choice comes from `std::mt19937`'s specified output via
/// `detail::tree_random`, per sequence and per frame.
/// Host code: allocates, no exceptions. Not part of the library.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "perch/analysis/scale.hpp"
#include "perch/track/motion.hpp"
#include "support/population.hpp"
#include "support/synthetic_tree.hpp"

namespace perch::support {

/// How a sequence is filmed and how noisy its masks are.
struct sequence_options {
  int frames = 90;                 ///< at 30 fps: a three-second approach
  std::uint32_t seed = 1;          ///< camera path and noise
  float start_distance = 3.0f;     ///< first frame's distance / last frame's (≥ 1)
  float drift = 0.15f;             ///< lateral drift of the aim point, fraction of the width
  float max_roll_deg = 15.0f;      ///< roll amplitude (a slow swing)
  float jitter_px = 1.5f;          ///< hand-held shake per frame, px (uniform ±)
  float jitter_deg = 0.5f;         ///< and degrees of roll
  float outline_noise_px = 1.5f;   ///< bumps and spurs on the outline, px (0: none)
  int pinholes = 6;                ///< small holes (1–2 px) per frame
  float dropout_chance = 0.05f;    ///< per frame: a limb segment starts missing for 1–3 frames
  float heavy_chance = 0.03f;      ///< per frame: heavy noise (3× outline, 5× pinholes, cuts)
};

/// One frame: its mask, the tree as seen, the camera, the true motion since the last frame.
struct sequence_frame {
  image<std::uint8_t> mask;
  synthetic_tree tree;  ///< the geometry in this frame's pixels; `tree.mask` its clean render
  float roll_deg = 0;   ///< the camera's roll (as `perch::attitude::roll_deg`)
  float scale = 1;      ///< world → frame scale (1/3 … 1 for a 3× approach)
  camera_motion motion{};  ///< previous frame → this one (identity for the first)
  camera_motion from_world{};  ///< the world tree's pixels → this frame's
  bool heavy = false;      ///< a heavy-noise frame
  int dropouts = 0;        ///< limb segments missing in this frame
};

namespace detail::sequences {

/// The world → frame similarity of a frame: p' = centre + scale·R(roll)·(p − aim) + shake.
struct pose {
  float scale = 1, roll_deg = 0;
  Eigen::Vector2f aim{0, 0}, shake{0, 0}, centre{0, 0};
  [[nodiscard]] camera_motion motion() const noexcept {
    const camera_motion rs = camera_motion::similarity(scale, roll_deg, 0, 0);
    const point2f moved = rs.apply(aim);
    return camera_motion::similarity(scale, roll_deg, centre.x() - moved.x() + shake.x(),
                                     centre.y() - moved.y() + shake.y());
  }
};

/// The inverse of a similarity made by `camera_motion::similarity`.
[[nodiscard]] inline camera_motion inverse_similarity(const camera_motion& m) noexcept {
  const float a = m.h[0], b = m.h[3];  // s·cos, s·sin
  const float s2 = a * a + b * b;
  // R(−θ)/s = [a b; −b a] / s².
  camera_motion inv;
  inv.h = {a / s2, b / s2, 0, -b / s2, a / s2, 0, 0, 0, 1};
  const point2f t = inv.apply(point2f(m.h[2], m.h[5]));
  inv.h[2] = -t.x();
  inv.h[5] = -t.y();
  return inv;
}

/// A limb segment missing from the mask for some frames.
struct dropout {
  int first_frame = 0, frames = 1;
  int limb = 0;
  float arc_fraction = 0.5f;  ///< where along the limb
};

}  // namespace detail::sequences

/// An approach to one tree (see the file comment). Frames are made on demand.
class approach_sequence {
 public:
  approach_sequence(const synthetic_tree& world, const sequence_options& options)
      : options_(options), world_(world) {
    world_.mask = image<std::uint8_t>();
    width_ = world.mask.width();
    height_ = world.mask.height();
    extend_trunk();
    plan_camera();
    plan_dropouts();
  }

  [[nodiscard]] int frames() const noexcept { return options_.frames; }
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }
  [[nodiscard]] const sequence_options& options() const noexcept { return options_; }

  /// The pinhole camera `depth_mm` assumes: focal length the frame's width in pixels (a 53°
  /// horizontal field of view), principal point at the frame's centre.
  [[nodiscard]] pinhole camera() const noexcept {
    const auto f = static_cast<float>(width_);
    return {f, f, 0.5f * static_cast<float>(width_ - 1), 0.5f * static_cast<float>(height_ - 1)};
  }

  /// The true distance of `frame`'s tree along the optical axis, millimetres: the tree is a
  /// plane facing the camera where `camera()` sees `frame.tree.mm_per_px` (Z = mm/px · f).
  [[nodiscard]] float distance_mm(const sequence_frame& frame) const noexcept {
    return frame.tree.mm_per_px * camera().fx;
  }

  /// The true camera-frame point, metres, of `frame`'s pixel `p` on the tree's plane.
  [[nodiscard]] point3f point_m(const sequence_frame& frame, point2f p) const noexcept {
    return camera().back_project(p, 1e-3f * distance_mm(frame));
  }

  /// What a depth camera registered to `frame`'s mask would see, millimetres along the optical
  /// axis: the tree (its clean render, `frame.tree.mask`) at `distance_mm`, rounded to the
  /// millimetre, 0 (no return) elsewhere.
  [[nodiscard]] image<std::uint16_t> depth_mm(const sequence_frame& frame) const {
    const float z = std::min(distance_mm(frame), 65535.0f);
    const auto value = static_cast<std::uint16_t>(std::lround(z));
    image<std::uint16_t> out(width_, height_, 0);
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x)
        if (frame.tree.mask(x, y) != 0) out(x, y) = value;
    return out;
  }

  /// Frame `f` (0 … frames − 1).
  [[nodiscard]] sequence_frame frame(int f) const {
    sequence_frame out;
    const auto& p = poses_[static_cast<std::size_t>(f)];
    const camera_motion to_frame = p.motion();
    out.from_world = to_frame;
    out.scale = p.scale;
    out.roll_deg = p.roll_deg;
    out.motion = f == 0 ? camera_motion::identity()
                        : to_frame.after(detail::sequences::inverse_similarity(
                              poses_[static_cast<std::size_t>(f - 1)].motion()));
    out.tree = transformed(to_frame, p.scale);
    out.tree.mask = image<std::uint8_t>(width_, height_, 0);
    for (const limb_truth& limb : out.tree.limbs) {
      std::vector<float> radii(limb.diameter_px.size());
      for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
      draw_polyline(out.tree.mask, limb.centreline, radii);
    }
    out.mask = out.tree.mask;
    add_noise(f, out);
    return out;
  }

 private:
  /// A straight limb under the trunk's base, down to three heights below the frame.
  void extend_trunk() {
    if (world_.limbs.empty() || world_.limbs[0].centreline.size() < 2) return;
    const limb_truth& trunk = world_.limbs[0];
    limb_truth ground;
    const Eigen::Vector2f base = trunk.centreline.front();
    const Eigen::Vector2f foot = base + Eigen::Vector2f(0, 3.0f * static_cast<float>(height_));
    ground.centreline = {foot, base};
    ground.diameter_px = {trunk.diameter_px.front(), trunk.diameter_px.front()};
    ground.arc_px = {0.0f, (base - foot).norm()};
    ground.kind = limb_kind::trunk;
    ground.parent = -1;
    ground.tree = trunk.tree;
    world_.limbs.push_back(ground);
  }

  /// The camera path: distance from `start_distance` to 1 (the picture's scale 1/start … 1),
  /// the aim point drifting sideways (and a little up or down), a slow roll swing, shake.
  void plan_camera() {
    detail::tree_random rng(options_.seed * 2654435761u + 17u);
    const float w = static_cast<float>(width_), h = static_cast<float>(height_);
    const Eigen::Vector2f centre(0.5f * (w - 1), 0.5f * (h - 1));
    const float side = static_cast<float>(rng.sign());
    const float rise = static_cast<float>(rng.uniform(-0.05, 0.05));
    const float roll_amplitude = options_.max_roll_deg * static_cast<float>(rng.uniform(0.5, 1.0));
    const float roll_phase = static_cast<float>(rng.uniform(0.0, 2.0 * detail::pi));
    const float roll_cycles = static_cast<float>(rng.uniform(0.3, 1.0));
    const int n = std::max(options_.frames, 1);
    poses_.resize(static_cast<std::size_t>(n));
    for (int f = 0; f < n; ++f) {
      const float u = n > 1 ? static_cast<float>(f) / static_cast<float>(n - 1) : 1.0f;
      detail::sequences::pose& p = poses_[static_cast<std::size_t>(f)];
      const float distance = options_.start_distance + (1.0f - options_.start_distance) * u;
      p.scale = 1.0f / distance;
      p.centre = centre;
      p.aim = centre + Eigen::Vector2f(side * options_.drift * w * (u - 0.5f), rise * h * u);
      double sn = 0, cs = 1;
      detail::sin_cos(2.0 * detail::pi * static_cast<double>(roll_cycles * u) +
                          static_cast<double>(roll_phase),
                      sn, cs);
      p.roll_deg = roll_amplitude * static_cast<float>(sn) +
                   options_.jitter_deg * static_cast<float>(rng.uniform(-1.0, 1.0));
      p.shake = options_.jitter_px * Eigen::Vector2f(static_cast<float>(rng.uniform(-1.0, 1.0)),
                                                     static_cast<float>(rng.uniform(-1.0, 1.0)));
    }
  }

  void plan_dropouts() {
    detail::tree_random rng(options_.seed * 40503u + 5u);
    std::vector<int> droppable;
    for (std::size_t i = 1; i < world_.limbs.size(); ++i)
      if (world_.limbs[i].kind == limb_kind::limb) droppable.push_back(static_cast<int>(i));
    for (int f = 0; f < options_.frames; ++f) {
      const bool starts = rng.uniform() < static_cast<double>(options_.dropout_chance);
      const int frames = rng.integer(1, 3);
      const int pick = rng.integer(0, std::max(0, static_cast<int>(droppable.size()) - 1));
      const auto where = static_cast<float>(rng.uniform(0.2, 0.8));
      if (starts && !droppable.empty())
        dropouts_.push_back({f, frames, droppable[static_cast<std::size_t>(pick)], where});
    }
  }

  /// The world's limbs moved into the frame by `m` (scale `s`).
  [[nodiscard]] synthetic_tree transformed(const camera_motion& m, float s) const {
    synthetic_tree t;
    t.mm_per_px = world_.mm_per_px / s;
    t.limbs = world_.limbs;
    for (limb_truth& limb : t.limbs) {
      for (Eigen::Vector2f& p : limb.centreline) p = m.apply(p);
      for (float& d : limb.diameter_px) d *= s;
      for (float& a : limb.arc_px) a *= s;
      limb.parent_arc_px *= s;
      limb.curvature_per_px /= s;
      limb.exact_arc = false;  // tangents from the moved polyline
    }
    return t;
  }

  void add_noise(int f, sequence_frame& out) const {
    detail::tree_random rng(options_.seed * 97u + static_cast<std::uint32_t>(f) * 7919u + 3u);
    out.heavy = rng.uniform() < static_cast<double>(options_.heavy_chance);
    const int heavy = out.heavy ? 1 : 0;
    tree_options noise;
    noise.seed = options_.seed * 1000003u + static_cast<std::uint32_t>(f);
    noise.noise = options_.outline_noise_px * static_cast<float>(1 + 2 * heavy);
    detail::add_outline_noise(noise, out.tree.limbs, out.mask);
    add_pinholes(rng, options_.pinholes * (1 + 4 * heavy), out);
    for (const detail::sequences::dropout& d : dropouts_)
      if (f >= d.first_frame && f < d.first_frame + d.frames) {
        cut(out.tree.limbs[static_cast<std::size_t>(d.limb)], d.arc_fraction, out.mask);
        ++out.dropouts;
      }
    if (out.heavy)
      for (int k = 0; k < 2; ++k) {
        const int li = rng.integer(1, static_cast<int>(out.tree.limbs.size()) - 1);
        cut(out.tree.limbs[static_cast<std::size_t>(li)], static_cast<float>(rng.uniform(0.2, 0.8)),
            out.mask);
      }
  }

  /// Holes of 1–2 px inside the limbs (a segmenter's misses; `find_perch` fills the smallest).
  static void add_pinholes(detail::tree_random& rng, int count, sequence_frame& out) {
    const auto& limbs = out.tree.limbs;
    if (limbs.size() < 2) return;
    for (int k = 0; k < count; ++k) {
      const limb_truth& limb = limbs[static_cast<std::size_t>(
          rng.integer(0, static_cast<int>(limbs.size()) - 2))];  // not the ground extension
      const auto s = static_cast<float>(rng.uniform() * static_cast<double>(length_px(limb)));
      const float r = 0.5f * truth_diameter_at(limb, s);
      const Eigen::Vector2f t = truth_tangent_at(limb, s);
      const Eigen::Vector2f n(-t.y(), t.x());
      const auto offset = static_cast<float>(rng.uniform(-0.6, 0.6)) * r;
      draw_disc(out.mask, truth_point_at(limb, s) + offset * n,
                static_cast<float>(rng.uniform(0.6, 1.3)), 0);
    }
  }

  /// Erases a piece of `limb` 1.5 diameters long at `fraction` of its length (a segmenter that
  /// lost it behind a leaf or in glare).
  static void cut(const limb_truth& limb, float fraction, image<std::uint8_t>& mask) {
    const float s = fraction * length_px(limb);
    const float d = truth_diameter_at(limb, s);
    const Eigen::Vector2f t = truth_tangent_at(limb, s);
    const Eigen::Vector2f c = truth_point_at(limb, s);
    const Eigen::Vector2f from = c - 0.75f * d * t, to = c + 0.75f * d * t;
    draw_capsule(mask, from, to, 0.5f * d + 2.0f, std::uint8_t{0});
  }

  sequence_options options_;
  synthetic_tree world_;
  int width_ = 0, height_ = 0;
  std::vector<detail::sequences::pose> poses_;
  std::vector<detail::sequences::dropout> dropouts_;
};

/// The claw spec of a frame: `spec` with the frame's roll.
[[nodiscard]] inline claw_spec spec_for(const sequence_frame& frame, claw_spec spec = {}) {
  spec.roll_deg = frame.roll_deg;
  return spec;
}

/// Sequence `i` of the evaluation set of `family`: the `i`-th member that offers a perch (the
/// 85 % of the population wished one), filmed with seed `i`.
[[nodiscard]] inline approach_sequence evaluation_sequence(int i, sequence_options options = {},
                                                           tree_family family = tree_family::arcs) {
  int member = 0;
  for (int seen = 0;; ++member)
    if (wishes_perch(member) && seen++ == i) break;
  const population_member m = population_tree(family, member);
  options.seed = static_cast<std::uint32_t>(i) + 1u;
  return approach_sequence(m.tree, options);
}

}  // namespace perch::support
