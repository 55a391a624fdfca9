// SPDX-License-Identifier: BSL-1.0
/// \file
/// Scorers: the paper's multi-criteria penalty (eq. 3) and small single-criterion scorers to
/// build others with `weighted_sum`.
#pragma once

#include <cmath>
#include <string_view>

#include "perch/analysis/measures.hpp"
#include "perch/core/result.hpp"

namespace perch {

/// Paper eq. 3: P = Σⱼ λⱼ·|pⱼ − p*ⱼ| / (pⱼ^max − pⱼ^min), j ∈ {slope, diameter}; lowest wins.
/// Defaults: the tendon claw (λ_slope 0.8, λ_diameter 0.2; slope 0–35° with ideal 0°;
/// claw-region diameter 30–110 mm with ideal the minimum, which leaves the most payload).
/// λ must be ≥ 0 and sum to 1 within 1e-4 (`errc::weights_not_normalised`, never a float ==).
/// Curvature is a filter only (paper §"Exemplar results").
struct pli_penalty {
  static constexpr std::string_view name = "pli_penalty";
  float lambda_slope = 0.8f;
  float lambda_diameter = 0.2f;
  float slope_min_deg = 0.0f;
  float slope_max_deg = 35.0f;
  float ideal_slope_deg = 0.0f;
  float diameter_min_mm = 30.0f;
  float diameter_max_mm = 110.0f;
  float ideal_diameter_mm = 30.0f;

  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return lambda_slope * std::abs(m.slope_deg - ideal_slope_deg) / (slope_max_deg - slope_min_deg) +
           lambda_diameter * std::abs(m.claw_diameter_mm - ideal_diameter_mm) /
               (diameter_max_mm - diameter_min_mm);
  }
  [[nodiscard]] status validate() const noexcept {
    for (const float v : {lambda_slope, lambda_diameter, slope_min_deg, slope_max_deg,
                          ideal_slope_deg, diameter_min_mm, diameter_max_mm, ideal_diameter_mm})
      if (!std::isfinite(v)) return fail(errc::invalid_parameter, "pli_penalty");
    if (lambda_slope < 0 || lambda_diameter < 0 ||
        std::abs(lambda_slope + lambda_diameter - 1.0f) > 1e-4f)
      return fail(errc::weights_not_normalised, "pli_penalty.lambda");
    if (!(slope_max_deg > slope_min_deg)) return fail(errc::range_inverted, "pli_penalty.slope");
    if (!(diameter_max_mm > diameter_min_mm))
      return fail(errc::range_inverted, "pli_penalty.diameter");
    return {};
  }
};

/// Penalty growing with the window's largest curvature: |κ|max / `scale_per_mm`, capped at 1.
/// For users who want straightness in the ranking, not only as a filter.
struct curvature_penalty {
  static constexpr std::string_view name = "curvature_penalty";
  float scale_per_mm = 1.0f / 150.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    const float p = m.curvature_max_per_mm / scale_per_mm;
    return p < 1.0f ? p : 1.0f;
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(scale_per_mm > 0 && std::isfinite(scale_per_mm)))
      return fail(errc::invalid_parameter, "curvature_penalty.scale_per_mm");
    return {};
  }
};

/// Penalty for a long lever arm (bending): horizontal distance from the branch origin divided
/// by `scale_mm`, capped at 1. Prefers perches near where a branch leaves its parent.
struct lever_penalty {
  static constexpr std::string_view name = "lever_penalty";
  float scale_mm = 2000.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    const float p = m.origin_horizontal_mm / scale_mm;
    return p < 1.0f ? p : 1.0f;
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(scale_mm > 0 && std::isfinite(scale_mm)))
      return fail(errc::invalid_parameter, "lever_penalty.scale_mm");
    return {};
  }
};

}  // namespace perch
