// SPDX-License-Identifier: BSL-1.0
// The one place the perch tool turns a platform's name and a scale choice into types: every
// `find_perch` the tool runs is called here, each platform with each scale policy (compiled once,
// in perch_find_perch_instances), not in every subcommand that analyses masks.
#include <type_traits>

#include "support/find_perch_instances.hpp"
#include "tool.hpp"

namespace perch::tool {

namespace {

/// Calls `f(platform)` with a default-constructed value of the platform type `id` names.
/// Every branch must return the same type.
template <class F>
decltype(auto) visit_platform(platform_id id, F&& f) {
  switch (id) {
    case platform_id::tensile_tether:
      return f(tensile_tether{});
    case platform_id::metamorphic:
      return f(metamorphic_quadrotor{});
    case platform_id::ornithopter:
      return f(ornithopter{});
    case platform_id::treecreeper:
      return f(treecreeper{});
    case platform_id::tendon_claw:
      break;
  }
  return f(tendon_claw{});
}

/// Calls `f(policy)` with the scale policy `scale` names (`scale_kind::depth` needs `depth_mm`).
/// Every branch must return the same type.
template <class F>
decltype(auto) visit_scale(const scale_config& scale, F&& f) {
  switch (scale.kind) {
    case scale_kind::fixed:
      return f(fixed_scale{scale.mm_per_px, scale.uncertainty.value_or(0.0f)});
    case scale_kind::depth:
      return f(depth_scale{scale.depth_mm->view(), scale.intrinsics,
                           scale.uncertainty.value_or(0.0f)});
    case scale_kind::trunk_prior:
      break;
  }
  return f(trunk_prior{scale.trunk_mm,
                       scale.uncertainty.value_or(trunk_prior{}.relative_uncertainty)});
}

}  // namespace

platform_limits limits_of(platform_id id) {
  return visit_platform(id, [](const auto& p) {
    platform_limits out;
    out.drone_width_mm = p.geometry.drone_width_mm;
    out.claw_width_mm = p.geometry.claw_width_mm;
    out.mass_kg = p.geometry.mass_kg;
    for_each_leaf(p.constraints, [&](const auto& leaf, std::size_t) {
      using leaf_type = std::remove_cvref_t<decltype(leaf)>;
      if constexpr (std::is_same_v<leaf_type, diameter_range>) {
        out.diameter_min_mm = leaf.min_mm;
        out.diameter_max_mm = leaf.max_mm;
      } else if constexpr (std::is_same_v<leaf_type, max_slope>) {
        out.slope_max_deg = leaf.max_deg;
      } else if constexpr (std::is_same_v<leaf_type, min_slope>) {
        out.slope_min_deg = leaf.min_deg;
        out.has_min_slope = true;
      } else if constexpr (std::is_same_v<leaf_type, max_bend>) {
        out.bend_max_deg = leaf.max_deg;
      } else if constexpr (std::is_same_v<leaf_type, image_border>) {
        out.border_px = leaf.margin_px;
      } else if constexpr (std::is_same_v<leaf_type, resolved_diameter>) {
        out.resolution_px = leaf.uncertainty_px;
      } else if constexpr (std::is_same_v<leaf_type, bending_stress>) {
        out.mass_kg = leaf.mass_kg;
        out.max_stress_mpa = leaf.modulus_of_rupture_mpa / (leaf.safety_factor * leaf.load_factor);
      } else if constexpr (std::is_same_v<leaf_type, clearance>) {
        out.has_clearance = true;
        out.clearance_mm = leaf.margin_mm;
        out.clearance_uncertainty_px = leaf.uncertainty_px;
      }
    });
    return out;
  });
}

platform_geometry geometry_of(platform_id id) {
  return visit_platform(id, [](const auto& p) { return p.geometry; });
}

result<perch_result> find_with(image_view<const std::uint8_t> mask, const run_config& config,
                               const perch_options& options, workspace& ws) {
  return visit_platform(config.platform, [&](const auto& platform) {
    return visit_scale(config.scale, [&](const auto& scale) { return find_perch(mask, platform, scale, ws, options); });
  });
}

result<perch_result> find_in_frame(const image<std::uint8_t>& mask, const run_config& config, const run_config* depth,
                                   workspace& ws, bool& depth_dropped) {
  depth_dropped = false;
  if (depth == nullptr) return find_with(mask.view(), config, perch_options_of(config), ws);
  auto found = find_with(mask.view(), *depth, perch_options_of(*depth), ws);
  if (found || found.error().code != errc::no_valid_depth) return found;
  depth_dropped = true;
  return find_with(mask.view(), config, perch_options_of(config), ws);
}

}  // namespace perch::tool
