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
#include <map>
#include <sstream>
#include <string>

#include "support/population.hpp"

namespace {

namespace st = perch::support;

/// Members of each family in the population.
constexpr int family_size = 200;

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

/// Runs `find_perch` with `scale_of(tree)` on members [0, count) of `family` and scores it.
template <class ScaleOf>
score evaluate(st::tree_family family, int count, ScaleOf&& scale_of,
               const perch::perch_options& options = {}, int magnify = 1) {
  perch::workspace ws;
  score s;
  for (int i = 0; i < count; ++i) {
    const st::population_member m = st::population_tree(family, i, magnify);
    const st::perch_truth truth(m.tree);
    auto found = perch::find_perch(m.tree.mask.view(), perch::tendon_claw{}, scale_of(m.tree), ws,
                                   options);
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

score evaluate_known_scale(st::tree_family family, int count,
                           const perch::perch_options& options = {}, int magnify = 1) {
  return evaluate(
      family, count, [](const st::synthetic_tree& t) { return perch::fixed_scale{t.mm_per_px}; },
      options, magnify);
}

// Under AddressSanitizer the population takes minutes per pass; the extra passes (trunk prior,
// downscale) run the same pipeline code as the main case, so the sanitizer workflow leaves them
// out.
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

}  // namespace

TEST_CASE("synthetic population: trees built without a perch have no feasible stretch") {
  int built_none = 0;
  for (int i = 0; i < family_size; ++i) {
    const st::population_member m = st::arcs_member(i);
    if (!m.built_without_perch) continue;
    ++built_none;
    CHECK_MESSAGE(!st::perch_truth(m.tree).has_perch(), "arcs " << i << " (" << m.kind << ")");
  }
  CHECK(built_none >= family_size / 6);
}

TEST_CASE("find_perch: the chosen perch lies on a truly feasible stretch (known scale)") {
  for (const st::tree_family family : {st::tree_family::arcs, st::tree_family::colonisation}) {
    CAPTURE(st::to_string(family));
    const score s = evaluate_known_scale(family, family_size);
    MESSAGE(st::to_string(family) << ": " << s.summary());
    MESSAGE("failures:\n" << s.failures.str());
    CHECK(s.errors == 0);
    CHECK(s.built_none_perch == 0);
    CHECK(s.with_truth >= family_size / 4);
    // Regression floors at the measured levels.
    if (family == st::tree_family::arcs) {
      CHECK(s.built_none >= family_size / 6);
      CHECK(s.false_perches == 0);  // never a perch where none is safe
      CHECK(s.rate() >= 0.64);      // measured 66.7 % (58 of 87)
      CHECK(s.incorrect <= 2);      // measured 1
    } else {
      // Space colonisation grows limbs in 3-D; seen from the side, some run inside another
      // for a stretch, which the mask cannot show (the truth's gap there is negative): most of
      // the wrong sites are such fused pairs (see docs/accuracy-log.md).
      CHECK(s.false_perches <= 3);  // measured 3
      CHECK(s.rate() >= 0.35);      // measured 38 % (19 of 50)
      CHECK(s.incorrect <= 7);      // measured 6
    }
  }
}

TEST_CASE("find_perch: the trunk prior on the same population" * doctest::skip(sanitized)) {
  // The scale from the trunk's width (paper: 180 mm by default; here each tree's own trunk
  // diameter, as a user who knows the species would give it).
  for (const st::tree_family family : {st::tree_family::arcs, st::tree_family::colonisation}) {
    const score s = evaluate(family, family_size, [](const st::synthetic_tree& t) {
      const float trunk_px = t.limbs.empty() ? 1.0f : t.limbs.front().diameter_px.front();
      return perch::trunk_prior{trunk_px * t.mm_per_px};
    });
    MESSAGE(st::to_string(family) << ", trunk prior: " << s.summary());
    CHECK(s.errors == 0);
    CHECK(s.false_perches <= 2);  // measured 0 (arcs), 1 (colonisation)
  }
}

TEST_CASE("find_perch: the accuracy cost of perch_options::downscale" * doctest::skip(sanitized)) {
  // The arcs family analysed at reduced resolution: 640-1280 px wide trees at factor 0.5 leave
  // 320-640 px and limbs of a few pixels, which the resolution rule then refuses.
  for (const float factor : {0.5f}) {
    perch::perch_options options;
    options.downscale = factor;
    const score s = evaluate_known_scale(st::tree_family::arcs, family_size, options);
    MESSAGE("downscale " << factor << ": " << s.summary());
    CHECK(s.errors == 0);
    CHECK(s.false_perches == 0);
  }
}

// Camera-sized frames: the arcs family three times larger (1920-3840 px wide, where downscale is
// meant to be used). Minutes in an optimised build, so CI skips it; run it with
//   build/test/tests/pli_accuracy_test --no-skip -tc='*camera-sized*'
TEST_CASE("find_perch: downscale on camera-sized frames" * doctest::skip()) {
  for (const float factor : {1.0f, 0.5f, 0.25f}) {
    perch::perch_options options;
    options.downscale = factor;
    const score s = evaluate_known_scale(st::tree_family::arcs, family_size, options, 3);
    MESSAGE("magnify 3, downscale " << factor << ": " << s.summary());
    CHECK(s.errors == 0);
    CHECK(s.false_perches == 0);
  }
}
