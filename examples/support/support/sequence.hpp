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
  approach_sequence(const synthetic_tree& world, const sequence_options& options);

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
  [[nodiscard]] image<std::uint16_t> depth_mm(const sequence_frame& frame) const;

  /// Frame `f` (0 … frames − 1).
  [[nodiscard]] sequence_frame frame(int f) const;

 private:
  /// A straight limb under the trunk's base, down to three heights below the frame.
  void extend_trunk();

  /// The camera path: distance from `start_distance` to 1 (the picture's scale 1/start … 1),
  /// the aim point drifting sideways (and a little up or down), a slow roll swing, shake.
  void plan_camera();

  void plan_dropouts();

  /// The world's limbs moved into the frame by `m` (scale `s`).
  [[nodiscard]] synthetic_tree transformed(const camera_motion& m, float s) const;

  void add_noise(int f, sequence_frame& out) const;

  /// Holes of 1–2 px inside the limbs (a segmenter's misses; `find_perch` fills the smallest).
  static void add_pinholes(detail::tree_random& rng, int count, sequence_frame& out);

  /// Erases a piece of `limb` 1.5 diameters long at `fraction` of its length (a segmenter that
  /// lost it behind a leaf or in glare).
  static void cut(const limb_truth& limb, float fraction, image<std::uint8_t>& mask);

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
[[nodiscard]] approach_sequence evaluation_sequence(int i, sequence_options options = {},
                                                    tree_family family = tree_family::arcs);

}  // namespace perch::support
