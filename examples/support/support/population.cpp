// SPDX-License-Identifier: BSL-1.0
// population.hpp's population members, compiled once into perch_support.
#include "support/population.hpp"

namespace perch::support {

namespace detail::population {

/// Image sizes of the population (4:3), smallest first.
inline constexpr int widths[] = {640, 800, 960, 1280};

/// A small deterministic hash of (i, salt) for choosing knobs: the same member is the same tree
/// everywhere, whatever else the population holds.
[[nodiscard]] constexpr std::uint32_t mix(int i, std::uint32_t salt) noexcept {
  std::uint32_t h = static_cast<std::uint32_t>(i) * 0x9E3779B9u + salt * 0x85EBCA6Bu;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  return h;
}
/// A value in [lo, hi] from (i, salt).
[[nodiscard]] constexpr float pick(int i, std::uint32_t salt, float lo, float hi) noexcept {
  return lo + (hi - lo) * static_cast<float>(mix(i, salt) % 10001u) / 10000.0f;
}
[[nodiscard]] constexpr bool chance(int i, std::uint32_t salt, float p) noexcept {
  return pick(i, salt, 0.0f, 1.0f) < p;
}

void add(std::string& kind, const char* what) {
  if (!kind.empty()) kind += '+';
  kind += what;
}

}  // namespace detail::population

population_member arcs_draw(int i, int draw, int magnify) {
  namespace p = detail::population;
  population_member m;
  m.family = tree_family::arcs;
  m.index = i;
  tree_options o;
  o.width = p::widths[i % 4] * magnify;
  o.height = o.width * 3 / 4;
  o.seed = 7000u + static_cast<std::uint32_t>(i) + 100003u * static_cast<std::uint32_t>(draw);
  // The trunk 3.5–8 % of the width: 1.8–8 mm/px at the base sizes.
  o.mm_per_px = 180.0f / (p::pick(i, 1, 0.035f, 0.08f) * static_cast<float>(o.width));
  o.levels = 2 + static_cast<int>(p::mix(i, 2) % 2u);
  o.branches_per_node = 2 + static_cast<int>(p::mix(i, 3) % 2u);
  o.side_limbs = static_cast<int>(p::mix(i, 4) % 3u);
  o.wide_side_angles = p::chance(i, 5, 0.5f);
  if (!wishes_perch(i)) {
    o.perches = perch_supply::none;
    m.built_without_perch = true;
    p::add(m.kind, "none");
  }
  const float noise = 1.0f + 0.0016f * static_cast<float>(o.width);
  if (p::chance(i, 6, 0.35f)) {
    o.noise = noise;
    o.twigs = 4 + static_cast<int>(p::mix(i, 7) % 8u);
    o.holes = static_cast<int>(p::mix(i, 8) % 3u);
    p::add(m.kind, "noisy");
  }
  if (p::chance(i, 9, 0.4f)) {
    o.bending = p::pick(i, 10, 0.3f, 1.0f);
    p::add(m.kind, "bent");
  }
  if (p::chance(i, 11, 0.25f)) {
    o.kinks = 1 + static_cast<int>(p::mix(i, 12) % 2u);
    p::add(m.kind, "kinks");
  }
  if (p::chance(i, 13, 0.25f)) {
    o.crossings = 1 + static_cast<int>(p::mix(i, 14) % 2u);
    p::add(m.kind, "crossings");
  }
  if (p::chance(i, 15, 0.25f)) {
    o.second_tree = p::pick(i, 16, 0.4f, 0.7f);
    p::add(m.kind, "second");
  }
  if (p::chance(i, 17, 0.25f)) {
    o.fragments = 1 + static_cast<int>(p::mix(i, 18) % 3u);
    p::add(m.kind, "fragments");
  }
  if (m.kind.empty()) m.kind = "clean";
  m.tree = make_tree(o);
  return m;
}

population_member colonisation_draw(int i, int draw, int magnify) {
  namespace p = detail::population;
  population_member m;
  m.family = tree_family::colonisation;
  m.index = i;
  colonisation_options o;
  o.width = p::widths[2 + i % 2] * magnify;  // crowns need room: 960 or 1280 px
  o.height = o.width * 3 / 4;
  o.seed = 9000u + static_cast<std::uint32_t>(i) + 100003u * static_cast<std::uint32_t>(draw);
  // The trunk 2.5–6 % of the width (a crown 8–20 trunks wide), 150–300 mm but at most 8 mm/px
  // (the scales of a drone's camera near a tree: 1.5–8 mm/px).
  const float trunk_share = p::pick(i, 22, 0.025f, 0.06f);
  constexpr float coarsest_mm_per_px = 8.0f;
  o.trunk_diameter_mm = std::min(p::pick(i, 21, 150.0f, 300.0f),
                                 coarsest_mm_per_px * trunk_share * static_cast<float>(o.width));
  o.mm_per_px = o.trunk_diameter_mm / (trunk_share * static_cast<float>(o.width));
  // Columnar crowns (steep limbs only) hardly ever offer a perch: they are the no-perch
  // members, with a share of the others' forms; the members wished a perch take the others.
  constexpr crown_form forms[] = {crown_form::decurrent, crown_form::excurrent,
                                  crown_form::irregular, crown_form::columnar};
  constexpr const char* form_names[] = {"decurrent", "excurrent", "irregular", "columnar"};
  const int form = wishes_perch(i) ? i % 3 : i % 4 == 0 ? 3 : i % 3;
  o.form = forms[form];
  p::add(m.kind, form_names[form]);
  if (p::chance(i, 23, 0.35f)) {
    o.noise = 1.0f + 0.0016f * static_cast<float>(o.width);
    o.twigs = 4 + static_cast<int>(p::mix(i, 24) % 8u);
    o.holes = static_cast<int>(p::mix(i, 25) % 3u);
    p::add(m.kind, "noisy");
  }
  if (p::chance(i, 26, 0.3f)) {
    o.overflow = p::pick(i, 27, 0.1f, 0.4f);
    p::add(m.kind, "overflow");
  }
  if (p::chance(i, 28, 0.25f)) {
    o.second_tree = p::pick(i, 29, 0.4f, 0.7f);
    p::add(m.kind, "second");
  }
  if (p::chance(i, 30, 0.25f)) {
    o.fragments = 1 + static_cast<int>(p::mix(i, 31) % 3u);
    p::add(m.kind, "fragments");
  }
  m.tree = make_colonisation_tree(o);
  return m;
}

population_member sympodial_draw(int i, int draw, int magnify) {
  namespace p = detail::population;
  constexpr int widths[] = {640, 800, 1024, 1280, 1600, 2000};
  population_member m;
  m.family = tree_family::sympodial;
  m.index = i;
  sympodial_options o;
  o.width = widths[p::mix(i, 40) % 6u] * magnify;
  o.height = o.width * 3 / 4;
  o.seed = 31000u + static_cast<std::uint32_t>(i) + 100003u * static_cast<std::uint32_t>(draw);
  // The trunk 120–350 mm over 2.5–9 % of the width, the scale kept in 1.5–8 mm/px.
  o.trunk_diameter_mm = p::pick(i, 41, 120.0f, 350.0f);
  const float share = p::pick(i, 42, 0.025f, 0.09f);
  o.mm_per_px = std::clamp(o.trunk_diameter_mm * static_cast<float>(magnify) / (share * static_cast<float>(o.width)),
                           1.5f, 8.0f) / static_cast<float>(magnify);
  constexpr tree_architecture forms[] = {tree_architecture::sympodial, tree_architecture::monopodial,
                                         tree_architecture::mixed};
  o.architecture = wishes_perch(i) ? forms[p::mix(i, 43) % 3u] : tree_architecture::fastigiate;
  p::add(m.kind, to_string(o.architecture));
  o.depth = p::pick(i, 44, 0.2f, 0.9f);
  o.crown = p::pick(i, 45, 0.9f, 1.5f);
  if (p::chance(i, 46, 0.25f)) {
    o.crown = p::pick(i, 47, 1.6f, 2.4f);
    p::add(m.kind, "overflow");
  }
  if (p::chance(i, 48, 0.35f)) {
    o.droop = p::pick(i, 49, 0.3f, 0.8f);
    p::add(m.kind, "droop");
  }
  if (p::chance(i, 50, 0.5f)) {
    o.bending = p::pick(i, 51, 0.3f, 1.0f);
    p::add(m.kind, "bent");
  }
  if (p::chance(i, 52, 0.3f)) {
    o.kinks = 1 + static_cast<int>(p::mix(i, 53) % 2u);
    p::add(m.kind, "kinks");
  }
  if (p::chance(i, 54, 0.4f)) {
    o.stubs = 1 + static_cast<int>(p::mix(i, 55) % 5u);
    p::add(m.kind, "stubs");
  }
  o.twigs = static_cast<int>(p::mix(i, 56) % 24u);
  if (p::chance(i, 57, 0.4f)) {
    o.foliage = p::pick(i, 58, 0.3f, 0.9f);
    p::add(m.kind, "foliage");
  }
  // Rasterisation: every member has its own threshold; some are soft, rough, biased.
  o.threshold = p::pick(i, 59, 0.3f, 0.7f);
  if (p::chance(i, 60, 0.5f)) {
    o.softness_px = p::pick(i, 61, 0.3f, 1.5f);
    p::add(m.kind, "soft");
  }
  if (p::chance(i, 62, 0.4f)) {
    o.roughness = p::pick(i, 63, 0.1f, 0.35f);
    p::add(m.kind, "rough");
  }
  if (p::chance(i, 64, 0.3f)) {
    o.outline_bias_px = p::chance(i, 65, 0.5f) ? 1 : -1;
    p::add(m.kind, o.outline_bias_px > 0 ? "dilated" : "eroded");
  }
  if (p::chance(i, 66, 0.35f)) {
    o.holes = 1 + static_cast<int>(p::mix(i, 67) % 4u);
    p::add(m.kind, "holes");
  }
  if (p::chance(i, 68, 0.3f)) {
    o.occlusions = 1 + static_cast<int>(p::mix(i, 69) % 3u);
    p::add(m.kind, "occluded");
  }
  if (p::chance(i, 70, 0.3f)) {
    o.broken = 1 + static_cast<int>(p::mix(i, 71) % 3u);
    p::add(m.kind, "broken");
  }
  if (p::chance(i, 72, 0.3f)) {
    o.fragments = 1 + static_cast<int>(p::mix(i, 73) % 4u);
    p::add(m.kind, "fragments");
  }
  if (p::chance(i, 74, 0.25f)) {
    o.second_tree = p::pick(i, 75, 0.4f, 0.8f);
    p::add(m.kind, "second");
  }
  if (o.mm_per_px >= 5.0f) p::add(m.kind, "coarse");
  m.tree = make_sympodial_tree(o);
  return m;
}

population_member population_tree(tree_family family, int i, int magnify) {
  const bool wish = wishes_perch(i);
  population_member m;
  for (int draw = 0; draw < max_draws; ++draw) {
    m = family == tree_family::arcs           ? arcs_draw(i, draw, magnify)
        : family == tree_family::colonisation ? colonisation_draw(i, draw, magnify)
                                              : sympodial_draw(i, draw, magnify);
    m.wished_perch = wish;
    m.draws = draw + 1;
    m.wish_met = perch_truth(m.tree).has_perch() == wish;
    if (m.wish_met) break;
  }
  return m;
}

}  // namespace perch::support
