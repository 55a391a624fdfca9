// End-to-end accuracy of find_perch on synthetic trees with ground truth (issue 5, item 7): on a
// population of generated trees with known scale, the chosen perch must lie on a truly feasible
// stretch (examples/support/support/synthetic_tree.hpp, `perch_truth`) in ≥ 95 % of the trees that
// have one, and trees built without any feasible perch must give `no_perch`.
//
// STATUS: the pipeline reaches 95.2 % (159 of 167), the target, and picks a wrong site
// on 3 trees. Of the 6 misses ("no perch though one exists"), 3 have a claw diameter within a
// pixel of the claw's 30 mm minimum plus the constraint's half-pixel margin (43, 204, 234), and
// 3 have one true stretch about one window long, where the trimming at a junction is 1-6 px
// more cautious than the truth (52, 68, 138; on 68 the limb is split at a side limb too thick
// for a twig, and its own continuation trims it at the base: see the README). The wrong sites:
// 1 "diameter" (a noisy outline read ~1 px wide near the 30 mm minimum: 34; the lower-tercile
// test of `diameter_range` fixed two more such trees, 41 and 64), 1 junction (54: a limb of
// the second tree touches this one tip to tip, and the skeleton runs on through the contact),
// 1 on a tree without a true perch (196). The printed failures say which.
// Two rules took it from 155 to 159: pinholes filled before the skeleton
// (`perch_options::max_hole_px`; a one-pixel hole made the skeleton loop round it and cut the
// limb in pieces on 51, 72 and 134), and a leaf cut by the image's edge never pruned as weak
// (`prune_skeleton_graph`'s `image`; on 94 the stub of a fork's limb leaving the picture was
// pruned, and the window ran over the fork).
// The checks below hold the measured levels as regression floors.
#include "perch/pli.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "support/synthetic_tree.hpp"

namespace {

namespace st = perch::support;

struct member {
  st::tree_options options;
  const char* kind = "clean";
};

/// Tree i of the population. Sizes 480×360, 640×480, 800×600, 960×720 in turn, each `magnify`
/// times larger (the same trees on a finer pixel grid); the 180 mm trunk is 6–10 % of the width
/// (1.9–6.3 mm/px at magnify 1); by i mod 10: 0 and 5 no feasible perch (`perch_supply::none`,
/// every other one of the 5s noisy with twigs), 1 noisy (outline noise, twigs, holes), 2 two
/// crossing limbs, 3 a second tree, 4 all of these at once, else clean.
member population(int i, int magnify = 1) {
  member m;
  st::tree_options& o = m.options;
  constexpr int widths[] = {480, 640, 800, 960};
  o.width = widths[i % 4] * magnify;
  o.height = o.width * 3 / 4;
  o.seed = 1000u + static_cast<std::uint32_t>(i);
  const float share = 0.06f + 0.01f * static_cast<float>((i / 4) % 5);
  o.trunk_diameter_mm = 180.0f;
  o.mm_per_px = 180.0f / (share * static_cast<float>(o.width));
  o.levels = 3;
  o.side_limbs = 1 + (i / 7) % 2;
  const float noise = 1.0f + 0.0016f * static_cast<float>(o.width);
  switch (i % 10) {
    case 0:
    case 5:
      o.perches = st::perch_supply::none;
      m.kind = "none";
      if (i % 20 == 5) {
        o.noise = noise;
        o.twigs = 8;
        m.kind = "none+noisy";
      }
      break;
    case 1:
      o.noise = noise;
      o.twigs = 10;
      o.holes = 2;
      m.kind = "noisy";
      break;
    case 2:
      o.crossings = 2;
      m.kind = "crossings";
      break;
    case 3:
      o.second_tree = 0.6f;
      m.kind = "second";
      break;
    case 4:
      o.crossings = 1;
      o.second_tree = 0.5f;
      o.noise = noise;
      o.twigs = 6;
      m.kind = "mixed";
      break;
    default:
      break;
  }
  return m;
}

constexpr int population_size = 240;

/// How far (px) the reported centre may sit from a feasible window centre: the centre is a
/// skeleton pixel (rounded, ±1 px from the true centreline), and windows start where the
/// skeleton's junction nodes are, which sit up to about a limb radius from where the limbs'
/// surfaces meet (the truth's junction rule): 3 px + 3 % of the window.
float tolerance_px(const st::perch_truth& truth) { return 3.0f + 0.03f * truth.window_px(); }

}  // namespace

TEST_CASE("synthetic trees: the no-perch trees have no feasible stretch, the others mostly do") {
  int with = 0, natural = 0;
  for (int i = 0; i < population_size; ++i) {
    const member m = population(i);
    const st::synthetic_tree tree = st::make_tree(m.options);
    const st::perch_truth truth(tree);
    if (m.options.perches == st::perch_supply::none) {
      CHECK_MESSAGE(!truth.has_perch(), "tree " << i << " (" << m.kind << ")");
    } else {
      ++natural;
      with += truth.has_perch() ? 1 : 0;
    }
  }
  MESSAGE(with << " of " << natural << " natural trees have a feasible stretch");
  CHECK(with * 2 > natural);
}

TEST_CASE("find_perch: the chosen perch lies on a truly feasible stretch (known scale)") {
  perch::workspace ws;
  int correct = 0, incorrect = 0, missed = 0, correct_none = 0, errors = 0;
  int with_truth = 0, without_truth = 0;
  int built_none = 0, built_none_no_perch = 0;  // trees built with perch_supply::none
  std::ostringstream failures;
  std::map<std::string, int> why;  // truth verdict at the wrongly chosen site
  int near_misses = 0;              // wrong sites within 4 tolerances of a feasible centre
  for (int i = 0; i < population_size; ++i) {
    const member m = population(i);
    const st::synthetic_tree tree = st::make_tree(m.options);
    const st::perch_truth truth(tree);
    auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{},
                                   perch::fixed_scale{tree.mm_per_px}, ws);
    if (!found) {
      ++errors;
      failures << "tree " << i << " (" << m.kind << "): error " << found.error().message() << "\n";
      continue;
    }
    const bool has = truth.has_perch();
    if (m.options.perches == st::perch_supply::none) {
      ++built_none;
      built_none_no_perch += found->outcome == perch::perch_outcome::no_perch ? 1 : 0;
    }
    (has ? with_truth : without_truth) += 1;
    if (found->outcome != perch::perch_outcome::found) {
      if (has) {
        ++missed;
        failures << "tree " << i << " (" << m.kind << ", " << m.options.width << "x"
                 << m.options.height << ", " << tree.mm_per_px << " mm/px): no perch, truth has "
                 << truth.stretches().size() << " stretches\n";
      } else {
        ++correct_none;
      }
      continue;
    }
    const perch::perch_site& best = found->sites.front();
    const Eigen::Vector2f p(static_cast<float>(best.window.centre.x),
                            static_cast<float>(best.window.centre.y));
    const st::site_match near = truth.nearest_site(p);
    if (has && near.distance_px <= tolerance_px(truth)) {
      ++correct;
      continue;
    }
    ++incorrect;
    const st::limb_location at = st::locate(tree, p, st::limb_set::without_twigs);
    const st::window_truth w = truth.window(at.limb, at.arc_px);
    ++why[has ? st::to_string(w.verdict) : "no truth perch"];
    near_misses += near.distance_px <= 4.0f * tolerance_px(truth) ? 1 : 0;
    failures << "tree " << i << " (" << m.kind << ", " << m.options.width << "x"
             << m.options.height << ", " << tree.mm_per_px << " mm/px): site (" << p.x() << ", "
             << p.y() << ") slope " << best.window.slope_deg << " claw "
             << best.window.claw_diameter_mm << " mm kmax " << best.window.curvature_max_per_mm
             << "; truth: limb " << at.limb << " arc " << at.arc_px << " off-axis "
             << at.distance_px << " px, window there " << st::to_string(w.verdict) << " (slope "
             << w.slope_deg << ", claw " << w.claw_diameter_mm << " mm, clearance gap "
             << w.clearance_mm << " mm), nearest feasible centre " << near.distance_px
             << " px (tolerance " << tolerance_px(truth) << ")\n";
  }
  const int wrong_when_none = without_truth - correct_none;  // found a perch where none exists
  const int attempts_with = with_truth;
  const double rate =
      attempts_with > 0 ? static_cast<double>(correct) / static_cast<double>(attempts_with) : 0.0;
  MESSAGE("trees " << population_size << ": " << with_truth << " with a feasible stretch, "
                   << without_truth << " without; correct location " << correct
                   << ", incorrect location " << incorrect << " (of which " << wrong_when_none
                   << " where none exists), no result though one existed " << missed
                   << ", correctly no result " << correct_none << ", errors " << errors
                   << "; success rate where one exists " << rate * 100.0 << " %");
  std::ostringstream verdicts;
  for (const auto& [verdict, count] : why) verdicts << " " << verdict << " " << count;
  MESSAGE("incorrect locations by the truth's verdict at the chosen centre:" << verdicts.str()
          << "; within 4 tolerances of a feasible centre: " << near_misses);
  MESSAGE("failures:\n" << failures.str());
  CHECK(errors == 0);
  MESSAGE("trees built without a perch: " << built_none << ", find_perch said no_perch for "
                                           << built_none_no_perch);
  CHECK(built_none >= 20);
  CHECK(built_none_no_perch == built_none);
  CHECK(without_truth >= 20);
  CHECK(with_truth >= 100);
  MESSAGE("issue 5 target: 95 % where a perch exists; measured " << 100.0 * rate << " %");
  CHECK(rate >= 0.95);    // the target (measured 95.2 %, 159 of 167)
  CHECK(incorrect <= 3);  // measured: 3 wrong sites, 1 on a tree without a truth perch
  CHECK(wrong_when_none <= 1);
}

/// The population at `magnify` analysed at `downscale`: how often the best site lies on a truly
/// feasible stretch, and how often a tree without one gets a perch.
struct downscale_score {
  int with_truth = 0, correct = 0, without_truth = 0, wrong_when_none = 0, errors = 0;
  [[nodiscard]] double rate() const {
    return with_truth > 0 ? static_cast<double>(correct) / static_cast<double>(with_truth) : 0.0;
  }
};

downscale_score score_downscaled(float downscale, int magnify) {
  perch::workspace ws;
  perch::perch_options options;
  options.downscale = downscale;
  downscale_score score;
  for (int i = 0; i < population_size; ++i) {
    const member m = population(i, magnify);
    const st::synthetic_tree tree = st::make_tree(m.options);
    const st::perch_truth truth(tree);
    auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{},
                                   perch::fixed_scale{tree.mm_per_px}, ws, options);
    if (!found) {
      ++score.errors;
      continue;
    }
    const bool has = truth.has_perch();
    (has ? score.with_truth : score.without_truth) += 1;
    if (found->outcome != perch::perch_outcome::found) continue;
    const perch::pixel c = found->sites.front().window.centre;
    const Eigen::Vector2f p(static_cast<float>(c.x), static_cast<float>(c.y));
    if (!has) ++score.wrong_when_none;
    if (has && truth.nearest_site(p).distance_px <= tolerance_px(truth)) ++score.correct;
  }
  MESSAGE("magnify " << magnify << ", downscale " << downscale
                     << ": success rate where a perch exists " << 100.0 * score.rate() << " % ("
                     << score.correct << " of " << score.with_truth
                     << "); a perch where none exists " << score.wrong_when_none << " of "
                     << score.without_truth);
  return score;
}

// Under AddressSanitizer the population takes minutes per pass; the downscale passes run the
// same pipeline code as the main case (and pli_invariants_test covers downscale's memory
// safety), so the sanitizer workflow leaves them out.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool sanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool sanitized = true;
#else
constexpr bool sanitized = false;
#endif
#else
constexpr bool sanitized = false;
#endif

TEST_CASE("find_perch: the accuracy cost of perch_options::downscale (issue 8)" *
          doctest::skip(sanitized)) {
  // The same population analysed at reduced resolution. These trees are 480-960 px wide, so
  // factor 0.25 leaves 120-240 px and limbs of 2-8 px: a harsh test, reported for the README.
  for (const float factor : {0.5f, 0.25f}) {
    const downscale_score score = score_downscaled(factor, 1);
    CHECK(score.errors == 0);
    // Regression floors at the measured levels (79.6 % at 0.5, 61.7 % at 0.25).
    CHECK(score.rate() >= (factor == 0.5f ? 0.79 : 0.61));
  }
}

// Camera-sized frames: the population four times larger (1920-3840 px wide, where downscale is
// meant to be used). About 1.5 minutes in an optimised build, so CI skips it; run it with
//   build/test/tests/pli_accuracy_test --no-skip -tc='*camera-sized*'
TEST_CASE("find_perch: downscale on camera-sized frames (issue 8)" * doctest::skip()) {
  for (const float factor : {1.0f, 0.5f, 0.25f}) {
    const downscale_score score = score_downscaled(factor, 4);
    CHECK(score.errors == 0);
    // Regression floors at the measured levels (90.3 %, 87.4 %, 87.4 %; a perch on none of
    // the 65 trees without one).
    CHECK(score.rate() >= (factor == 1.0f ? 0.9 : 0.87));
    CHECK(score.wrong_when_none == 0);
  }
}
