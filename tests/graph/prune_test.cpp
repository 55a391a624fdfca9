// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/prune.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/graph/skeleton_graph.hpp"
#include "support/ascii_art.hpp"

using perch::branch_type;
using perch::node_kind;
using perch::prune_options;
using perch::skeleton_graph;

namespace {

/// doctest::Approx of a float without an implicit promotion (-Wdouble-promotion).
doctest::Approx approx(float v) { return doctest::Approx(static_cast<double>(v)); }

using u8image = perch::image<std::uint8_t>;
using u32image = perch::image<std::uint32_t>;

perch::image_view<const std::uint32_t> cview(const u32image& d) {
  return {d.data(), d.width(), d.height()};
}
perch::image_view<const std::uint8_t> cview(const u8image& d) {
  return {d.data(), d.width(), d.height()};
}

/// Brute-force squared Euclidean distance to the nearest background pixel centre; pixels
/// outside the image are background. Slow and obviously right.
u32image brute_edt(const u8image& mask) {
  const int w = mask.width(), h = mask.height();
  u32image out(w, h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (mask(x, y) == 0) continue;
      long long best = std::min({(x + 1LL) * (x + 1LL), (w - x) * 1LL * (w - x),
                                 (y + 1LL) * (y + 1LL), (h - y) * 1LL * (h - y)});
      for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u)
          if (mask(u, v) == 0)
            best = std::min(best, 1LL * (u - x) * (u - x) + 1LL * (v - y) * (v - y));
      out(x, y) = static_cast<std::uint32_t>(best);
    }
  return out;
}

/// Paints every pixel within `radius` of segment (a, b).
void thick_line(u8image& m, perch::pixel a, perch::pixel b, float radius) {
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x) {
      const float ax = static_cast<float>(a.x), ay = static_cast<float>(a.y);
      const float dx = static_cast<float>(b.x - a.x), dy = static_cast<float>(b.y - a.y);
      const float len2 = dx * dx + dy * dy;
      float t = len2 > 0 ? ((static_cast<float>(x) - ax) * dx + (static_cast<float>(y) - ay) * dy) / len2 : 0;
      t = std::clamp(t, 0.0f, 1.0f);
      const float px = ax + t * dx - static_cast<float>(x), py = ay + t * dy - static_cast<float>(y);
      if (px * px + py * py <= radius * radius) m(x, y) = 1;
    }
}

/// An 8-connected digital segment (Bresenham).
void thin_line(u8image& m, perch::pixel a, perch::pixel b) {
  int x = a.x, y = a.y;
  const int dx = std::abs(b.x - a.x), dy = -std::abs(b.y - a.y);
  const int sx = a.x < b.x ? 1 : -1, sy = a.y < b.y ? 1 : -1;
  int err = dx + dy;
  for (;;) {
    m(x, y) = 1;
    if (x == b.x && y == b.y) break;
    const int e2 = 2 * err;
    if (e2 >= dy) { err += dy; x += sx; }
    if (e2 <= dx) { err += dx; y += sy; }
  }
}

struct counts {
  int ends = 0, junctions = 0, loops = 0, isolated = 0;
};
counts count_nodes(const skeleton_graph& g) {
  counts c;
  g.for_each_node([&](const perch::skeleton_node& n) {
    c.ends += n.kind == node_kind::end;
    c.junctions += n.kind == node_kind::junction;
    c.loops += n.kind == node_kind::loop;
    c.isolated += n.kind == node_kind::isolated;
  });
  return c;
}

void check_handshake(const skeleton_graph& g) {
  long long sum = 0;
  g.for_each_node([&](const perch::skeleton_node& n) { sum += n.degree; });
  CHECK(sum == 2 * static_cast<long long>(g.branch_count()));
  g.for_each_branch([&](const perch::skeleton_branch& b) {
    CHECK(b.points.size() == b.radius_px.size());
    CHECK(g.contains_node(b.from));
    CHECK(g.contains_node(b.to));
  });
}

/// The T of the weighting test: a bar of 11 px at y = 0 and a stem of 9 px below its middle.
/// Left arm r = 2 (diameter 3 px), right arm r = 1 (1 px), stem and junction r = 3 (5 px).
struct t_shape {
  u8image skeleton = perch::support::mask_from_ascii(R"(
    ###########
    .....#.....
    .....#.....
    .....#.....
    .....#.....
    .....#.....
    .....#.....
    .....#.....
    .....#.....
    .....#.....
  )");
  u32image dist2{skeleton.width(), skeleton.height(), 0};
  t_shape() {
    for (int x = 0; x < 5; ++x) dist2(x, 0) = 4;
    for (int x = 6; x < 11; ++x) dist2(x, 0) = 1;
    for (int y = 0; y < 10; ++y) dist2(5, y) = 9;
  }
};

}  // namespace

TEST_CASE("prune: eq. 1 weights computed by hand") {
  t_shape t;
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(t.skeleton), cview(t.dist2), ws);
  REQUIRE(g);
  REQUIRE(g->branch_count() == 3);
  // 10 mm/px: diameters 30 mm (in [30, 110]), 10 mm (out), 50 mm (in).
  REQUIRE(perch::weigh_skeleton_graph(*g, 10.0f));
  g->for_each_branch([&](const perch::skeleton_branch& b) {
    const perch::pixel p = b.points.front();
    if (b.points.size() == 9) {  // stem: l = 9 = L_max, w̄ = 5 = W_max, f_in = 1
      CHECK(b.length_px == approx(9.0f));
      CHECK(b.weight == approx(0.6f + 0.4f));
    } else if (p.x < 5) {  // left: 0.6·5/9 + 0.4·1·3/5
      CHECK(b.length_px == approx(5.0f));
      CHECK(b.mean_diameter_px == approx(3.0f));
      CHECK(b.weight == approx(0.6f * 5.0f / 9.0f + 0.4f * 3.0f / 5.0f));
    } else {  // right: f_in = 0
      CHECK(b.weight == approx(0.6f * 5.0f / 9.0f));
    }
  });
  // α = 0: width only.
  REQUIRE(perch::weigh_skeleton_graph(*g, 10.0f, prune_options{.alpha = 0.0f}));
  g->for_each_branch([&](const perch::skeleton_branch& b) {
    if (b.points.size() == 9) CHECK(b.weight == approx(1.0f));
  });
}

TEST_CASE("prune: a weak short leaf goes, the degree-2 merge joins points and radii in order") {
  t_shape t;
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(t.skeleton), cview(t.dist2), ws);
  REQUIRE(g);
  const perch::node_id trunk = g->trunk(0);
  CHECK(g->node(trunk).position == perch::pixel{5, 9});
  // Spur rule off; the right arm (W = 1/3, 50 mm) is weak and shorter than 60 mm.
  const prune_options o{.max_length_mm = 60.0f, .tip_spur_factor = 0.0f, .tip_spur_px = 0.0f};
  auto report = perch::prune_skeleton_graph(*g, 10.0f, ws, o);
  REQUIRE(report);
  CHECK(report->weak_leaves_removed == 1);
  CHECK(report->tip_spurs_removed == 0);
  CHECK(report->nodes_merged == 1);
  CHECK(report->nodes_removed == 1);
  CHECK(report->branches_before == 3);
  CHECK(report->branches_after == 1);
  REQUIRE(g->branch_count() == 1);
  check_handshake(*g);
  perch::skeleton_branch merged{};
  g->for_each_branch([&](const perch::skeleton_branch& b) { merged = b; });
  // Left arm (x 0..4), the junction pixel (5,0), the stem (5,1..9), in walking order.
  REQUIRE(merged.points.size() == 15);
  const bool from_left = merged.points.front() == perch::pixel{0, 0};
  std::vector<perch::pixel> expected;
  for (int x = 0; x <= 5; ++x) expected.push_back({x, 0});
  for (int y = 1; y <= 9; ++y) expected.push_back({5, y});
  if (!from_left) std::reverse(expected.begin(), expected.end());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(merged.points[i] == expected[i]);
    const float r = expected[i].x < 5 ? 2.0f : 3.0f;
    CHECK(merged.radius_px[i] == approx(r));
  }
  CHECK(merged.length_px == approx(14.0f));
  CHECK(merged.mean_diameter_px == approx((5 * 3.0f + 10 * 5.0f) / 15.0f));
  CHECK(merged.type == branch_type::tip_tip);
  CHECK(g->contains_node(trunk));
}

TEST_CASE("prune: a noisy-boundary skeleton loses every short spur and keeps its line") {
  // A band 11 px thick whose left end bends down to the image bottom (the trunk), its
  // centreline, and 2–4 px spurs up and down every 5 px.
  u8image mask(70, 25, 0);
  for (int y = 7; y <= 17; ++y)
    for (int x = 0; x < 70; ++x) mask(x, y) = 1;
  for (int y = 7; y < 25; ++y)
    for (int x = 0; x <= 10; ++x) mask(x, y) = 1;
  u8image skeleton(70, 25, 0);
  thin_line(skeleton, {5, 24}, {5, 12});
  thin_line(skeleton, {5, 12}, {66, 12});
  int spurs = 0;
  for (int x = 9; x <= 54; x += 5) {  // the last one 12 px from the tip
    const int length = 2 + (x / 5) % 3;
    const int dir = (x / 5) % 2 == 0 ? -1 : 1;
    for (int k = 1; k <= length; ++k) skeleton(x, 12 + dir * k) = 1;
    ++spurs;
  }
  const u32image dist2 = brute_edt(mask);
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  CHECK(g->branch_count() == static_cast<std::size_t>(2 * spurs + 1));
  CHECK(g->node(g->trunk(0)).position == perch::pixel{5, 24});
  auto report = perch::prune_skeleton_graph(*g, 1.0f, ws);
  REQUIRE(report);
  CHECK(report->tip_spurs_removed == static_cast<std::uint32_t>(spurs));
  CHECK(report->nodes_merged == static_cast<std::uint32_t>(spurs));
  REQUIRE(g->branch_count() == 1);
  CHECK(g->node_count() == 2);
  check_handshake(*g);
  g->for_each_branch([&](const perch::skeleton_branch& b) {
    REQUIRE(b.points.size() == 13 + 61);
    CHECK(b.length_px == approx(12.0f + 61.0f));
    std::vector<perch::pixel> expected;
    for (int y = 24; y >= 12; --y) expected.push_back({5, y});
    for (int x = 6; x <= 66; ++x) expected.push_back({x, 12});
    if (b.points.front() != expected.front()) std::reverse(expected.begin(), expected.end());
    for (std::size_t i = 0; i < b.points.size(); ++i) CHECK(b.points[i] == expected[i]);
    CHECK(b.type == branch_type::tip_tip);
  });
}

TEST_CASE("prune: a long thin real branch stays; so does a loop") {
  // A thick trunk (r ≈ 6) with a long thin side branch (r ≈ 1.5).
  u8image mask(60, 90, 0);
  thick_line(mask, {20, 5}, {20, 89}, 6.0f);
  thick_line(mask, {20, 40}, {55, 10}, 1.5f);
  u8image skeleton(60, 90, 0);
  thin_line(skeleton, {20, 5}, {20, 89});
  thin_line(skeleton, {21, 39}, {55, 10});
  const u32image dist2 = brute_edt(mask);
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  const std::size_t before = g->branch_count();
  CHECK(before == 3);
  auto report = perch::prune_skeleton_graph(*g, 2.0f, ws);
  REQUIRE(report);
  CHECK(g->branch_count() == 3);
  CHECK(count_nodes(*g).junctions == 1);

  // A ring with a tail (the trunk) and a one-pixel spur: the spur goes, its junction is merged
  // away, and the ring stays as a cycle at the tail's junction.
  u8image ring = perch::support::mask_from_ascii(R"(
    ..........
    ...####...
    ..#....#..
    .#......#.
    .#......##
    .#......#.
    ..#....#..
    ...####...
    .....#....
    .....#....
    .....#....
  )");
  u32image d(ring.width(), ring.height(), 9);
  auto gr = perch::build_skeleton_graph(cview(ring), cview(d), ws);
  REQUIRE(gr);
  CHECK(gr->branch_count() == 4);
  CHECK(gr->node(gr->trunk(0)).position == perch::pixel{5, 10});
  auto ring_report = perch::prune_skeleton_graph(*gr, 1.0f, ws);
  REQUIRE(ring_report);
  CHECK(ring_report->tip_spurs_removed == 1);
  REQUIRE(gr->branch_count() == 2);
  int cycles = 0;
  gr->for_each_branch([&](const perch::skeleton_branch& b) {
    if (b.type != branch_type::cycle) return;
    ++cycles;
    CHECK(b.points.size() == 17);  // 18 ring pixels minus the tail's junction pixel
  });
  CHECK(cycles == 1);
  CHECK(count_nodes(*gr).junctions == 1);
  check_handshake(*gr);
}

TEST_CASE("prune: the trunk path is never removed") {
  // Every leaf is weak (threshold above any weight) and short: all go except the trunk's.
  t_shape t;
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(t.skeleton), cview(t.dist2), ws);
  REQUIRE(g);
  const perch::node_id trunk = g->trunk(0);
  auto report = perch::prune_skeleton_graph(
      *g, 1.0f, ws, prune_options{.weight_threshold = 2.0f, .max_length_mm = 1000.0f});
  REQUIRE(report);
  REQUIRE(g->contains_node(trunk));
  CHECK(g->node(trunk).degree == 1);
  CHECK(g->branch_count() == 1);
  CHECK(g->component_count() == 1);
  check_handshake(*g);
}

TEST_CASE("prune: thick Y and X with forked tips -> 1 junction, 3 and 4 branches") {
  for (const int scale : {1, 2}) {
    CAPTURE(scale);
    const float r = 4.0f * static_cast<float>(scale);
    const int s = scale;
    // Y: stem from the bottom edge up to the centre, two arms up-left and up-right.
    u8image mask(60 * s, 60 * s, 0);
    const perch::pixel c{30 * s, 30 * s};
    const perch::pixel tips[3] = {{30 * s, 59 * s}, {10 * s, 10 * s}, {50 * s, 10 * s}};
    for (const auto& tip : tips) thick_line(mask, c, tip, r);
    u8image skeleton(60 * s, 60 * s, 0);
    for (const auto& tip : tips) {
      // Centreline up to a fork point short of the tip, then two prongs (the medial axis of a
      // round tip forks like this).
      const perch::pixel fork{tip.x + (c.x - tip.x) / 6, tip.y + (c.y - tip.y) / 6};
      thin_line(skeleton, c, fork);
      const int len = static_cast<int>(r);
      const int dx = tip.x == c.x ? 1 : 0;
      const int dy = tip.x == c.x ? 0 : 1;
      thin_line(skeleton, fork, {fork.x + (tip.x - fork.x) / 2 + dx * len / 2,
                                 fork.y + (tip.y - fork.y) / 2 + dy * len / 2});
      thin_line(skeleton, fork, {fork.x + (tip.x - fork.x) / 2 - dx * len / 2,
                                 fork.y + (tip.y - fork.y) / 2 - dy * len / 2});
    }
    const u32image dist2 = brute_edt(mask);
    perch::workspace ws;
    auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(g);
    CHECK(g->branch_count() > 3);
    REQUIRE(perch::prune_skeleton_graph(*g, 1.0f, ws));
    const counts n = count_nodes(*g);
    CHECK(n.junctions == 1);
    CHECK(n.ends == 3);
    CHECK(g->branch_count() == 3);
    check_handshake(*g);
  }
}

TEST_CASE("prune: thick X with forked tips -> 1 junction cluster, 4 branches") {
  u8image mask(80, 80, 0);
  const perch::pixel a{8, 8}, b{71, 71}, c{71, 8}, d{8, 71};
  thick_line(mask, a, b, 5.0f);
  thick_line(mask, c, d, 5.0f);
  u8image skeleton(80, 80, 0);
  const perch::pixel centre{40, 40};
  for (const perch::pixel tip : {a, b, c, d}) {
    const perch::pixel fork{tip.x + (centre.x - tip.x) / 8, tip.y + (centre.y - tip.y) / 8};
    thin_line(skeleton, centre, fork);
    const int sx = tip.x < centre.x ? -1 : 1, sy = tip.y < centre.y ? -1 : 1;
    thin_line(skeleton, fork, {fork.x + 4 * sx, fork.y});
    thin_line(skeleton, fork, {fork.x, fork.y + 4 * sy});
  }
  const u32image dist2 = brute_edt(mask);
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  CHECK(g->branch_count() == 12);
  auto report = perch::prune_skeleton_graph(*g, 1.0f, ws);
  REQUIRE(report);
  const counts n = count_nodes(*g);
  CHECK(n.junctions == 1);
  CHECK(n.ends == 4);
  CHECK(g->branch_count() == 4);
  check_handshake(*g);
}

TEST_CASE("prune: options and scale are validated; the graph is left alone") {
  t_shape t;
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(t.skeleton), cview(t.dist2), ws);
  REQUIRE(g);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const prune_options o :
       {prune_options{.alpha = nan}, prune_options{.alpha = 1.5f},
        prune_options{.weight_threshold = -1.0f}, prune_options{.max_length_mm = nan},
        prune_options{.tip_spur_factor = -0.1f},
        prune_options{.tip_spur_px = std::numeric_limits<float>::infinity()}}) {
    auto r = perch::prune_skeleton_graph(*g, 1.0f, ws, o);
    REQUIRE(!r);
    CHECK(r.error().code == perch::errc::invalid_parameter);
  }
  auto inverted = perch::prune_skeleton_graph(
      *g, 1.0f, ws, prune_options{.diameter_min_mm = 50.0f, .diameter_max_mm = 40.0f});
  REQUIRE(!inverted);
  CHECK(inverted.error().code == perch::errc::range_inverted);
  for (const float scale : {0.0f, -1.0f, nan}) {
    auto r = perch::prune_skeleton_graph(*g, scale, ws);
    REQUIRE(!r);
    CHECK(r.error().code == perch::errc::invalid_parameter);
    CHECK(!perch::weigh_skeleton_graph(*g, scale));
  }
  CHECK(g->branch_count() == 3);
}

TEST_CASE("prune: random skeletons keep the handshake, every component and its trunk") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 10 + static_cast<int>(rng() % 40), h = 10 + static_cast<int>(rng() % 40);
    u8image skeleton(w, h, 0);
    const int walks = 1 + static_cast<int>(rng() % 5);
    for (int k = 0; k < walks; ++k) {
      int x = static_cast<int>(rng() % static_cast<unsigned>(w));
      int y = static_cast<int>(rng() % static_cast<unsigned>(h));
      int dir = static_cast<int>(rng() % 8);
      const int steps = 5 + static_cast<int>(rng() % 80);
      for (int i = 0; i < steps; ++i) {
        skeleton(x, y) = 1;
        if (rng() % 3 == 0) dir = (dir + (rng() % 2 == 0 ? 1 : 7)) % 8;
        x = std::clamp(x + perch::neighbours8[dir].x, 0, w - 1);
        y = std::clamp(y + perch::neighbours8[dir].y, 0, h - 1);
      }
    }
    u32image dist2(w, h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) dist2(x, y) = static_cast<std::uint32_t>(1 + rng() % 30);
    perch::workspace ws;
    auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(g);
    std::size_t pixels = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) pixels += skeleton(x, y) != 0 ? 1u : 0u;
    auto report = perch::prune_skeleton_graph(*g, 0.5f + static_cast<float>(rng() % 10), ws);
    REQUIRE(report);
    check_handshake(*g);
    std::vector<int> nodes_in(static_cast<std::size_t>(g->component_count()), 0);
    g->for_each_node([&](const perch::skeleton_node& n) { ++nodes_in[static_cast<std::size_t>(n.component)]; });
    for (std::int32_t c = 0; c < g->component_count(); ++c) {
      CHECK(nodes_in[static_cast<std::size_t>(c)] > 0);
      CHECK(g->contains_node(g->trunk(c)));
    }
    // Merged polylines: skeleton pixels, each at most once, within the pool.
    std::vector<int> seen(static_cast<std::size_t>(w * h), 0);
    std::size_t total = 0;
    g->for_each_branch([&](const perch::skeleton_branch& b) {
      total += b.points.size();
      for (const perch::pixel p : b.points) {
        CHECK(skeleton(p.x, p.y) != 0);
        CHECK(++seen[static_cast<std::size_t>(p.y * w + p.x)] == 1);
      }
      float arc = 0;
      for (std::size_t i = 1; i < b.points.size(); ++i) {
        const float dx = static_cast<float>(b.points[i].x - b.points[i - 1].x);
        const float dy = static_cast<float>(b.points[i].y - b.points[i - 1].y);
        arc += std::sqrt(dx * dx + dy * dy);
      }
      CHECK(b.length_px >= arc - 1e-3f);
    });
    CHECK(total <= pixels);
    // Pruning again changes nothing more than a fixed point allows.
    auto again = perch::prune_skeleton_graph(*g, 1.0f, ws, prune_options{.max_length_mm = 0.0f,
                                                                          .tip_spur_factor = 0.0f,
                                                                          .tip_spur_px = 0.0f});
    REQUIRE(again);
    CHECK(again->nodes_merged == 0);
    CHECK(again->branches_after == again->branches_before);
  }
}

TEST_CASE("prune: no allocation after warm-up") {
  u8image mask(70, 25, 0);
  for (int y = 7; y <= 17; ++y)
    for (int x = 0; x < 70; ++x) mask(x, y) = 1;
  u8image skeleton(70, 25, 0);
  thin_line(skeleton, {3, 12}, {66, 12});
  for (int x = 7; x <= 62; x += 5) skeleton(x, 11) = skeleton(x, 10) = 1;
  const u32image dist2 = brute_edt(mask);
  perch::workspace ws;
  for (int round = 0; round < 2; ++round) {
    ws.reset();
    perch::test::allocation_scope scope;
    auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(g);
    auto report = perch::prune_skeleton_graph(*g, 1.0f, ws);
    REQUIRE(report);
    CHECK(g->branch_count() == 1);
    if (round == 1) CHECK(scope.count() == 0);
  }
}

TEST_CASE("prune: a light leaf that runs out of the image is a limb cut by the frame, not weak") {
  // A thick limb along row 9 and a thin stub from it up to row 0: light (out of the diameter
  // range, short) and weak by eq. 1, unless row 0 is the image's top edge.
  u8image skeleton(30, 12, 0);
  u32image dist2(30, 12, 0);
  for (int x = 0; x < 30; ++x) {
    skeleton(x, 9) = 1;
    dist2(x, 9) = 9;  // 5 px wide: 40 mm at 8 mm/px
  }
  for (int y = 0; y < 9; ++y) {
    skeleton(14, y) = 1;
    dist2(14, y) = 1;  // 1 px wide: 8 mm
  }
  const prune_options options{.max_length_mm = 100.0f};
  for (const bool top_is_edge : {false, true}) {
    CAPTURE(top_is_edge);
    perch::workspace ws;
    auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(g);
    REQUIRE(g->branch_count() == 3);
    // The image's extent in the graph's coordinates: a larger frame all round, or one whose
    // top edge is row 0.
    const perch::pixel_box image{-10, top_is_edge ? 0 : -10, 40, 40};
    auto report = perch::prune_skeleton_graph(*g, 8.0f, ws, options, image);
    REQUIRE(report);
    CHECK(report->weak_leaves_removed == (top_is_edge ? 0u : 1u));
    CHECK(report->cut_leaves_kept == (top_is_edge ? 1u : 0u));
    CHECK(g->branch_count() == (top_is_edge ? 3u : 1u));
    check_handshake(*g);
  }
}
