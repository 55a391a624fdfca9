// SPDX-License-Identifier: BSL-1.0
// A sixth platform, composed in user code without touching perch: a sleeve gripper that slides
// a padded collar over the branch. The collar only closes on a stretch of nearly constant
// diameter, so it brings a constraint of its own (`uniform_diameter`) and a scorer of its own
// (`collar_fit`: prefer diameters near the collar's nominal size), mixed with perch's parts.
//
// Usage: custom_platform [SEED]   (runs on a synthetic tree; exit 0 when the pipeline ran)
#include <perch/pli.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "support/synthetic_tree.hpp"

namespace {

/// Rejects windows whose diameter varies by more than `max_spread_mm` (max − min): a collar
/// cannot close on a tapering or knotted stretch. Models `perch::GeometricConstraint`.
struct uniform_diameter {
  static constexpr std::string_view name = "uniform_diameter";
  static constexpr std::string_view unit = "mm";
  float max_spread_mm = 5.0f;
  [[nodiscard]] float operator()(const perch::window_measures& m) const noexcept {
    return (m.diameter_max_mm - m.diameter_min_mm) - max_spread_mm;  // ≤ 0 passes
  }
};

/// Penalty in [0, 1]: how far the claw-region diameter is from the collar's nominal size,
/// relative to `tolerance_mm`. Models `perch::Scorer`.
struct collar_fit {
  static constexpr std::string_view name = "collar_fit";
  float nominal_mm = 50.0f;
  float tolerance_mm = 30.0f;
  [[nodiscard]] float operator()(const perch::window_measures& m) const noexcept {
    const float p = std::abs(m.claw_diameter_mm - nominal_mm) / tolerance_mm;
    return p < 1.0f ? p : 1.0f;
  }
};

/// The platform: geometry, a pack of constraints (perch's and ours), one scorer.
struct sleeve_gripper {  // each number written once: the parts are built from them
  static constexpr std::string_view name = "sleeve-gripper";
  static constexpr float max_slope_deg = 30.0f;
  perch::platform_geometry geometry{.drone_width_mm = 220.0f, .claw_width_mm = 80.0f,
                                    .mass_kg = 1.2f, .grasp_min_mm = 25.0f,
                                    .grasp_max_mm = 80.0f};
  perch::all_of<perch::diameter_range, perch::max_slope, perch::monotonic, uniform_diameter,
                perch::bending_stress>
      constraints{perch::diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  perch::max_slope{max_slope_deg}, perch::monotonic{}, uniform_diameter{},
                  perch::bending_stress{.mass_kg = geometry.mass_kg}};
  perch::weighted_sum<perch::pli_penalty, collar_fit> scorer{
      .weights = {0.6f, 0.4f},
      .parts = {perch::pli_penalty{.slope_max_deg = max_slope_deg,
                                   .diameter_min_mm = geometry.grasp_min_mm,
                                   .diameter_max_mm = geometry.grasp_max_mm,
                                   .ideal_diameter_mm = geometry.grasp_min_mm},
                collar_fit{}}};
};
static_assert(perch::Platform<sleeve_gripper>);

}  // namespace

int main(int argc, char** argv) {
  perch::support::tree_options options;
  options.width = 1280;
  options.height = 960;
  options.seed = argc > 1 ? static_cast<std::uint32_t>(std::strtoul(argv[1], nullptr, 10)) : 3u;
  const perch::support::synthetic_tree tree = perch::support::make_tree(options);

  perch::workspace ws;
  const auto found = perch::find_perch(tree.mask.view(), sleeve_gripper{},
                                       perch::fixed_scale{tree.mm_per_px}, ws);
  if (!found) {
    const std::string_view why = found.error().message();
    std::fprintf(stderr, "custom_platform: %.*s\n", static_cast<int>(why.size()), why.data());
    return 1;
  }
  const std::string_view outcome = perch::to_string(found->outcome);
  std::printf("sleeve-gripper on seed %u: %.*s, %u windows, %u viable\n", options.seed,
              static_cast<int>(outcome.size()), outcome.data(), found->windows, found->viable);
  for (const perch::perch_site& s : found->sites)
    std::printf("  #%u at (%d, %d): slope %.1f deg, diameter %.1f mm (spread %.1f mm), penalty %.3f\n",
                s.rank, s.window.centre.x, s.window.centre.y, static_cast<double>(s.window.slope_deg),
                static_cast<double>(s.window.claw_diameter_mm),
                static_cast<double>(s.window.diameter_max_mm - s.window.diameter_min_mm),
                static_cast<double>(s.penalty));
  std::printf("rejected by:");
  for (const perch::rejection_count& r : found->rejections)
    std::printf(" %.*s %u,", static_cast<int>(r.constraint.size()), r.constraint.data(), r.windows);
  std::printf("\n");
  return 0;
}
