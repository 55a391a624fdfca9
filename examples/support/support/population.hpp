// SPDX-License-Identifier: BSL-1.0
/// \file
/// The synthetic populations perch is measured on: three differently built tree families, each
/// varied widely (sizes, scales, crown forms, bending, kinks, crossings, twigs, pinholes,
/// outline noise, fragments, a second tree, limbs leaving the frame), with the truth of
/// `perch_truth`. For finding failures, not for a score: no member is tuned one by one.
///
///  - `tree_family::arcs` (`make_tree`): forks and side limbs on circular arcs, bent and kinked
///    at will; its no-perch members are built with no feasible perch (`perch_supply::none`).
///  - `tree_family::colonisation` (`make_colonisation_tree`, Runions et al. 2007): crowns grown
///    toward attraction points, decurrent, excurrent, columnar and irregular.
///  - `tree_family::sympodial` (`make_sympodial_tree`): a 3-D turtle's codominant forks,
///    monopodial leaders, mixed and fastigiate crowns, pipe-model diameters with knots, stubs,
///    drawn by sampled coverage thresholded per tree, with segmenter-like defects (foliage,
///    rough outlines, outline bias, occluding leaves, broken thin limbs); built with conventions
///    the other two do not share, to stand for a generator perch has never seen.
///
/// The mix: 15 % of each family's members have no feasible stretch, the rest have one (a
/// population where most trees offer nothing measures only caution). A member's knobs come
/// from its index; its tree is the first of its draws (seeds) whose truth has the wished
/// outcome, so the selection looks at the truth only, never at what the pipeline answers.
///
/// Host code: allocates, no exceptions. Not part of the library.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "support/colonisation_tree.hpp"
#include "support/sympodial_tree.hpp"
#include "support/synthetic_tree.hpp"

namespace perch::support {

/// A generator of trees.
enum class tree_family : std::uint8_t { arcs, colonisation, sympodial };

[[nodiscard]] constexpr std::string_view to_string(tree_family f) noexcept {
  switch (f) {
    case tree_family::arcs: return "arcs";
    case tree_family::colonisation: return "colonisation";
    case tree_family::sympodial: return "sympodial";
  }
  return "unknown";
}

/// The family named `name` (as `to_string` spells it), or none.
[[nodiscard]] constexpr std::optional<tree_family> family_named(std::string_view name) noexcept {
  for (const tree_family f : {tree_family::arcs, tree_family::colonisation, tree_family::sympodial})
    if (to_string(f) == name) return f;
  return std::nullopt;
}

/// One member of a population: its tree and what it was built with.
struct population_member {
  tree_family family = tree_family::arcs;
  int index = 0;
  std::string kind;        ///< the knobs that are on, e.g. "noisy+kinks"
  bool built_without_perch = false;  ///< `perch_supply::none`: must get no perch
  bool wished_perch = true;  ///< the mix asked this member for a feasible stretch (else none)
  int draws = 1;             ///< seeds tried until the truth had the wished outcome
  bool wish_met = true;      ///< false: no draw had it (the last draw is the member)
  synthetic_tree tree;
};

/// Members `i` with `i % no_perch_period < no_perch_members` have no feasible stretch: 15 %.
inline constexpr int no_perch_period = 20;
inline constexpr int no_perch_members = 3;
/// Seeds a member tries for its wished outcome before it keeps the last.
inline constexpr int max_draws = 16;

/// Whether member `i` of a family is to have a feasible stretch.
[[nodiscard]] constexpr bool wishes_perch(int i) noexcept {
  return i % no_perch_period >= no_perch_members;
}

/// Draw `draw` of member `i` of the arcs family at `magnify` times the base size.
[[nodiscard]] population_member arcs_draw(int i, int draw, int magnify = 1);

/// Draw `draw` of member `i` of the colonisation family at `magnify` times the base size.
[[nodiscard]] population_member colonisation_draw(int i, int draw, int magnify = 1);

/// Draw `draw` of member `i` of the sympodial family at `magnify` times the base size: 640x480
/// to 2000x1500, 1.5–8 mm/px, trunks 120–350 mm; members not wished a perch are fastigiate
/// (steep limbs only), the others sympodial, monopodial or mixed. Every knob is drawn from `i`
/// (the draw changes only the seed), so a member keeps its kind across draws.
[[nodiscard]] population_member sympodial_draw(int i, int draw, int magnify = 1);

/// Member `i` of `family`: its first draw whose truth has a feasible stretch if
/// `wishes_perch(i)`, else its first draw without one (at most `max_draws` draws; the truth
/// is computed once per draw).
[[nodiscard]] population_member population_tree(tree_family family, int i, int magnify = 1);

}  // namespace perch::support
