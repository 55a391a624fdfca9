// SPDX-License-Identifier: BSL-1.0
// End-to-end accuracy of find_perch on synthetic trees with ground truth (issue 24): two
// differently built tree families (examples/support/support/population.hpp: forks and side limbs
// on bent arcs; crowns grown by space colonisation), each varied widely, judged by the physical
// definition of a safe perch computed from the drawn geometry (`perch_truth`: clearance from
// every other limb, local slope, bend over a drone width, border, resolved diameter, supported,
// bending stress). A chosen perch is right when it lies within 3 px + 3 % of a window of a truly
// feasible window centre.
//
// What matters most is the wrong answers: a perch on a tree with no feasible stretch, or a
// perch off every feasible stretch. The checks hold the measured levels as regression floors;
// the printed failures say which rule the chosen point breaks and by how much.
#include "perch/pli.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "support/find_perch_instances.hpp"
#include "support/population.hpp"

namespace {

namespace st = perch::support;

// Under AddressSanitizer the population takes minutes per pass: the sanitizer workflow runs a
// smaller population, and leaves out the extra passes (trunk prior, downscale), which run the
// same pipeline code as the main case.
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

/// Members of each family in the population: the arcs family 200 (10 s), the colonisation
/// family 100 (its members take about 0.3 s each to draw and judge; `perch eval --population`
/// runs any number). Under the sanitizers a quarter of the arcs and an eighth of the
/// colonisation family (12 members, 3 of them without a feasible stretch): drawing a colonisation
/// member (up to 16 draws, each judged by the truth) is most of the sanitizer workflow's time.
[[nodiscard]] constexpr int family_size(st::tree_family family) {
  if (family == st::tree_family::arcs) return sanitized ? 200 / 4 : 200;
  return sanitized ? 100 / 8 : 100;
}

/// Whether this run scores `family`: the environment's PERCH_ACCURACY_FAMILY names one (CTest
/// runs the arcs and the colonisation family as two tests, side by side), every family when unset.
[[nodiscard]] bool scored(st::tree_family family) {
  const char* only = std::getenv("PERCH_ACCURACY_FAMILY");
  return only == nullptr || *only == '\0' || st::to_string(family) == std::string_view(only);
}

/// The members [0, family_size) of `family` at base size, drawn once for every test case.
const std::vector<st::population_member>& population(st::tree_family family) {
  static std::vector<st::population_member> families[2];
  auto& members = families[family == st::tree_family::arcs ? 0 : 1];
  if (members.empty())
    for (int i = 0; i < family_size(family); ++i) members.push_back(st::population_tree(family, i));
  return members;
}

/// How far (px) the reported centre may sit from a feasible window centre: the centre is a
/// skeleton pixel (rounded, ±1 px from the true centreline), and a window's ends follow the
/// skeleton's junctions, which sit up to about a limb radius from where the limbs' surfaces
/// meet: 3 px + 3 % of the window.
float tolerance_px(const st::perch_truth& truth) { return 3.0f + 0.03f * truth.window_px(); }

/// The paper's four outcomes over a population, and why the wrong sites were wrong.
struct score {
  int trees = 0, with_truth = 0, without_truth = 0;
  int correct = 0, incorrect = 0, missed = 0, correct_none = 0, errors = 0;
  int false_perches = 0;          ///< a perch on a tree with no feasible stretch
  int built_none = 0, built_none_perch = 0;  ///< trees built without a perch, and perches there
  std::map<std::string, int> causes;         ///< truth verdict at each wrong site
  std::ostringstream failures;

  [[nodiscard]] double rate() const {
    return with_truth > 0 ? static_cast<double>(correct) / static_cast<double>(with_truth) : 0.0;
  }
  [[nodiscard]] std::string summary() const {
    std::ostringstream out;
    out << trees << " trees, " << with_truth << " with a feasible stretch: correct location "
        << correct << " (" << 100.0 * rate() << " %), incorrect location " << incorrect
        << " (of which " << false_perches << " on trees without one), no result though one existed "
        << missed << ", correctly no result " << correct_none << ", errors " << errors
        << "; wrong sites by the truth's verdict there:";
    for (const auto& [cause, count] : causes) out << " " << cause << " " << count;
    return out.str();
  }
};

/// Runs `find_perch` with `scale_of(tree)` on the population of `family` (at base size, or its
/// first `family_size` members drawn `magnify` times bigger) and scores it.
template <class ScaleOf>
score evaluate(st::tree_family family, ScaleOf&& scale_of,
               const perch::perch_options& options = {}, int magnify = 1, int outline_bias = 0) {
  perch::workspace ws;
  score s;
  for (int i = 0; i < family_size(family); ++i) {
    st::population_member magnified;
    if (magnify != 1) magnified = st::population_tree(family, i, magnify);
    const st::population_member& m =
        magnify == 1 ? population(family)[static_cast<std::size_t>(i)] : magnified;
    const st::perch_truth truth(m.tree);
    perch::image<std::uint8_t> shifted;  // the mask as a biased segmenter draws it
    if (outline_bias != 0) {
      shifted = m.tree.mask;
      st::shift_outline(shifted, outline_bias);
    }
    const auto mask = outline_bias != 0 ? std::as_const(shifted).view() : m.tree.mask.view();
    auto found = perch::find_perch(mask, perch::tendon_claw{}, scale_of(m.tree), ws, options);
    ++s.trees;
    const std::string name = std::string(st::to_string(family)) + " " + std::to_string(i) + " (" +
                             m.kind + ", " + std::to_string(m.tree.mask.width()) + "x" +
                             std::to_string(m.tree.mask.height()) + ", " +
                             std::to_string(m.tree.mm_per_px) + " mm/px)";
    if (!found) {
      ++s.errors;
      s.failures << name << ": error " << found.error().message() << "\n";
      continue;
    }
    const bool has = truth.has_perch();
    (has ? s.with_truth : s.without_truth) += 1;
    const bool perched = found->outcome == perch::perch_outcome::found;
    if (m.built_without_perch) {
      ++s.built_none;
      s.built_none_perch += perched ? 1 : 0;
    }
    if (!perched) {
      (has ? s.missed : s.correct_none) += 1;
      continue;
    }
    const perch::pixel c = found->sites.front().window.centre;
    const Eigen::Vector2f p(static_cast<float>(c.x), static_cast<float>(c.y));
    const st::site_match near = truth.nearest_site(p);
    if (has && near.distance_px <= tolerance_px(truth)) {
      ++s.correct;
      continue;
    }
    ++s.incorrect;
    s.false_perches += has ? 0 : 1;
    const st::limb_location at = st::locate(m.tree, p, st::limb_set::without_twigs);
    const st::window_truth w = truth.window(at.limb, at.arc_px);
    ++s.causes[st::to_string(w.verdict)];
    s.failures << name << ": site (" << c.x << ", " << c.y << "), truth there "
               << st::to_string(w.verdict) << " (clearance gap " << w.clearance_mm << " mm, slope "
               << w.slope_deg << ", bend " << w.bend_deg << ", claw " << w.claw_diameter_mm
               << " mm), nearest feasible centre " << near.distance_px << " px (tolerance "
               << tolerance_px(truth) << ")\n";
  }
  return s;
}

score evaluate_known_scale(st::tree_family family, const perch::perch_options& options = {},
                           int magnify = 1, int outline_bias = 0) {
  return evaluate(
      family, [](const st::synthetic_tree& t) { return perch::fixed_scale{t.mm_per_px}; },
      options, magnify, outline_bias);
}


}  // namespace

TEST_CASE("PERCH_ACCURACY_FAMILY, when set, names a family this test scores") {
  CHECK((scored(st::tree_family::arcs) || scored(st::tree_family::colonisation)));
}

TEST_CASE("synthetic population: the mix, and trees built without a perch have none") {
  for (const st::tree_family family : {st::tree_family::arcs, st::tree_family::colonisation}) {
    if (!scored(family)) continue;
    CAPTURE(st::to_string(family));
    int without = 0, unmet = 0;
    for (const st::population_member& m : population(family)) {
      const bool has = st::perch_truth(m.tree).has_perch();
      without += has ? 0 : 1;
      CHECK(m.wish_met == (has == m.wished_perch));
      unmet += m.wish_met ? 0 : 1;
      if (m.built_without_perch)
        CHECK_MESSAGE(!has, st::to_string(family) << " " << m.index << " (" << m.kind << ")");
    }
    const int n = family_size(family);
    MESSAGE(without << " of " << n << " without a feasible stretch, " << unmet << " unmet wishes");
    // The mix asks 15 %; a colonisation member wished a perch keeps its last draw when none of
    // its draws has one (measured: arcs 16.5 %, colonisation 25 % of 200).
    CHECK(without * 100 >= 15 * n);
    CHECK(without * 100 <= (family == st::tree_family::arcs ? 20 : 30) * n);
  }
}

TEST_CASE("find_perch: the chosen perch lies on a truly feasible stretch (known scale)") {
  for (const st::tree_family family : {st::tree_family::arcs, st::tree_family::colonisation}) {
    if (!scored(family)) continue;
    CAPTURE(st::to_string(family));
    const score s = evaluate_known_scale(family);
    MESSAGE(st::to_string(family) << ": " << s.summary());
    MESSAGE("failures:\n" << s.failures.str());
    CHECK(s.errors == 0);
    CHECK(s.built_none_perch == 0);
    // Regression floors at the measured levels. The counts of wrong answers hold on the
    // sanitizer's smaller population too (its members are the first of the same trees); the
    // rates only on the whole.
    if (family == st::tree_family::arcs) {
      CHECK(s.false_perches == 0);               // never a perch where none is safe
      if (!sanitized) CHECK(s.rate() >= 0.57);  // measured 59.3 % (99 of 167)
      CHECK(s.incorrect <= 3);                   // measured 1
    } else {
      // Space colonisation grows limbs in 3-D; seen from the side, some run inside another
      // for a stretch, which the mask cannot show (the truth's gap there is negative): most of
      // the wrong sites are such fused pairs (see docs/accuracy-log.md).
      CHECK(s.false_perches <= 3);  // measured 2
      if (!sanitized) CHECK(s.rate() >= 0.14);  // measured 15.6 % (12 of 77)
      CHECK(s.incorrect <= 8);      // measured 7
    }
  }
}

TEST_CASE("find_perch: a segmenter's outline a pixel off" * doctest::skip(sanitized)) {
  if (!scored(st::tree_family::arcs)) return;
  // The same arcs trees drawn a pixel wider (an over-segmenting network) and a pixel narrower,
  // judged by the drawn truth: the margins of perch::outline_uncertainty_px keep limbs under
  // the grasp range and limbs read as twigs out (with half a pixel per side: 27 and 6 wrong).
  for (const int bias : {1, -1}) {
    CAPTURE(bias);
    const score s = evaluate_known_scale(st::tree_family::arcs, {}, 1, bias);
    MESSAGE("outline bias " << bias << ": " << s.summary());
    MESSAGE("failures:\n" << s.failures.str());
    CHECK(s.errors == 0);
    CHECK(s.false_perches == 0);
    CHECK(s.incorrect <= (bias > 0 ? 8 : 6));  // measured 5 and 4
  }
}

TEST_CASE("find_perch: the trunk prior on the same population" * doctest::skip(sanitized)) {
  // The scale from the trunk's width (paper: 180 mm by default; here each tree's own trunk
  // diameter, as a user who knows the species would give it).
  for (const st::tree_family family : {st::tree_family::arcs, st::tree_family::colonisation}) {
    if (!scored(family)) continue;
    const score s = evaluate(family, [](const st::synthetic_tree& t) {
      const float trunk_px = t.limbs.empty() ? 1.0f : t.limbs.front().diameter_px.front();
      return perch::trunk_prior{trunk_px * t.mm_per_px};
    });
    MESSAGE(st::to_string(family) << ", trunk prior: " << s.summary());
    CHECK(s.errors == 0);
    CHECK(s.false_perches <= 2);  // measured 0 and 0 with the prior's ±10 % (0 and 1 without)
  }
}

TEST_CASE("find_perch: the accuracy cost of perch_options::downscale" * doctest::skip(sanitized)) {
  if (!scored(st::tree_family::arcs)) return;
  // The arcs family analysed at reduced resolution: 640-1280 px wide trees at factor 0.5 leave
  // 320-640 px and limbs of a few pixels, which the resolution rule then refuses.
  for (const float factor : {0.5f}) {
    perch::perch_options options;
    options.downscale = factor;
    const score s = evaluate_known_scale(st::tree_family::arcs, options);
    MESSAGE("downscale " << factor << ": " << s.summary());
    MESSAGE("failures:\n" << s.failures.str());
    CHECK(s.errors == 0);
    // Known failure: arcs 184 (a kinked limb at 640x480, 320x240 analysed) gets a perch
    // inside another limb at 0.5 (docs/accuracy-log.md); the floor holds it at one.
    CHECK(s.false_perches <= 1);  // measured 1
  }
}

// Camera-sized frames: the arcs family three times larger (1920-3840 px wide, where downscale is
// meant to be used). Minutes in an optimised build, so CI skips it; run it with
//   build/test/tests/pli_accuracy_test --no-skip -tc='*camera-sized*'
TEST_CASE("find_perch: downscale on camera-sized frames" * doctest::skip()) {
  if (!scored(st::tree_family::arcs)) return;
  for (const float factor : {1.0f, 0.5f, 0.25f}) {
    perch::perch_options options;
    options.downscale = factor;
    const score s = evaluate_known_scale(st::tree_family::arcs, options, 3);
    MESSAGE("magnify 3, downscale " << factor << ": " << s.summary());
    CHECK(s.errors == 0);
    CHECK(s.false_perches == 0);
  }
}
