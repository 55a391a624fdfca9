// SPDX-License-Identifier: BSL-1.0
/// \file
/// The camera's motion between frames estimated from the masks alone, for when no visual
/// odometry gives it: the junctions and ends of each frame's skeleton graph (from `find_perch`'s
/// result) are keypoints, matched between frames under a 2-D similarity found by RANSAC and
/// refined by least squares over its inliers, which also say how well its scale is known. A
/// mask's flicker adds or removes a few keypoints; the consensus ignores them. Fixed capacity,
/// no allocation, deterministic.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>

#include "perch/pipeline.hpp"
#include "perch/track/motion.hpp"

namespace perch {

/// Options of `motion_estimator`.
struct motion_estimate_options {
  /// The largest shift of a keypoint between frames, as a share of the image's diagonal: the
  /// search radius for its matches. More: faster camera motion is followed, but more wrong
  /// candidate matches are tried.
  float max_shift_share = 0.08f;
  /// A keypoint agrees with a motion when it lands within this many pixels of a keypoint of its
  /// kind (plus 3 % of the keypoint's distance moved, for the skeleton's jitter).
  float inlier_px = 3.0f;
  std::uint32_t iterations = 200;  ///< hypotheses at most (each from one candidate match)
  float max_scale_step = 1.25f;    ///< a frame's zoom is within [1/this, this]
  float max_rotation_deg = 10.0f;  ///< and its roll within ± this
  /// The motion is trusted when at least this share of the smaller keypoint set agrees (and at
  /// least `min_inliers` keypoints).
  float min_inlier_share = 0.3f;
  std::uint32_t min_inliers = 4;
};

/// What `motion_estimator::update` found.
struct motion_estimate {
  /// Previous frame's pixels → this frame's, with its scale's uncertainty from the keypoints'
  /// residuals; when not found the identity, its scale uncertain by `max_scale_step` − 1 (any
  /// zoom the search allows).
  camera_motion motion{};
  bool estimated = false;   ///< a motion was found and trusted
  std::uint32_t keypoints = 0;  ///< this frame's keypoints
  std::uint32_t inliers = 0;    ///< keypoints that agree with the motion
};

/// Estimates each frame's motion from the previous frame's keypoints. Call `update` once per
/// frame, in order, with `find_perch`'s result (before the workspace is reused).
///
/// Method: hypothesise and verify as in RANSAC (Fischler and Bolles, "Random sample consensus",
/// Comm. ACM 24(6), 1981) over candidate matches (keypoints of the same kind, junction or end,
/// within the search radius, of similar radius), with one match per hypothesis and the last
/// frame's zoom and roll as a prior, as in 1-point RANSAC (Civera et al., J. Field Robotics
/// 27(5), 2010): two-match hypotheses drawn at random hit two right matches too rarely among
/// the many look-alike junctions. Hypotheses are taken in order (deterministic, no random
/// draw); the score is the number of previous keypoints that land near a current keypoint of
/// their kind; the best is refined by the least-squares similarity over its inliers (Umeyama,
/// "Least-squares estimation of transformation parameters between two point patterns", IEEE
/// PAMI 13(4), 1991, in 2-D).
class motion_estimator {
 public:
  static constexpr std::size_t max_keypoints = 64;
  static constexpr std::size_t max_matches = 1024;

  explicit motion_estimator(const motion_estimate_options& options = {}) noexcept
      : options_(options) {}

  void reset() noexcept {
    previous_count_ = 0;
    prior_ = {};
  }

  /// The motion from the previous frame given to `update` to `frame`; this frame's keypoints
  /// become the previous ones. The first frame, a frame with too few keypoints, or one whose
  /// keypoints agree with no motion gives the identity, `estimated` false.
  [[nodiscard]] motion_estimate update(const perch_result& frame) noexcept {
    collect(frame, current_, current_count_);
    motion_estimate out;
    out.keypoints = static_cast<std::uint32_t>(current_count_);
    if (previous_count_ >= 2 && current_count_ >= 2) {
      diagonal_ = std::hypot(static_cast<float>(frame.width), static_cast<float>(frame.height));
      out = estimate();
      out.keypoints = static_cast<std::uint32_t>(current_count_);
    }
    if (!out.estimated) out.motion.scale_uncertainty = unknown_scale();
    previous_ = current_;
    previous_count_ = current_count_;
    return out;
  }

 private:
  struct keypoint {
    point2f p;
    float radius;
    bool junction;
  };
  struct match {
    std::uint16_t prev, cur;
  };
  /// z' = a·z + b on complex numbers: a = scale·e^{iθ}.
  struct similarity {
    float ar = 1, ai = 0, bx = 0, by = 0;
    [[nodiscard]] point2f apply(point2f p) const noexcept {
      return {ar * p.x() - ai * p.y() + bx, ai * p.x() + ar * p.y() + by};
    }
  };

  /// The graph's junctions and ends in input pixels; the widest `max_keypoints` when there are
  /// more (thick limbs' junctions are the steadiest). An end within its radius and
  /// `border_px` of the frame's edge is left out: it is where the frame cuts a limb, and it
  /// slides along the limb as the camera moves instead of moving with the tree (as the picture
  /// grows those ends stay on the edge and pull the scale toward 1).
  static void collect(const perch_result& frame, std::array<keypoint, max_keypoints>& out,
                      std::size_t& count) noexcept {
    count = 0;
    const pixel offset = frame.mask.offset;
    const float right = static_cast<float>(frame.width - 1);
    const float bottom = static_cast<float>(frame.height - 1);
    frame.graph.for_each_node([&](const skeleton_node& n) {
      if (n.kind != node_kind::junction && n.kind != node_kind::end) return;
      const keypoint k{frame.mask.to_input(point2f(static_cast<float>(n.position.x + offset.x),
                                                   static_cast<float>(n.position.y + offset.y))),
                       n.radius_px / frame.mask.factor, n.kind == node_kind::junction};
      const float edge =
          std::min(std::min(k.p.x(), right - k.p.x()), std::min(k.p.y(), bottom - k.p.y()));
      if (!k.junction && edge <= k.radius + border_px) return;
      if (count < max_keypoints) {
        out[count++] = k;
        return;
      }
      // Full: replace the thinnest if this one is wider.
      std::size_t thinnest = 0;
      for (std::size_t i = 1; i < count; ++i)
        if (out[i].radius < out[thinnest].radius) thinnest = i;
      if (k.radius > out[thinnest].radius) out[thinnest] = k;
    });
  }

  /// Candidate matches: same kind, within the search radius, radii within a factor 1.6 (plus
  /// a pixel), by previous keypoint.
  void find_matches() noexcept {
    match_count_ = 0;
    const float reach = options_.max_shift_share * diagonal_;
    for (std::size_t i = 0; i < previous_count_; ++i)
      for (std::size_t j = 0; j < current_count_; ++j) {
        const keypoint& a = previous_[i];
        const keypoint& b = current_[j];
        if (a.junction != b.junction || (a.p - b.p).norm() > reach) continue;
        const float lo = std::min(a.radius, b.radius) + 1.0f, hi = std::max(a.radius, b.radius);
        if (hi > 1.6f * lo || match_count_ == max_matches) continue;
        matches_[match_count_++] = {static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(j)};
      }
  }

  static void finish_offset(similarity& s, point2f from, point2f to) noexcept {
    s.bx = to.x() - (s.ar * from.x() - s.ai * from.y());
    s.by = to.y() - (s.ai * from.x() + s.ar * from.y());
  }

  [[nodiscard]] bool plausible(const similarity& s) const noexcept {
    const float scale = std::hypot(s.ar, s.ai);
    const float angle = std::abs(std::atan2(s.ai, s.ar)) * 180.0f / std::numbers::pi_v<float>;
    return scale >= 1.0f / options_.max_scale_step && scale <= options_.max_scale_step &&
           angle <= options_.max_rotation_deg;
  }

  /// For each previous keypoint, its candidate match nearest to where `s` takes it, if near
  /// enough: the count of such inliers and the sum of their squared distances.
  /// `slack` widens the tolerance by that share of a keypoint's distance from `anchor` (a
  /// hypothesis whose scale and rotation are only the prior's is exact at its anchor only).
  std::uint32_t score(const similarity& s, float& residual, bool record, point2f anchor = {0, 0},
                      float slack = 0) noexcept {
    std::uint32_t inliers = 0;
    residual = 0;
    std::size_t k = 0;
    for (std::size_t i = 0; i < previous_count_; ++i) {
      const point2f moved = s.apply(previous_[i].p);
      const float tolerance = options_.inlier_px + 0.03f * (moved - previous_[i].p).norm() +
                              slack * (previous_[i].p - anchor).norm();
      float best = tolerance * tolerance;
      std::int32_t best_cur = -1;
      for (; k < match_count_ && matches_[k].prev == i; ++k) {
        const float d2 = (current_[matches_[k].cur].p - moved).squaredNorm();
        if (d2 <= best) {
          best = d2;
          best_cur = matches_[k].cur;
        }
      }
      if (best_cur < 0) continue;
      if (record) inlier_pairs_[inliers] = {static_cast<std::uint16_t>(i),
                                            static_cast<std::uint16_t>(best_cur)};
      ++inliers;
      residual += best;
    }
    return inliers;
  }

  /// The least-squares similarity over the recorded inlier pairs (Umeyama 1991, 2-D).
  [[nodiscard]] bool refine(std::uint32_t n, similarity& s) const noexcept {
    point2f mp = point2f::Zero(), mq = point2f::Zero();
    for (std::uint32_t k = 0; k < n; ++k) {
      mp += previous_[inlier_pairs_[k].prev].p;
      mq += current_[inlier_pairs_[k].cur].p;
    }
    mp /= static_cast<float>(n);
    mq /= static_cast<float>(n);
    float sr = 0, si = 0, pp = 0;
    for (std::uint32_t k = 0; k < n; ++k) {
      const point2f p = previous_[inlier_pairs_[k].prev].p - mp;
      const point2f q = current_[inlier_pairs_[k].cur].p - mq;
      sr += q.x() * p.x() + q.y() * p.y();
      si += q.y() * p.x() - q.x() * p.y();
      pp += p.squaredNorm();
    }
    if (!(pp > 0)) return false;
    similarity r{sr / pp, si / pp, 0, 0};
    if (!plausible(r)) return false;
    finish_offset(r, mp, mq);
    s = r;
    return true;
  }

  /// Hypotheses: each candidate match (every `stride`-th, at most `iterations`) with the prior's
  /// scale and rotation (the last estimate's: a camera's zoom and roll change slowly) gives a
  /// translation; the few most keypoints agree with (with the slack for the prior's error) are
  /// refined by least squares over their inliers, three times, and judged with the tight
  /// tolerance alone (the slack lets wrong shifts collect look-alike keypoints of a dense crown).
  [[nodiscard]] motion_estimate estimate() noexcept {
    motion_estimate out;
    find_matches();
    shortlist_count_ = 0;
    similarity still = prior_;
    still.bx = still.by = 0;
    float residual = 0;
    keep({still, score(still, residual, false), residual});  // no shift at all
    const std::size_t stride =
        std::max<std::size_t>(1, match_count_ / std::max<std::uint32_t>(options_.iterations, 1));
    for (std::size_t k = 0; k < match_count_; k += stride) {
      similarity s = prior_;
      const point2f from = previous_[matches_[k].prev].p;
      finish_offset(s, from, current_[matches_[k].cur].p);
      const std::uint32_t inliers = score(s, residual, false, from, hypothesis_slack);
      keep({s, inliers, residual});
    }
    // The shortlist refined, then judged with the tight tolerance alone.
    similarity best = still;
    std::uint32_t best_inliers = 0;
    float best_residual = 0;
    for (std::size_t h = 0; h < shortlist_count_; ++h) {
      similarity s = shortlist_[h].s;
      std::uint32_t inliers = 0;
      for (int round = 0; round < 3; ++round) {
        inliers = score(s, residual, true);
        if (inliers < 2 || !refine(inliers, s)) break;
      }
      inliers = score(s, residual, false);
      if (inliers > best_inliers || (inliers == best_inliers && residual < best_residual)) {
        best = s;
        best_inliers = inliers;
        best_residual = residual;
      }
    }
    const float smaller = static_cast<float>(std::min(previous_count_, current_count_));
    if (best_inliers < options_.min_inliers ||
        static_cast<float>(best_inliers) < options_.min_inlier_share * smaller)
      return out;
    out.motion.h = {best.ar, -best.ai, best.bx, best.ai, best.ar, best.by, 0, 0, 1};
    out.estimated = out.motion.valid();
    if (!out.estimated) {
      out.motion = camera_motion::identity();
      return out;
    }
    out.inliers = best_inliers;
    out.motion.scale_uncertainty = scale_uncertainty(best);
    prior_ = best;
    return out;
  }

  /// The scale's uncertainty when the keypoints do not tell it: any zoom the search allows.
  [[nodiscard]] float unknown_scale() const noexcept {
    const float range = options_.max_scale_step - 1.0f;
    return range > 0 ? std::min(range, 1.0f) : 1.0f;
  }

  /// The relative standard uncertainty of `s`'s scale from its inliers' residuals: the
  /// least-squares similarity's coefficients have variance σ²/Σ|p − p̄|², σ² the residual
  /// variance per coordinate over 2n − 4 degrees of freedom (Umeyama 1991; the linear model's
  /// covariance σ²(AᵀA)⁻¹). The inliers' residuals only, so somewhat less than the error (on
  /// the arcs sequences the scale's error is 1.3 times the stated value, RMS).
  [[nodiscard]] float scale_uncertainty(const similarity& s) noexcept {
    float residual = 0;
    const std::uint32_t n = score(s, residual, true);
    if (n < 3) return unknown_scale();
    point2f mean = point2f::Zero();
    for (std::uint32_t k = 0; k < n; ++k) mean += previous_[inlier_pairs_[k].prev].p;
    mean /= static_cast<float>(n);
    float spread = 0;
    for (std::uint32_t k = 0; k < n; ++k)
      spread += (previous_[inlier_pairs_[k].prev].p - mean).squaredNorm();
    const float scale = std::hypot(s.ar, s.ai);
    if (!(spread > 0 && scale > 0)) return unknown_scale();
    const float variance = residual / static_cast<float>(2 * n - 4);
    return std::min(std::sqrt(variance / spread) / scale, 1.0f);
  }

  struct hypothesis {
    similarity s;
    std::uint32_t inliers;
    float residual;
  };

  /// Keeps the `shortlist_size` hypotheses with the most inliers (then the least residual).
  void keep(const hypothesis& h) noexcept {
    auto better = [](const hypothesis& a, const hypothesis& b) {
      return a.inliers > b.inliers || (a.inliers == b.inliers && a.residual < b.residual);
    };
    std::size_t at = shortlist_count_;
    if (shortlist_count_ < shortlist_size) {
      ++shortlist_count_;
    } else if (!better(h, shortlist_[shortlist_size - 1])) {
      return;
    } else {
      at = shortlist_size - 1;
    }
    while (at > 0 && better(h, shortlist_[at - 1])) {
      shortlist_[at] = shortlist_[at - 1];
      --at;
    }
    shortlist_[at] = h;
  }

  static constexpr std::size_t shortlist_size = 8;

  /// How close to the frame's edge, beyond its radius, an end is taken for a cut limb, px.
  static constexpr float border_px = 2.0f;

  /// The share of a keypoint's distance from a hypothesis's anchor its tolerance grows by: a
  /// zoom or roll 6 % (3.4°) off the prior's still finds its inliers.
  static constexpr float hypothesis_slack = 0.06f;

  motion_estimate_options options_;
  std::array<keypoint, max_keypoints> previous_{}, current_{};
  std::size_t previous_count_ = 0, current_count_ = 0;
  std::array<match, max_matches> matches_{};
  std::size_t match_count_ = 0;
  std::array<match, max_keypoints> inlier_pairs_{};
  float diagonal_ = 1;
  similarity prior_{};  ///< the last estimate's scale and rotation
  std::array<hypothesis, shortlist_size> shortlist_{};
  std::size_t shortlist_count_ = 0;
};

}  // namespace perch
