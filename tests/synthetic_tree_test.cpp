// Tests of the synthetic tree generator (examples/support/support/synthetic_tree.hpp): the masks
// the benchmarks, the tool's `synth` subcommand and the pipeline tests rely on, and their truth.
#include "support/synthetic_tree.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
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
        12782355193781005450ull);
  CHECK(fnv1a(perch::support::benchmark_tree(640, 480, tree_noise::noisy).mask) ==
        11261795359396173248ull);
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

TEST_CASE("benchmark trees: 4000x3000 clean and noisy in well under a second") {
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
    CHECK(ms < 3000.0);  // generous for sanitizer builds; ~50 ms optimised
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
