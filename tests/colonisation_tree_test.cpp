// SPDX-License-Identifier: BSL-1.0
// Tests of the space-colonisation tree family (examples/support/support/colonisation_tree.hpp):
// determinism, the truth's structure (grounded trunk, parents first, bases on the parent's
// axis, pipe model), the mask against a redraw of the truth, and the defects.
#include "support/colonisation_tree.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

using perch::image;
using perch::support::colonisation_options;
using perch::support::crown_form;
using perch::support::limb_kind;
using perch::support::limb_truth;
using perch::support::synthetic_tree;
using Vec = Eigen::Vector2f;

namespace {

constexpr crown_form all_forms[] = {crown_form::decurrent, crown_form::excurrent,
                                    crown_form::columnar, crown_form::irregular};

colonisation_options options(crown_form form, std::uint32_t seed, int width = 1280,
                             int height = 960) {
  colonisation_options o;
  o.width = width;
  o.height = height;
  o.seed = seed;
  o.form = form;
  o.mm_per_px = 2.5f;
  o.trunk_diameter_mm = 200.0f;
  return o;
}

bool same_bytes(const image<std::uint8_t>& a, const image<std::uint8_t>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.view().size()) == 0;
}

/// The mask the truth describes: every limb drawn as tapered capsules.
image<std::uint8_t> redraw(const synthetic_tree& tree, bool with_fragments = true) {
  image<std::uint8_t> mask(tree.mask.width(), tree.mask.height(), 0);
  for (const limb_truth& limb : tree.limbs) {
    if (!with_fragments && limb.kind == limb_kind::fragment) continue;
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    perch::support::draw_polyline(mask.view(), limb.centreline, radii);
  }
  return mask;
}

/// 8-connected component labels (0 = background), plain stack flood fill.
std::vector<int> label8(const image<std::uint8_t>& mask) {
  const int w = mask.width(), h = mask.height();
  std::vector<int> label(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  std::vector<int> stack;
  int next = 0;
  for (int i0 = 0; i0 < w * h; ++i0) {
    if (mask(i0 % w, i0 / w) == 0 || label[static_cast<std::size_t>(i0)] != 0) continue;
    label[static_cast<std::size_t>(i0)] = ++next;
    stack.push_back(i0);
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = i % w + dx, y = i / w + dy;
          if (x < 0 || y < 0 || x >= w || y >= h || mask(x, y) == 0) continue;
          const auto j = static_cast<std::size_t>(y * w + x);
          if (label[j] != 0) continue;
          label[j] = next;
          stack.push_back(y * w + x);
        }
    }
  }
  return label;
}

/// Distance from p to a polyline.
float distance_to(const std::vector<Vec>& c, Vec p) {
  float best = 1e30f;
  for (std::size_t i = 0; i + 1 < c.size(); ++i) {
    const Vec ab = c[i + 1] - c[i];
    const float t = std::clamp((p - c[i]).dot(ab) / std::max(ab.squaredNorm(), 1e-12f), 0.0f, 1.0f);
    best = std::min(best, (p - (c[i] + t * ab)).norm());
  }
  return best;
}

double foreground_share(const image<std::uint8_t>& mask) {
  std::size_t n = 0;
  for (int y = 0; y < mask.height(); ++y)
    for (auto v : mask.row(y)) n += v != 0 ? 1u : 0u;
  return static_cast<double>(n) / static_cast<double>(mask.view().size());
}

/// Checks the structure every tree must have: limb 0 the grounded trunk, parents first, bases on
/// the parent's centreline, well-formed vertex arrays, arc lengths consistent.
void check_structure(const synthetic_tree& tree) {
  REQUIRE_FALSE(tree.limbs.empty());
  const limb_truth& trunk = tree.limbs[0];
  CHECK(trunk.kind == limb_kind::trunk);
  CHECK(trunk.parent == -1);
  CHECK(trunk.level == 0);
  CHECK(trunk.centreline[0].y() >= static_cast<float>(tree.mask.height() - 1));
  for (std::size_t i = 0; i < tree.limbs.size(); ++i) {
    const limb_truth& limb = tree.limbs[i];
    CAPTURE(i);
    REQUIRE(limb.centreline.size() >= 2);
    REQUIRE(limb.diameter_px.size() == limb.centreline.size());
    REQUIRE(limb.arc_px.size() == limb.centreline.size());
    CHECK(limb.arc_px[0] == 0.0f);
    CHECK(limb.curvature_per_px == 0.0f);
    for (std::size_t k = 1; k < limb.centreline.size(); ++k) {
      if (limb.kind == limb_kind::fragment) break;  // 2-point capsules
      const float step = (limb.centreline[k] - limb.centreline[k - 1]).norm();
      CHECK(step <= 2.0f + 1e-3f);  // resampled to ≤ 2 px
      CHECK(limb.arc_px[k] ==
            doctest::Approx(static_cast<double>(limb.arc_px[k - 1] + step)).epsilon(1e-3));
    }
    for (float d : limb.diameter_px) CHECK((std::isfinite(d) && d > 0.0f));
    if (limb.kind == limb_kind::fragment || limb.kind == limb_kind::trunk) {
      CHECK(limb.parent == -1);
      continue;
    }
    REQUIRE(limb.parent >= 0);
    REQUIRE(static_cast<std::size_t>(limb.parent) < i);  // parents before children
    const limb_truth& parent = tree.limbs[static_cast<std::size_t>(limb.parent)];
    CHECK(parent.kind != limb_kind::fragment);
    CHECK(limb.level == parent.level + 1);
    CHECK(limb.tree == parent.tree);
    const Vec on_parent = perch::support::truth_point_at(parent, limb.parent_arc_px);
    CHECK((limb.centreline[0] - on_parent).norm() <= 1.0f);
    CHECK(distance_to(parent.centreline, limb.centreline[0]) <= 1.0f);
  }
}

}  // namespace

TEST_CASE("make_colonisation_tree: same options, same bytes and truth; other seeds differ") {
  for (crown_form form : all_forms) {
    colonisation_options o = options(form, 7);
    o.noise = 1.5f;
    o.holes = 3;
    o.twigs = 10;
    o.fragments = 4;
    o.second_tree = 0.6f;
    const synthetic_tree a = perch::support::make_colonisation_tree(o);
    const synthetic_tree b = perch::support::make_colonisation_tree(o);
    CHECK(same_bytes(a.mask, b.mask));
    REQUIRE(a.limbs.size() == b.limbs.size());
    for (std::size_t i = 0; i < a.limbs.size(); ++i) {
      CHECK(a.limbs[i].centreline == b.limbs[i].centreline);
      CHECK(a.limbs[i].diameter_px == b.limbs[i].diameter_px);
      CHECK(a.limbs[i].parent == b.limbs[i].parent);
    }
    o.seed = 8;
    CHECK_FALSE(same_bytes(a.mask, perch::support::make_colonisation_tree(o).mask));
  }
}

TEST_CASE("make_colonisation_tree: structure, grounded trunk, bases on the parent's axis") {
  for (crown_form form : all_forms)
    for (std::uint32_t seed = 1; seed <= 3; ++seed) {
      CAPTURE(static_cast<int>(form));
      CAPTURE(seed);
      colonisation_options o = options(form, seed);
      o.twigs = 12;
      o.fragments = 5;
      o.second_tree = seed == 2 ? 0.7f : 0.0f;
      o.overflow = seed == 3 ? 0.3f : 0.0f;
      const synthetic_tree tree = perch::support::make_colonisation_tree(o);
      check_structure(tree);
      // The trunk covers the bottom row where it stands, d0 wide (it leans by a few degrees).
      const limb_truth& trunk = tree.limbs[0];
      const float d0 = o.trunk_diameter_mm / o.mm_per_px;
      CHECK(trunk.diameter_px[0] == doctest::Approx(static_cast<double>(d0)).epsilon(1e-5));
      const int h = o.height;
      int run = 0;
      const int x0 = static_cast<int>(std::lround(trunk.centreline[0].x()));
      REQUIRE(tree.mask(x0, h - 1) != 0);
      for (int x = x0; x < o.width && tree.mask(x, h - 1) != 0; ++x) ++run;
      for (int x = x0 - 1; x >= 0 && tree.mask(x, h - 1) != 0; --x) ++run;
      CHECK(static_cast<float>(run) >= d0 - 2.0f);
      CHECK(static_cast<float>(run) <= 1.05f * d0 + 3.0f);
      // A tree of limbs, with a good share of the image but far from all of it.
      int limbs = 0;
      for (const limb_truth& l : tree.limbs) limbs += l.kind == limb_kind::limb ? 1 : 0;
      CHECK(limbs >= 10);
      const double share = foreground_share(tree.mask);
      CHECK(share > 0.03);
      CHECK(share < 0.5);
    }
}

TEST_CASE("make_colonisation_tree: without noise and holes the mask is the redrawn truth") {
  for (crown_form form : all_forms) {
    colonisation_options o = options(form, 11);
    o.twigs = 15;
    o.fragments = 6;
    o.second_tree = 0.5f;
    const synthetic_tree tree = perch::support::make_colonisation_tree(o);
    CHECK(same_bytes(tree.mask, redraw(tree)));
    // Noise and holes change the mask, not the truth.
    o.noise = 2.0f;
    o.holes = 6;
    const synthetic_tree noisy = perch::support::make_colonisation_tree(o);
    CHECK_FALSE(same_bytes(noisy.mask, redraw(noisy)));
  }
}

TEST_CASE("make_colonisation_tree: the pipe model holds at every fork") {
  for (crown_form form : all_forms)
    for (float a : {2.0f, 2.5f}) {
      colonisation_options o = options(form, 5);
      o.pipe_exponent = a;
      o.min_tip_diameter_mm = 0.1f;  // tips at the pipe model's own size (≥ 1.2 px)
      o.second_tree = 0.6f;
      const synthetic_tree tree = perch::support::make_colonisation_tree(o);
      const float d_floor = 1.2f * 1.001f;
      int forks = 0;
      for (std::size_t p = 0; p < tree.limbs.size(); ++p) {
        const limb_truth& parent = tree.limbs[p];
        // The arc positions of its forks, with the children leaving there.
        std::vector<std::pair<float, float>> kids;  // (arc, child base diameter)
        for (const limb_truth& c : tree.limbs)
          if (c.parent == static_cast<int>(p)) kids.emplace_back(c.parent_arc_px, c.diameter_px[0]);
        std::sort(kids.begin(), kids.end());
        for (std::size_t k = 0; k < kids.size();) {
          const float s = kids[k].first;
          double children = 0.0;
          bool clamped = false;
          for (; k < kids.size() && kids[k].first == s; ++k) {
            children += std::pow(static_cast<double>(kids[k].second), static_cast<double>(a));
            clamped = clamped || kids[k].second <= d_floor;
          }
          // Between forks a limb keeps its diameter: after this fork it is what it is at the
          // next fork (or the tip).
          const float next = k < kids.size() ? kids[k].first : perch::support::length_px(parent);
          const double before = perch::support::truth_diameter_at(parent, s);
          const double after = perch::support::truth_diameter_at(parent, next);
          if (clamped || after <= static_cast<double>(d_floor)) continue;
          ++forks;
          CAPTURE(p);
          CAPTURE(s);
          const double sum = std::pow(after, static_cast<double>(a)) + children;
          CHECK(std::pow(sum, 1.0 / static_cast<double>(a)) ==
                doctest::Approx(before).epsilon(0.01));
        }
      }
      CHECK(forks >= 10);
    }
}

TEST_CASE("make_colonisation_tree: fragments are detached from every tree (8-connectivity)") {
  for (crown_form form : all_forms) {
    colonisation_options o = options(form, 3);
    o.fragments = 12;
    o.twigs = 10;
    o.noise = 1.5f;
    o.second_tree = 0.6f;
    const synthetic_tree tree = perch::support::make_colonisation_tree(o);
    int fragments = 0;
    for (const limb_truth& l : tree.limbs) fragments += l.kind == limb_kind::fragment ? 1 : 0;
    CHECK(fragments == 12);
    const std::vector<int> label = label8(tree.mask);
    // Components holding tree pixels (the mask without the fragments, noise included: draw the
    // trees and keep the mask's pixels there).
    const image<std::uint8_t> trees = redraw(tree, false);
    std::vector<std::uint8_t> tree_label(label.size() + 1, 0);
    const int w = o.width;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < w; ++x)
        if (trees(x, y) != 0 && tree.mask(x, y) != 0)
          tree_label[static_cast<std::size_t>(label[static_cast<std::size_t>(y * w + x)])] = 1;
    for (const limb_truth& f : tree.limbs) {
      if (f.kind != limb_kind::fragment) continue;
      const Vec c = 0.5f * (f.centreline.front() + f.centreline.back());
      const int x = static_cast<int>(std::lround(c.x())), y = static_cast<int>(std::lround(c.y()));
      REQUIRE(tree.mask(x, y) != 0);
      const int l = label[static_cast<std::size_t>(y * w + x)];
      CHECK(tree_label[static_cast<std::size_t>(l)] == 0);
      CHECK(f.parent == -1);
    }
  }
}

TEST_CASE("make_colonisation_tree: the defects are there when asked for") {
  colonisation_options o = options(crown_form::decurrent, 4);
  o.second_tree = 0.6f;
  o.twigs = 20;
  o.overflow = 0.4f;
  const synthetic_tree tree = perch::support::make_colonisation_tree(o);
  int second_trunks = 0, second_limbs = 0, twigs = 0, leaving = 0;
  for (const limb_truth& l : tree.limbs) {
    if (l.tree == 1) {
      ++second_limbs;
      second_trunks += l.kind == limb_kind::trunk && l.parent == -1 ? 1 : 0;
    }
    twigs += l.kind == limb_kind::twig ? 1 : 0;
    for (const Vec& p : l.centreline)
      if (p.x() < 0.0f || p.y() < 0.0f || p.x() > static_cast<float>(o.width - 1)) {
        ++leaving;
        break;
      }
  }
  CHECK(second_trunks == 1);
  CHECK(second_limbs >= 5);
  CHECK(twigs >= 20);
  CHECK(leaving >= 3);
}

TEST_CASE("make_colonisation_tree: tree-like at the given scale") {
  for (crown_form form : all_forms)
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      CAPTURE(static_cast<int>(form));
      CAPTURE(seed);
      colonisation_options o = options(form, seed, 1920, 1080);
      o.mm_per_px = 2.0f;
      o.trunk_diameter_mm = 180.0f;
      const synthetic_tree tree = perch::support::make_colonisation_tree(o);
      int perch_sized = 0, level = 0, steep = 0;
      for (const limb_truth& l : tree.limbs) {
        if (l.kind != limb_kind::limb) continue;
        const float d_mm = l.diameter_px[0] * o.mm_per_px;
        if (d_mm < 30.0f || d_mm > 110.0f) continue;
        ++perch_sized;
        const Vec chord = l.centreline.back() - l.centreline.front();
        const float slope = std::atan2(std::abs(chord.y()), std::abs(chord.x())) * 57.29578f;
        level += slope < 30.0f ? 1 : 0;
        steep += slope > 60.0f ? 1 : 0;
      }
      CHECK(perch_sized >= 5);
      if (form != crown_form::columnar) CHECK(level >= 1);
      if (form != crown_form::excurrent) CHECK(steep >= 1);
      if (form == crown_form::excurrent)  // the leader runs up into the top fifth
        CHECK(tree.limbs[0].centreline.back().y() < 0.2f * static_cast<float>(o.height));
    }
}

TEST_CASE("make_colonisation_tree: 640x480 and 4000x3000 at 1.5-8 mm/px") {
  struct size_case {
    int w, h;
    float mm_per_px, trunk_mm;
  };
  for (const size_case& s :
       {size_case{640, 480, 8.0f, 150.0f}, size_case{640, 480, 1.5f, 150.0f},
        size_case{4000, 3000, 1.5f, 300.0f}, size_case{4000, 3000, 8.0f, 300.0f}})
    for (crown_form form : all_forms) {
      CAPTURE(s.w);
      CAPTURE(s.mm_per_px);
      CAPTURE(static_cast<int>(form));
      colonisation_options o = options(form, 2, s.w, s.h);
      o.mm_per_px = s.mm_per_px;
      o.trunk_diameter_mm = s.trunk_mm;
      o.fragments = 3;
      o.twigs = 5;
      const synthetic_tree tree = perch::support::make_colonisation_tree(o);
      REQUIRE(tree.mask.width() == s.w);
      REQUIRE(tree.mask.height() == s.h);
      check_structure(tree);
      const double share = foreground_share(tree.mask);
      CHECK(share > 0.01);
      CHECK(share < 0.6);
    }
}

TEST_CASE("make_colonisation_tree: invalid options give an empty tree") {
  colonisation_options o;
  o.width = 0;
  CHECK(perch::support::make_colonisation_tree(o).limbs.empty());
  o = colonisation_options{};
  o.mm_per_px = 0.0f;
  CHECK(perch::support::make_colonisation_tree(o).mask.view().empty());
  o = colonisation_options{};
  o.trunk_diameter_mm = std::nanf("");
  CHECK(perch::support::make_colonisation_tree(o).limbs.empty());
}
