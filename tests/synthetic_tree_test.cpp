// SPDX-License-Identifier: BSL-1.0
// Tests of the synthetic tree generator (examples/support/support/synthetic_tree.hpp): the masks
// the benchmarks, the tool's `synth` subcommand and the pipeline tests rely on, and their truth.
#include "support/synthetic_tree.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "support/ascii_art.hpp"

using perch::image;
using perch::support::limb_kind;
using perch::support::limb_truth;
using perch::support::synthetic_tree;
using perch::support::tree_noise;
using perch::support::tree_options;
using Vec = Eigen::Vector2f;

namespace {

/// Number of 8-connected components of the non-zero pixels (plain stack flood fill).
int count_components8(const image<std::uint8_t>& mask) {
  const int w = mask.width(), h = mask.height();
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  std::vector<int> stack;
  int components = 0;
  for (int y0 = 0; y0 < h; ++y0)
    for (int x0 = 0; x0 < w; ++x0) {
      const int i0 = y0 * w + x0;
      if (mask(x0, y0) == 0 || seen[static_cast<std::size_t>(i0)] != 0) continue;
      ++components;
      seen[static_cast<std::size_t>(i0)] = 1;
      stack.push_back(i0);
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        const int x = i % w, y = i / w;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h || mask(nx, ny) == 0) continue;
            const int j = ny * w + nx;
            if (seen[static_cast<std::size_t>(j)] != 0) continue;
            seen[static_cast<std::size_t>(j)] = 1;
            stack.push_back(j);
          }
      }
    }
  return components;
}

double foreground_share(const image<std::uint8_t>& mask) {
  std::size_t n = 0;
  for (int y = 0; y < mask.height(); ++y)
    for (auto v : mask.row(y)) n += v != 0 ? 1u : 0u;
  return static_cast<double>(n) / static_cast<double>(mask.view().size());
}

bool same_bytes(const image<std::uint8_t>& a, const image<std::uint8_t>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.view().size()) == 0;
}

/// Distance from p to a limb's surface (negative inside), brute force over its segments.
float depth_to(const limb_truth& limb, const Vec& p) {
  float best = 1e30f;
  for (std::size_t i = 0; i + 1 < limb.centreline.size(); ++i) {
    const Vec a = limb.centreline[i], ab = limb.centreline[i + 1] - a;
    const float t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12f), 0.0f, 1.0f);
    const float r =
        0.5f * (limb.diameter_px[i] + t * (limb.diameter_px[i + 1] - limb.diameter_px[i]));
    best = std::min(best, (p - (a + t * ab)).norm() - r);
  }
  return best;
}

bool in_image(const image<std::uint8_t>& m, Vec p, float margin = 0.0f) {
  return p.x() >= margin && p.y() >= margin &&
         p.x() <= static_cast<float>(m.width() - 1) - margin &&
         p.y() <= static_cast<float>(m.height() - 1) - margin;
}

bool tree_pixel(const image<std::uint8_t>& m, Vec p) {
  const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
  return m.view().contains(x, y) && m(x, y) != 0;
}

doctest::Approx approx(float value) { return doctest::Approx(static_cast<double>(value)); }

tree_options small(std::uint32_t seed) {
  tree_options o = perch::support::benchmark_tree_options(640, 480, tree_noise::clean);
  o.seed = seed;
  return o;
}

}  // namespace

TEST_CASE("draw_capsule: pixel centres within the radius of the segment, clipped") {
  image<std::uint8_t> img(9, 5);
  perch::support::draw_capsule(img, Vec(2, 2), Vec(6, 2), 1.0f);
  CHECK(perch::support::to_ascii(img.view()) ==
        ".........\n"
        "..#####..\n"
        ".#######.\n"
        "..#####..\n"
        ".........\n");
  image<std::uint8_t> disc(5, 5);
  perch::support::draw_disc(disc, Vec(2, 2), 1.5f);
  CHECK(perch::support::to_ascii(disc.view()) ==
        ".....\n"
        ".###.\n"
        ".###.\n"
        ".###.\n"
        ".....\n");
  // Erasing, clipping at every border, nothing drawn for a negative radius or NaN.
  perch::support::draw_disc(disc, Vec(2, 2), 0.5f, 0);
  CHECK(disc(2, 2) == 0);
  CHECK(disc(1, 1) == 1);
  image<std::uint8_t> clip(4, 3);
  perch::support::draw_capsule(clip, Vec(-10, 1), Vec(20, 1), 0.2f);
  CHECK(perch::support::to_ascii(clip.view()) == "....\n####\n....\n");
  perch::support::draw_capsule(clip, Vec(-10, -10), Vec(-5, -5), 2.0f);
  perch::support::draw_capsule(clip, Vec(1, 1), Vec(2, 2), -1.0f);
  perch::support::draw_capsule(clip, Vec(std::nanf(""), 1), Vec(2, 2), 3.0f);
  CHECK(perch::support::to_ascii(clip.view()) == "....\n####\n....\n");
  image<std::uint8_t> none;
  perch::support::draw_disc(none, Vec(0, 0), 3.0f);
}

TEST_CASE("draw_polyline and draw_arc: tapered strokes and arcs of the given radius") {
  image<std::uint8_t> img(40, 20);
  perch::support::draw_polyline(img, {Vec(2, 10), Vec(37, 10)}, {6.0f, 1.0f});
  // Column 8 lies where the radius is 6 - 5·6/35 ≈ 5.14: rows 5…15.
  int column = 0;
  for (int y = 0; y < img.height(); ++y) column += img(8, y);
  CHECK(column == 11);
  CHECK(img(37, 10) == 1);
  CHECK(img(37, 12) == 0);
  // Sizes that differ draw nothing.
  image<std::uint8_t> other(10, 10);
  perch::support::draw_polyline(other, {Vec(2, 2), Vec(5, 5)}, {1.0f});
  CHECK(foreground_share(other) == 0.0);

  image<std::uint8_t> arc(64, 64);
  const Vec centre(32, 32);
  perch::support::draw_arc(arc, centre, 20.0f, 0.0f, std::numbers::pi_v<float>, 2.0f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (arc(x, y) == 0) continue;
      const float r = (Vec(static_cast<float>(x), static_cast<float>(y)) - centre).norm();
      CHECK(std::abs(r - 20.0f) <= 2.01f);
      CHECK(y >= 30);  // angles 0…π with y down: the lower half
    }
  CHECK(arc(32, 52) == 1);
  CHECK(arc(32, 12) == 0);
}

TEST_CASE("sin_cos: the platform-independent series matches libm") {
  for (int i = -2000; i <= 2000; ++i) {
    const double a = i * 0.00731;
    double s = 0.0, c = 0.0;
    perch::support::detail::sin_cos(a, s, c);
    CHECK(std::abs(s - std::sin(a)) < 1e-13);
    CHECK(std::abs(c - std::cos(a)) < 1e-13);
  }
}

TEST_CASE("make_tree: same seed, same bytes and truth; other seeds differ") {
  for (const tree_noise noise : {tree_noise::clean, tree_noise::noisy}) {
    const auto o = perch::support::benchmark_tree_options(640, 480, noise);
    const synthetic_tree a = perch::support::make_tree(o);
    const synthetic_tree b = perch::support::make_tree(o);
    CHECK(same_bytes(a.mask, b.mask));
    REQUIRE(a.limbs.size() == b.limbs.size());
    for (std::size_t i = 0; i < a.limbs.size(); ++i) {
      CHECK(a.limbs[i].centreline == b.limbs[i].centreline);
      CHECK(a.limbs[i].diameter_px == b.limbs[i].diameter_px);
    }
    tree_options other = o;
    other.seed = o.seed + 1;
    CHECK_FALSE(same_bytes(a.mask, perch::support::make_tree(other).mask));
  }
}

TEST_CASE("benchmark_tree: pinned bytes, so every compiler and platform benches the same masks") {
  // FNV-1a of the 640x480 masks. A change here changes the benchmark inputs: update on purpose.
  auto fnv1a = [](const image<std::uint8_t>& mask) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < mask.view().size(); ++i) {
      h ^= mask.data()[i];
      h *= 1099511628211ull;
    }
    return h;
  };
  CHECK(fnv1a(perch::support::benchmark_tree(640, 480, tree_noise::clean).mask) ==
        15229586214027178014ull);  // seed 23 (issue 24: a tree with safe perches)
  CHECK(fnv1a(perch::support::benchmark_tree(640, 480, tree_noise::noisy).mask) ==
        4076996194955107712ull);
}

TEST_CASE(
    "make_tree: the clean and noisy benchmark trees share their limbs; noise changes the mask") {
  const synthetic_tree clean = perch::support::benchmark_tree(1920, 1080, tree_noise::clean);
  const synthetic_tree noisy = perch::support::benchmark_tree(1920, 1080, tree_noise::noisy);
  REQUIRE(noisy.limbs.size() == clean.limbs.size() + 24);
  for (std::size_t i = 0; i < clean.limbs.size(); ++i)
    CHECK(noisy.limbs[i].centreline == clean.limbs[i].centreline);
  for (std::size_t i = clean.limbs.size(); i < noisy.limbs.size(); ++i)
    CHECK(noisy.limbs[i].kind == limb_kind::twig);
  // Bumps and twigs add pixels outside the clean tree; holes remove pixels inside it.
  int added = 0, removed = 0;
  for (int y = 0; y < clean.mask.height(); ++y)
    for (int x = 0; x < clean.mask.width(); ++x) {
      added += clean.mask(x, y) == 0 && noisy.mask(x, y) != 0;
      removed += clean.mask(x, y) != 0 && noisy.mask(x, y) == 0;
    }
  CHECK(added > 2000);
  CHECK(removed > 20);
  CHECK(count_components8(clean.mask) == 1);
  MESSAGE("noisy 1920x1080: +" << added << " px, -" << removed << " px, components "
                               << count_components8(noisy.mask));
}

TEST_CASE("make_tree: the trunk rises from the bottom edge, full width there") {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const synthetic_tree tree = perch::support::make_tree(small(seed));
    REQUIRE(!tree.limbs.empty());
    const limb_truth& trunk = tree.limbs[0];
    CHECK(trunk.kind == limb_kind::trunk);
    CHECK(trunk.parent == -1);
    const int bottom = tree.mask.height() - 1;
    const float d = trunk.diameter_px.front();
    const Vec at = perch::support::truth_point_at(trunk, 0.5f * d);  // the bottom row's centre
    int run = 0;
    for (int x = 0; x < tree.mask.width(); ++x) run += tree.mask(x, bottom);
    CHECK(tree.mask(static_cast<int>(std::lround(at.x())), bottom) == 1);
    CHECK(std::abs(static_cast<float>(run) - d) <= 2.0f);
    // The trunk is the widest limb everywhere (the trunk scale rule relies on it).
    for (const limb_truth& limb : tree.limbs)
      for (float di : limb.diameter_px) CHECK(di <= d);
  }
}

TEST_CASE("make_tree: a clean tree is one 8-connected component") {
  for (std::uint32_t seed = 1; seed <= 10; ++seed)
    CHECK(count_components8(perch::support::make_tree(small(seed)).mask) == 1);
  CHECK(count_components8(perch::support::benchmark_tree(1920, 1080, tree_noise::clean).mask) == 1);
}

TEST_CASE("make_tree: foreground share is sane at every benchmark size") {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    const double share = foreground_share(perch::support::make_tree(small(seed)).mask);
    CHECK(share >= 0.05);
    CHECK(share <= 0.40);
  }
  const double share =
      foreground_share(perch::support::benchmark_tree(1920, 1080, tree_noise::noisy).mask);
  CHECK(share >= 0.05);
  CHECK(share <= 0.40);
}

TEST_CASE("make_tree: the truth is finite and well-formed; the pipe rule holds at forks") {
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    tree_options o = small(seed);
    o.twigs = 10;
    const synthetic_tree tree = perch::support::make_tree(o);
    CHECK(tree.mm_per_px == o.mm_per_px);
    bool twigs_started = false;
    for (std::size_t i = 0; i < tree.limbs.size(); ++i) {
      const limb_truth& limb = tree.limbs[i];
      REQUIRE(limb.centreline.size() >= 2);
      REQUIRE(limb.diameter_px.size() == limb.centreline.size());
      REQUIRE(limb.arc_px.size() == limb.centreline.size());
      CHECK(limb.arc_px[0] == 0.0f);
      for (std::size_t k = 0; k < limb.centreline.size(); ++k) {
        CHECK(limb.centreline[k].allFinite());
        CHECK(std::isfinite(limb.diameter_px[k]));
        CHECK(limb.diameter_px[k] > 0.0f);
        if (k > 0) CHECK(limb.arc_px[k] > limb.arc_px[k - 1]);
      }
      CHECK(std::isfinite(limb.base_heading_rad));
      CHECK(std::isfinite(limb.curvature_per_px));
      // Gentle: at most 30° of turning along a limb.
      CHECK(std::abs(limb.curvature_per_px) * perch::support::length_px(limb) <= 0.53f);
      if (i == 0) continue;
      CHECK(limb.parent >= 0);
      CHECK(limb.parent < static_cast<int>(i));
      const limb_truth& parent = tree.limbs[static_cast<std::size_t>(limb.parent)];
      CHECK(limb.level == parent.level + 1);
      // It starts on its parent's centreline.
      CHECK(
          (limb.centreline[0] - perch::support::truth_point_at(parent, limb.parent_arc_px)).norm() <
          0.01f);
      twigs_started = twigs_started || limb.kind == limb_kind::twig;
      CHECK((limb.kind == limb_kind::twig) == twigs_started);  // twigs come last
    }
    // Pipe model at each fork: the children leaving a limb's tip share its cross-section.
    for (std::size_t p = 0; p < tree.limbs.size(); ++p) {
      const limb_truth& parent = tree.limbs[p];
      if (parent.kind == limb_kind::twig) continue;
      double area = 0.0;
      int children = 0;
      for (const limb_truth& limb : tree.limbs)
        if (limb.parent == static_cast<int>(p) && limb.kind != limb_kind::twig &&
            limb.parent_arc_px == perch::support::length_px(parent)) {
          area += static_cast<double>(limb.diameter_px[0] * limb.diameter_px[0]);
          ++children;
        }
      const double tip = static_cast<double>(parent.diameter_px.back());
      if (children >= 2) CHECK(area <= tip * tip * 1.0001);
      if (children >= 2) CHECK(area >= tip * tip * 0.7);  // only limbs below the minimum dropped
    }
  }
}

TEST_CASE("make_tree: diameters measured across the mask match the truth within 1.5 px") {
  int measured = 0;
  float worst = 0.0f;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    tree_options o = perch::support::benchmark_tree_options(1920, 1080, tree_noise::clean);
    o.seed = seed;
    const synthetic_tree tree = perch::support::make_tree(o);
    // Each limb's bounding box, grown by its radius and the 3 px clearance.
    std::vector<std::pair<Vec, Vec>> boxes;
    for (const limb_truth& limb : tree.limbs) {
      Vec lo = limb.centreline[0], hi = limb.centreline[0];
      for (const Vec& q : limb.centreline) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      const float grow = 0.5f * limb.diameter_px.front() + 3.5f;
      boxes.emplace_back(lo.array() - grow, hi.array() + grow);
    }
    for (std::size_t li = 0; li < tree.limbs.size(); ++li) {
      const limb_truth& limb = tree.limbs[li];
      const float length = perch::support::length_px(limb);
      const float d_max = limb.diameter_px.front();
      for (float s = d_max; s < length - d_max; s += std::max(8.0f, d_max)) {
        const Vec c = perch::support::truth_point_at(limb, s);
        const Vec t = perch::support::truth_tangent_at(limb, s);
        const Vec n(-t.y(), t.x());
        const float d = perch::support::truth_diameter_at(limb, s);
        const float reach = 0.5f * d + 3.0f;
        if (!in_image(tree.mask, c + reach * n, 1.0f) || !in_image(tree.mask, c - reach * n, 1.0f))
          continue;
        // Only where no other limb comes within 3 px of the scan line.
        bool clear = true;
        const Vec lo = (c - reach * n).cwiseMin(c + reach * n);
        const Vec hi = (c - reach * n).cwiseMax(c + reach * n);
        for (std::size_t lj = 0; lj < tree.limbs.size() && clear; ++lj) {
          if (lj == li || (boxes[lj].first.array() > hi.array()).any() ||
              (boxes[lj].second.array() < lo.array()).any())
            continue;
          for (float u = -reach; u <= reach && clear; u += 1.0f)
            clear = depth_to(tree.limbs[lj], c + u * n) > 3.0f;
        }
        if (!clear) continue;
        // Walk out to the first sky pixel on each side; the edge lies half-way between samples.
        auto edge = [&](const Vec& dir) {
          float u = 0.0f;
          while (tree_pixel(tree.mask, c + u * dir)) u += 0.05f;
          return u - 0.025f;
        };
        const float width = edge(n) + edge(-n);
        const float error = std::abs(width - d);
        worst = std::max(worst, error);
        ++measured;
        CHECK_MESSAGE(error <= 1.5f,
                      "limb " << li << " s " << s << " truth " << d << " measured " << width);
      }
    }
  }
  CHECK(measured > 200);
  MESSAGE(measured << " cross-sections, worst error " << worst << " px");
}

TEST_CASE("locate: points on and beside a centreline come back to that limb and arc position") {
  int located = 0, own = 0;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    tree_options o = small(seed);
    o.twigs = 6;
    const synthetic_tree tree = perch::support::make_tree(o);
    for (std::size_t li = 0; li < tree.limbs.size(); ++li) {
      const limb_truth& limb = tree.limbs[li];
      const float length = perch::support::length_px(limb);
      for (float s = 0.0f; s <= length; s += std::max(2.0f, 0.1f * length)) {
        for (const float offset : {0.0f, 0.4f, -0.4f}) {
          const float d = perch::support::truth_diameter_at(limb, s);
          const Vec t = perch::support::truth_tangent_at(limb, s);
          const Vec p = perch::support::truth_point_at(limb, s) + offset * d * Vec(-t.y(), t.x());
          const auto loc = perch::support::locate(tree, p);
          REQUIRE(loc.limb >= 0);
          ++located;
          // Whatever limb it names, the point is at least as deep inside it as inside this one.
          const limb_truth& found = tree.limbs[static_cast<std::size_t>(loc.limb)];
          CHECK(depth_to(found, p) <= depth_to(limb, p) + 1e-3f);
          CHECK(loc.inside());
          CHECK(std::abs(loc.distance_px - (p - loc.closest).norm()) < 1e-3f);
          CHECK(std::abs(loc.diameter_px - perch::support::truth_diameter_at(found, loc.arc_px)) <
                1e-2f);
          CHECK(loc.slope_deg >= 0.0f);
          CHECK(loc.slope_deg <= 90.0f);
          if (loc.limb != static_cast<int>(li)) continue;
          ++own;
          CHECK(std::abs(loc.distance_px - std::abs(offset) * d) < 0.05f + 0.01f * d);
          CHECK(std::abs(loc.arc_px - s) < 0.5f + 0.02f * d);
          CHECK(std::abs(loc.slope_deg - perch::support::truth_slope_deg_at(limb, s)) < 1.0f);
          CHECK(loc.curvature_per_px == approx(std::abs(limb.curvature_per_px)));
        }
      }
    }
  }
  // Most samples lie outside every other limb and come back to their own limb.
  CHECK(own > located * 3 / 4);
  MESSAGE(own << " of " << located << " samples located on their own limb");
  const auto nowhere = perch::support::locate(std::vector<limb_truth>{}, Vec(1, 1));
  CHECK(nowhere.limb == -1);
  CHECK_FALSE(nowhere.inside());
}

TEST_CASE("truth helpers: slope folded into [0, 90], diameter interpolated") {
  limb_truth limb;
  limb.centreline = {Vec(0, 0), Vec(10, 0), Vec(20, 0)};
  limb.diameter_px = {6.0f, 4.0f, 2.0f};
  limb.arc_px = {0.0f, 10.0f, 20.0f};
  limb.base_heading_rad = std::numbers::pi_v<float> / 2.0f;  // pointing +x: horizontal
  limb.exact_arc = true;  // the tangent from the heading (the polyline agrees at first)
  CHECK(perch::support::truth_slope_deg_at(limb, 5.0f) == approx(0.0f).epsilon(1e-4));
  CHECK(perch::support::truth_diameter_at(limb, 15.0f) == approx(3.0f));
  CHECK(perch::support::truth_diameter_at(limb, -5.0f) == approx(6.0f));
  CHECK(perch::support::truth_diameter_at(limb, 99.0f) == approx(2.0f));
  CHECK(perch::support::truth_point_at(limb, 12.5f).isApprox(Vec(12.5f, 0.0f)));
  for (const float heading_deg : {0.0f, 30.0f, -30.0f, 150.0f, -100.0f}) {
    limb.base_heading_rad = heading_deg * std::numbers::pi_v<float> / 180.0f;
    const float slope = perch::support::truth_slope_deg_at(limb, 0.0f);
    const float expected = 90.0f - std::abs(std::remainder(heading_deg, 180.0f));
    CHECK(slope == approx(std::abs(expected)).epsilon(1e-3));
  }
  const auto loc = perch::support::locate(std::vector<limb_truth>{limb}, Vec(15.0f, 1.0f));
  CHECK(loc.limb == 0);
  CHECK(loc.arc_px == approx(15.0f));
  CHECK(loc.distance_px == approx(1.0f));
  CHECK(loc.diameter_px == approx(3.0f));
}

TEST_CASE("benchmark trees: perchable limbs for a tendon claw exist at every size") {
  // Tendon claw (PLI paper): 30–110 mm diameter, slope ≤ 35°, over a 180 mm window.
  struct size {
    int w, h;
  };
  for (const size sz : {size{640, 480}, size{1920, 1080}}) {
    const synthetic_tree tree = perch::support::benchmark_tree(sz.w, sz.h, tree_noise::clean);
    CHECK(tree.limbs[0].diameter_px[0] * tree.mm_per_px == approx(180.0f));
    CHECK(tree.limbs[0].diameter_px[0] == approx(0.045f * static_cast<float>(sz.w)));
    const float window_px = 180.0f / tree.mm_per_px;
    int perchable_limbs = 0;
    for (const limb_truth& limb : tree.limbs) {
      const float length = perch::support::length_px(limb);
      bool found = false;
      for (float s = 0.0f; s + window_px <= length && !found; s += 1.0f) {
        bool ok = true;
        for (float u = s; u <= s + window_px && ok; u += 0.5f * window_px) {
          const float d_mm = perch::support::truth_diameter_at(limb, u) * tree.mm_per_px;
          ok = d_mm >= 30.0f && d_mm <= 110.0f &&
               perch::support::truth_slope_deg_at(limb, u) <= 35.0f &&
               in_image(tree.mask, perch::support::truth_point_at(limb, u));
        }
        found = ok;
      }
      perchable_limbs += found ? 1 : 0;
    }
    CHECK(perchable_limbs >= 2);
    MESSAGE(sz.w << "x" << sz.h << ": " << perchable_limbs << " limbs with a tendon-claw perch");
  }
}

TEST_CASE("benchmark trees: 4000x3000 clean and noisy") {
  for (const tree_noise noise : {tree_noise::clean, tree_noise::noisy}) {
    const auto start = std::chrono::steady_clock::now();
    const synthetic_tree tree = perch::support::benchmark_tree(4000, 3000, noise);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    CHECK(tree.mask.width() == 4000);
    CHECK(tree.mask.height() == 3000);
    CHECK(tree.mm_per_px == approx(1.0f));
    const double share = foreground_share(tree.mask);
    CHECK(share >= 0.05);
    CHECK(share <= 0.40);
    MESSAGE("4000x3000 " << (noise == tree_noise::noisy ? "noisy" : "clean") << ": " << ms
                         << " ms, " << tree.limbs.size() << " limbs, foreground " << share);
  }
}

TEST_CASE("make_tree: invalid options give an empty tree") {
  tree_options o;
  o.width = 0;
  CHECK(perch::support::make_tree(o).mask.width() == 0);
  o = tree_options{};
  o.mm_per_px = 0.0f;
  CHECK(perch::support::make_tree(o).limbs.empty());
  o = tree_options{};
  o.trunk_diameter_mm = std::nanf("");
  CHECK(perch::support::make_tree(o).mask.view().empty());
  // Degenerate but valid: a bare trunk, a tiny image.
  o = tree_options{};
  o.levels = 0;
  o.side_limbs = 0;
  const synthetic_tree bare = perch::support::make_tree(o);
  CHECK(bare.limbs.size() == 1);
  CHECK(count_components8(bare.mask) == 1);
  o = tree_options{};
  o.width = 3;
  o.height = 2;
  const synthetic_tree tiny = perch::support::make_tree(o);
  CHECK(tiny.mask.width() == 3);
}

// ------------------------------------------------------------------------------------------------
// The truth's rules (perch_truth) on hand-built trees, 1 mm/px unless said: a window is 180 px.
// ------------------------------------------------------------------------------------------------

namespace {

using perch::support::perch_truth;
using perch::support::window_verdict;

/// A polyline limb through `points` with diameters `d` (px).
limb_truth polyline_limb(std::vector<Vec> points, std::vector<float> d,
                         limb_kind kind = limb_kind::trunk, int parent = -1) {
  limb_truth limb;
  limb.kind = kind;
  limb.parent = parent;
  limb.centreline = std::move(points);
  limb.diameter_px = std::move(d);
  limb.arc_px.assign(limb.centreline.size(), 0.0f);
  for (std::size_t i = 1; i < limb.centreline.size(); ++i)
    limb.arc_px[i] = limb.arc_px[i - 1] + (limb.centreline[i] - limb.centreline[i - 1]).norm();
  return limb;
}

/// A straight limb from a to b, diameters da → db.
limb_truth straight_limb(Vec a, Vec b, float da, float db, limb_kind kind = limb_kind::trunk,
                         int parent = -1) {
  return polyline_limb({a, b}, {da, db}, kind, parent);
}

/// A tree of these limbs on a w×h mask (drawn, though the truth never reads it).
synthetic_tree hand_tree(int w, int h, float mm_per_px, std::vector<limb_truth> limbs) {
  synthetic_tree tree;
  tree.mm_per_px = mm_per_px;
  tree.mask = image<std::uint8_t>(w, h, 0);
  tree.limbs = std::move(limbs);
  for (const limb_truth& limb : tree.limbs) {
    std::vector<float> radii;
    for (const float d : limb.diameter_px) radii.push_back(0.5f * d);
    perch::support::draw_polyline(tree.mask.view(), limb.centreline, radii);
  }
  return tree;
}

/// A level 60 mm limb along y = 300 from x = 100 to 700, and a second, `d_other` thick, level
/// above it with its surface `gap` px (mm) from the first's (kind `other_kind`, its own tree).
synthetic_tree two_level_limbs(float gap, float d_other, limb_kind other_kind = limb_kind::trunk) {
  const float y = 300.0f - 30.0f - gap - 0.5f * d_other;
  limb_truth other = straight_limb(Vec(100, y), Vec(700, y), d_other, d_other, other_kind);
  other.tree = 1;
  return hand_tree(800, 600, 1.0f,
                   {straight_limb(Vec(100, 300), Vec(700, 300), 60.0f, 60.0f), other});
}

}  // namespace

TEST_CASE("bias_radii and shift_outline: limbs drawn thicker or thinner, the rest kept") {
  // A level limb 5.6 px thick along y = 10: columns of 5 px (|dy| <= 2.8). A lone noise pixel
  // and a pinhole away from the limb's outline stay whatever the bias.
  auto column = [](const synthetic_tree& t, int x) {
    int n = 0;
    for (int y = 0; y < t.mask.height(); ++y) n += t.mask(x, y) != 0 ? 1 : 0;
    return n;
  };
  auto make = []() {
    synthetic_tree t = hand_tree(60, 21, 1.0f, {straight_limb(Vec(5, 10), Vec(50, 10), 5.6f, 5.6f)});
    t.mask(56, 2) = 1;   // noise
    t.mask(30, 10) = 0;  // pinhole on the axis
    return t;
  };
  const synthetic_tree drawn = make();
  CHECK(column(drawn, 20) == 5);
  for (const auto& [bias, width] : {std::pair{0.5f, 7}, std::pair{0.1f, 5}, std::pair{-0.5f, 5},
                                    std::pair{-0.9f, 3}, std::pair{-3.0f, 0}}) {
    CAPTURE(bias);
    synthetic_tree t = make();
    perch::support::bias_radii(t, bias);
    CHECK(column(t, 20) == width);
    CHECK(t.mask(56, 2) != 0);
    CHECK(t.mask(30, 10) == (bias > 0.0f ? 1 : 0));  // a thicker limb is drawn over its pinhole
    CHECK(t.limbs[0].diameter_px[0] == 5.6f);        // the truth stays
  }
  synthetic_tree wider = make(), narrower = make();
  perch::support::shift_outline(wider.mask, 1);
  perch::support::shift_outline(narrower.mask, -1);
  CHECK(column(wider, 20) == 7);
  CHECK(column(narrower, 20) == 3);
  CHECK(narrower.mask(56, 2) == 0);  // a whole-pixel erosion takes the lone pixel too
}

TEST_CASE("cut_gaps: bands cut across limbs, nothing inside another limb, the truth kept") {
  // A trunk 12 px thick and a child 8 px thick leaving it level at y = 50.
  auto make = []() {
    return hand_tree(120, 100, 1.0f,
                     {straight_limb(Vec(30, 99), Vec(30, 0), 12.0f, 12.0f),
                      straight_limb(Vec(30, 50), Vec(110, 50), 8.0f, 8.0f, limb_kind::limb, 0)});
  };
  const synthetic_tree drawn = make();
  synthetic_tree none = make();
  perch::support::cut_gaps(none, 0, 7u);
  CHECK(std::equal(none.mask.data(), none.mask.data() + 120 * 100, drawn.mask.data()));
  synthetic_tree cut = make(), again = make();
  perch::support::cut_gaps(cut, 6, 7u);
  perch::support::cut_gaps(again, 6, 7u);
  CHECK(std::equal(cut.mask.data(), cut.mask.data() + 120 * 100, again.mask.data()));  // seeded
  int removed = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 120; ++x) {
      if (drawn.mask(x, y) == 0 || cut.mask(x, y) != 0) continue;
      ++removed;
      const Vec p(static_cast<float>(x), static_cast<float>(y));
      const float to_trunk = perch::support::detail::surface_distance(drawn.limbs[0], p);
      const float to_child = perch::support::detail::surface_distance(drawn.limbs[1], p);
      CHECK_FALSE((to_trunk <= 0.5f && to_child <= 0.5f));  // the junction is both limbs: kept
    }
  CHECK(removed > 0);
  CHECK(cut.limbs[1].centreline == drawn.limbs[1].centreline);  // the truth stays
  CHECK(cut.limbs[1].parent == 0);
}

TEST_CASE("perch_truth: clearance is 70 mm from every other limb's surface at least 20 mm thick") {
  {
    const synthetic_tree tree = two_level_limbs(69.0f, 40.0f);
    const perch_truth truth(tree);
    const auto w = truth.window(0, 300.0f);
    CHECK(w.verdict == window_verdict::clearance);
    CHECK(w.clearance_mm == approx(69.0f).epsilon(1e-3));
  }
  {
    const synthetic_tree tree = two_level_limbs(71.0f, 40.0f);
    const perch_truth truth(tree);
    const auto w = truth.window(0, 300.0f);
    CHECK(w.verdict == window_verdict::feasible);
    CHECK(w.clearance_mm == approx(71.0f).epsilon(1e-3));
    CHECK(truth.has_perch());
  }
  // Thinner than 20 mm there, or a twig: no obstacle. A fragment is one.
  CHECK(perch_truth(two_level_limbs(30.0f, 19.0f)).window(0, 300.0f).verdict ==
        window_verdict::feasible);
  CHECK(perch_truth(two_level_limbs(30.0f, 40.0f, limb_kind::twig)).window(0, 300.0f).verdict ==
        window_verdict::feasible);
  CHECK(perch_truth(two_level_limbs(30.0f, 40.0f, limb_kind::fragment)).window(0, 300.0f).verdict ==
        window_verdict::clearance);
  // A tapering obstacle counts only where it is 20 mm thick or more: 40 → 0 mm from x 100 to
  // 700 is 20 mm at x = 400; beyond it, it is no obstacle (its surface 25–50 px from ours), so
  // a window over x ∈ [510, 690] passes, its gap measured to (400, 250), radius 10.
  {
    limb_truth taper = straight_limb(Vec(100, 250), Vec(700, 250), 40.0f, 0.0f);
    taper.tree = 1;
    const synthetic_tree tree = hand_tree(
        800, 600, 1.0f, {straight_limb(Vec(100, 300), Vec(700, 300), 60.0f, 60.0f), taper});
    const perch_truth truth(tree);
    CHECK(truth.window(0, 200.0f).verdict == window_verdict::clearance);
    const auto far = truth.window(0, 500.0f);
    CHECK(far.verdict == window_verdict::feasible);
    // From (510, 300), radius 30: √(110² + 50²) − 10 − 30 ≈ 80.8 mm.
    CHECK(far.clearance_mm ==
          approx(std::sqrt(110.0f * 110.0f + 50.0f * 50.0f) - 40.0f).epsilon(1e-3));
  }
}

TEST_CASE("perch_truth: a window near its own base is inside its parent; one over a child fails") {
  // A level 80 mm parent along y = 300; a 40 mm child leaving its axis at (400, 300), rising at
  // 30°. At arc s the child's axis is s/2 from the parent's, its surface s/2 − 40 − 20 from the
  // parent's surface: ≥ 70 from s = 260 on, so windows centred at c ≥ 350 pass.
  const float c30 = std::cos(std::numbers::pi_v<float> / 6.0f);
  const Vec base(400, 300), tip = base + 500.0f * Vec(c30, -0.5f);
  const synthetic_tree tree =
      hand_tree(1000, 600, 1.0f,
                {straight_limb(Vec(50, 300), Vec(950, 300), 80.0f, 80.0f),
                 straight_limb(base, tip, 40.0f, 40.0f, limb_kind::limb, 0)});
  const perch_truth truth(tree);
  const auto near_base = truth.window(1, 95.0f);
  CHECK(near_base.verdict == window_verdict::clearance);
  CHECK(near_base.clearance_mm < 0.0f);  // inside the parent
  CHECK(truth.window(1, 345.0f).verdict == window_verdict::clearance);
  CHECK(truth.window(1, 345.0f).clearance_mm == approx(67.5f).epsilon(1e-3));
  CHECK(truth.window(1, 355.0f).verdict == window_verdict::feasible);
  CHECK(truth.window(1, 355.0f).slope_deg == approx(30.0f).epsilon(1e-3));
  const auto over_child = truth.window(0, 350.0f);  // the parent's window over the child's base
  CHECK(over_child.verdict == window_verdict::clearance);
  CHECK(over_child.clearance_mm < 0.0f);
  // Far from the child: window x ∈ [60, 240], the child's base 160 px away (gap 100 mm).
  CHECK(truth.window(0, 100.0f).verdict == window_verdict::feasible);
}

TEST_CASE("perch_truth: the border margin is 3 px beyond the limb's surface") {
  for (const float margin : {2.0f, 3.0f}) {
    const float y = 20.0f + margin;  // 40 px limb: its surface `margin` from the top edge
    const synthetic_tree tree =
        hand_tree(800, 600, 1.0f, {straight_limb(Vec(100, y), Vec(700, y), 40.0f, 40.0f)});
    const auto w = perch_truth(tree).window(0, 300.0f);
    CHECK(w.border_px == approx(margin));
    CHECK(w.verdict == (margin < 3.0f ? window_verdict::outside_image : window_verdict::feasible));
  }
  // The left edge, at the window's end only.
  const synthetic_tree tree =
      hand_tree(800, 600, 1.0f, {straight_limb(Vec(22, 300), Vec(700, 300), 40.0f, 40.0f)});
  const perch_truth truth(tree);
  CHECK(truth.window(0, 90.0f).verdict == window_verdict::outside_image);  // end at x = 22
  CHECK(truth.window(0, 91.5f).verdict == window_verdict::feasible);       // end at x = 23.5
}

TEST_CASE("perch_truth: diameter, then resolution: a 3 px wide 36 mm limb is no safe grasp") {
  // 12 mm/px: 36 mm is 3 px; 3 − 1 = 2 px is below 30 mm (2.5 px).
  const synthetic_tree thin =
      hand_tree(200, 100, 12.0f, {straight_limb(Vec(20, 50), Vec(180, 50), 3.0f, 3.0f)});
  const auto w = perch_truth(thin).window(0, 80.0f);
  CHECK(w.claw_diameter_mm == approx(36.0f));
  CHECK(w.verdict == window_verdict::resolution);
  // 4 px = 48 mm: 3 px = 36 mm ≥ 30, 5 px = 60 mm ≤ 110: fine.
  const synthetic_tree ok =
      hand_tree(200, 100, 12.0f, {straight_limb(Vec(20, 50), Vec(180, 50), 4.0f, 4.0f)});
  CHECK(perch_truth(ok).window(0, 80.0f).verdict == window_verdict::feasible);
  // 1 mm/px: 115 mm is out of range (diameter), 109.5 mm within it but 110.5 mm after a pixel.
  for (const auto& [d, expected] :
       {std::pair{115.0f, window_verdict::diameter}, std::pair{109.5f, window_verdict::resolution},
        std::pair{100.0f, window_verdict::feasible}}) {
    const synthetic_tree tree =
        hand_tree(800, 600, 1.0f, {straight_limb(Vec(100, 300), Vec(700, 300), d, d)});
    CHECK(perch_truth(tree).window(0, 300.0f).verdict == expected);
  }
}

TEST_CASE("perch_truth: twigs by kind or by thickness; fragments and their limbs unsupported") {
  const synthetic_tree tree = hand_tree(
      1000, 800, 1.0f,
      {straight_limb(Vec(100, 100), Vec(700, 100), 19.5f, 19.5f),  // thin everywhere: a twig
       straight_limb(Vec(100, 300), Vec(700, 300), 50.0f, 50.0f, limb_kind::fragment),
       straight_limb(Vec(400, 300), Vec(400, 700), 50.0f, 50.0f, limb_kind::twig, 1),
       straight_limb(Vec(700, 300), Vec(900, 500), 40.0f, 40.0f, limb_kind::limb, 1),
       straight_limb(Vec(100, 600), Vec(300, 600), 40.0f, 40.0f, limb_kind::limb, 3)});
  const perch_truth truth(tree);
  CHECK(truth.window(0, 300.0f).verdict == window_verdict::twig);
  CHECK(truth.window(1, 300.0f).verdict == window_verdict::unsupported);
  CHECK(truth.window(2, 200.0f).verdict == window_verdict::twig);
  CHECK(truth.window(4, 100.0f).verdict == window_verdict::unsupported);  // grandchild
  CHECK(!truth.has_perch());
  CHECK(std::string(perch::support::to_string(window_verdict::unsupported)) == "unsupported");
}

TEST_CASE("perch_truth: slope at every point, bend over a window length around a kink") {
  auto slope_tree = [](float deg) {
    const float a = deg * std::numbers::pi_v<float> / 180.0f;
    const Vec base(100, 500);
    return hand_tree(
        900, 700, 1.0f,
        {straight_limb(base, base + 600.0f * Vec(std::cos(a), -std::sin(a)), 50.0f, 50.0f)});
  };
  CHECK(perch_truth(slope_tree(34.0f)).window(0, 300.0f).verdict == window_verdict::feasible);
  const auto steep = perch_truth(slope_tree(36.0f)).window(0, 300.0f);
  CHECK(steep.verdict == window_verdict::slope);
  CHECK(steep.slope_deg == approx(36.0f).epsilon(1e-3));
  // Level for 300 px, then a kink of 30° (rising): windows within a window length of the kink
  // see it (bend), others not; the steepest local slope, not the chord, is judged.
  const float a = 30.0f * std::numbers::pi_v<float> / 180.0f;
  const Vec k(100, 500);
  const synthetic_tree kinked =
      hand_tree(1000, 700, 1.0f,
                {polyline_limb(
                    {k, k + Vec(300, 0), k + Vec(300, 0) + 300.0f * Vec(std::cos(a), -std::sin(a))},
                    {50.0f, 50.0f, 50.0f})});
  const perch_truth truth(kinked);
  const auto at_kink = truth.window(0, 300.0f);
  CHECK(at_kink.verdict == window_verdict::bend);
  CHECK(at_kink.bend_deg == approx(30.0f).epsilon(1e-3));
  CHECK(at_kink.slope_deg == approx(30.0f).epsilon(1e-3));
  CHECK(truth.window(0, 140.0f).verdict == window_verdict::bend);  // s + 90 reaches the kink
  CHECK(truth.window(0, 100.0f).verdict == window_verdict::feasible);
  CHECK(truth.window(0, 100.0f).bend_deg == approx(0.0f));
  CHECK(truth.window(0, 500.0f).verdict == window_verdict::feasible);
  CHECK(truth.window(0, 460.0f).verdict == window_verdict::bend);
  // A gentle 15° kink is allowed.
  const float b = 15.0f * std::numbers::pi_v<float> / 180.0f;
  const synthetic_tree gentle =
      hand_tree(1000, 700, 1.0f,
                {polyline_limb(
                    {k, k + Vec(300, 0), k + Vec(300, 0) + 300.0f * Vec(std::cos(b), -std::sin(b))},
                    {50.0f, 50.0f, 50.0f})});
  CHECK(perch_truth(gentle).window(0, 300.0f).verdict == window_verdict::feasible);
}

TEST_CASE("perch_truth: window off the limb; measures filled; stretches only of feasible windows") {
  const synthetic_tree tree =
      hand_tree(800, 600, 1.0f, {straight_limb(Vec(100, 300), Vec(700, 300), 60.0f, 60.0f)});
  const perch_truth truth(tree);
  CHECK(truth.window(0, 80.0f).verdict == window_verdict::off_limb);
  CHECK(truth.window(0, 90.0f).verdict == window_verdict::feasible);
  CHECK(truth.window(0, 511.0f).verdict == window_verdict::off_limb);
  REQUIRE(truth.stretches().size() == 1);
  CHECK(truth.stretches()[0].arc_begin_px == approx(0.0f));
  CHECK(truth.stretches()[0].arc_end_px == approx(600.0f));
  CHECK(truth.is_feasible_site(Vec(400, 301), 1.5f));
  CHECK(!truth.is_feasible_site(Vec(150, 300), 1.5f));  // within half a window of the base
  CHECK(truth.window(5, 100.0f).limb == 5);             // no such limb: off_limb
  CHECK(truth.window(5, 100.0f).verdict == window_verdict::off_limb);
}

// ------------------------------------------------------------------------------------------------
// The variety knobs
// ------------------------------------------------------------------------------------------------

namespace {

/// The heading of a polyline segment, degrees from vertical-up (+ towards +x).
double segment_heading_deg(const limb_truth& limb, std::size_t i) {
  const Vec d = limb.centreline[i + 1] - limb.centreline[i];
  return std::atan2(static_cast<double>(d.x()), -static_cast<double>(d.y())) * 180.0 /
         std::numbers::pi;
}

double wrap_deg(double a) { return std::remainder(a, 360.0); }

/// Every limb but the roots starts on its parent's centreline.
void check_attached(const synthetic_tree& tree) {
  for (const limb_truth& limb : tree.limbs) {
    if (limb.parent < 0) continue;
    const limb_truth& parent = tree.limbs[static_cast<std::size_t>(limb.parent)];
    CHECK((limb.centreline[0] - perch::support::truth_point_at(parent, limb.parent_arc_px)).norm() <
          0.01f);
  }
}

}  // namespace

TEST_CASE("tree_options::bending: deterministic smooth wander, no longer one arc") {
  tree_options o = small(3);
  o.bending = 0.8f;
  const synthetic_tree a = perch::support::make_tree(o), b = perch::support::make_tree(o);
  CHECK(same_bytes(a.mask, b.mask));
  CHECK(!same_bytes(a.mask, perch::support::make_tree(small(3)).mask));
  check_attached(a);
  int wandering = 0;
  for (const limb_truth& limb : a.limbs) {
    if (limb.kind != limb_kind::limb && limb.kind != limb_kind::trunk) continue;
    CHECK(!limb.exact_arc);
    // Heading at quarter points: an arc turns evenly; a wandering limb does not.
    auto heading_at = [&](float u) {
      float t = 0.0f;
      const std::size_t i =
          perch::support::detail::segment_at(limb, u * perch::support::length_px(limb), t);
      return segment_heading_deg(limb, i);
    };
    const double second = wrap_deg(heading_at(0.75f) - heading_at(0.5f)) -
                          wrap_deg(heading_at(0.5f) - heading_at(0.25f));
    wandering += std::abs(second) > 3.0 ? 1 : 0;
    // Smooth: no two consecutive segments turn by 10° (kinks turn 20° or more; none asked).
    for (std::size_t i = 0; i + 2 < limb.centreline.size(); ++i)
      CHECK(std::abs(wrap_deg(segment_heading_deg(limb, i + 1) - segment_heading_deg(limb, i))) <
            10.0);
    // The mean curvature is the heading change over the length (the last segment's heading is
    // that of its middle: a few degrees from the tip's).
    const double turn =
        wrap_deg(segment_heading_deg(limb, limb.centreline.size() - 2) -
                 static_cast<double>(limb.base_heading_rad) * 180.0 / std::numbers::pi);
    CHECK(std::abs(static_cast<double>(limb.curvature_per_px * perch::support::length_px(limb)) *
                       180.0 / std::numbers::pi -
                   turn) < 6.0);
  }
  CHECK(wandering >= 3);
  // The tangent of a wandering limb follows the polyline.
  const limb_truth& trunk = a.limbs[0];
  const Vec t = perch::support::truth_tangent_at(trunk, 0.5f);
  const Vec d = (trunk.centreline[1] - trunk.centreline[0]).normalized();
  CHECK((t - d).norm() < 1e-4f);
}

TEST_CASE("tree_options::kinks: sharp turns of 20-60 degrees on limbs, the trunk straight") {
  int kinks = 0;
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    tree_options o = small(seed);
    o.kinks = 2;
    const synthetic_tree tree = perch::support::make_tree(o);
    CHECK(same_bytes(tree.mask, perch::support::make_tree(o).mask));
    check_attached(tree);
    for (const limb_truth& limb : tree.limbs) {
      if (limb.kind != limb_kind::limb && limb.kind != limb_kind::trunk) continue;
      for (std::size_t i = 0; i + 2 < limb.centreline.size(); ++i) {
        const double turn =
            std::abs(wrap_deg(segment_heading_deg(limb, i + 1) - segment_heading_deg(limb, i)));
        if (turn < 5.0) continue;
        CHECK(limb.kind != limb_kind::trunk);
        CHECK(turn >= 19.0);
        CHECK(turn <= 61.0);  // two kinks may not share a vertex by chance: each 20–60°
        ++kinks;
      }
    }
  }
  CHECK(kinks >= 5);
}

TEST_CASE("tree_options::fragments: detached pieces of mask near the crown, unsupported") {
  for (const float noise : {0.0f, 3.0f}) {
    tree_options o = small(5);
    o.fragments = 4;
    o.noise = noise;
    const synthetic_tree tree = perch::support::make_tree(o);
    CHECK(same_bytes(tree.mask, perch::support::make_tree(o).mask));
    int fragments = 0;
    bool started = false;
    for (const limb_truth& limb : tree.limbs) {
      started = started || limb.kind == limb_kind::fragment;
      CHECK((limb.kind == limb_kind::fragment) == started);  // fragments come last
      if (limb.kind != limb_kind::fragment) continue;
      ++fragments;
      CHECK(limb.parent == -1);
      CHECK(limb.tree == 0);
      CHECK(in_image(tree.mask,
                     perch::support::truth_point_at(limb, 0.5f * perch::support::length_px(limb))));
    }
    CHECK(fragments >= 3);
    // Each is its own component: the tree and every fragment.
    CHECK(count_components8(tree.mask) == 1 + fragments);
    const perch_truth truth(tree);
    for (std::size_t i = 0; i < tree.limbs.size(); ++i)
      if (tree.limbs[i].kind == limb_kind::fragment) {
        const auto v =
            truth.window(static_cast<int>(i), 0.5f * perch::support::length_px(tree.limbs[i]))
                .verdict;
        CHECK((v == window_verdict::unsupported || v == window_verdict::twig ||
               v == window_verdict::off_limb));
      }
  }
}

TEST_CASE("tree_options::wide_side_angles: side limbs leave at 20-80 degrees") {
  int below_35 = 0, above_70 = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    tree_options o = small(seed);
    o.wide_side_angles = true;
    o.side_limbs = 2;
    const synthetic_tree tree = perch::support::make_tree(o);
    check_attached(tree);
    for (const limb_truth& limb : tree.limbs) {
      if (limb.parent < 0 || limb.kind != limb_kind::limb) continue;
      const limb_truth& parent = tree.limbs[static_cast<std::size_t>(limb.parent)];
      if (limb.parent_arc_px >= perch::support::length_px(parent)) continue;  // a fork child
      const Vec t = perch::support::truth_tangent_at(parent, limb.parent_arc_px);
      const double here = std::atan2(static_cast<double>(t.x()), -static_cast<double>(t.y())) *
                          180.0 / std::numbers::pi;
      const double divergence = std::abs(
          wrap_deg(static_cast<double>(limb.base_heading_rad) * 180.0 / std::numbers::pi - here));
      CHECK(divergence <= 80.5);
      below_35 += divergence < 35.0 ? 1 : 0;
      above_70 += divergence > 70.0 ? 1 : 0;
    }
  }
  CHECK(below_35 >= 1);
  CHECK(above_70 >= 1);
}

TEST_CASE("perch_truth: no-perch trees stay so with every knob") {
  int with = 0;
  double worst_ms = 0.0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    for (const bool none : {true, false}) {
      tree_options o = perch::support::benchmark_tree_options(960, 720, tree_noise::clean);
      o.seed = 500u + seed;
      o.mm_per_px = 180.0f / (0.08f * 960.0f);
      o.bending = 0.7f;
      o.kinks = 1;
      o.fragments = 3;
      o.wide_side_angles = true;
      o.crossings = 1;
      o.second_tree = seed % 2 == 0 ? 0.6f : 0.0f;
      o.noise = seed % 3 == 0 ? 2.5f : 0.0f;
      o.twigs = seed % 3 == 0 ? 8 : 0;
      if (none) o.perches = perch::support::perch_supply::none;
      const synthetic_tree tree = perch::support::make_tree(o);
      const auto start = std::chrono::steady_clock::now();
      const perch_truth truth(tree);
      worst_ms = std::max(worst_ms, std::chrono::duration<double, std::milli>(
                                        std::chrono::steady_clock::now() - start)
                                        .count());
      if (none)
        CHECK_MESSAGE(!truth.has_perch(), "seed " << o.seed);
      else
        with += truth.has_perch() ? 1 : 0;
    }
  }
  // Speed is the benchmarks' to measure, never a test's to assert: the time is only reported.
  MESSAGE(with << " of 12 natural trees with every knob have a perch; truth worst " << worst_ms
               << " ms");
}
