// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/skeleton_graph.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/graph/pixel_kinds.hpp"
#include "support/ascii_art.hpp"

using perch::branch_type;
using perch::node_kind;
using perch::skeleton_graph;
using perch::support::mask_from_ascii;

namespace {

/// doctest::Approx of a float without an implicit promotion (-Wdouble-promotion).
doctest::Approx approx(float v) { return doctest::Approx(static_cast<double>(v)); }

constexpr float sqrt2 = 1.41421356f;

perch::image_view<const std::uint32_t> cview(const perch::image<std::uint32_t>& d) {
  return {d.data(), d.width(), d.height()};
}
perch::image_view<const std::uint8_t> cview(const perch::image<std::uint8_t>& d) {
  return {d.data(), d.width(), d.height()};
}

/// A skeleton drawn as ASCII art with a constant squared radius, and its graph.
struct drawn {
  perch::image<std::uint8_t> skeleton;
  perch::image<std::uint32_t> dist2;
  perch::workspace ws;
  skeleton_graph graph;

  explicit drawn(std::string_view art, std::uint32_t d2 = 4)
      : skeleton(mask_from_ascii(art)), dist2(skeleton.width(), skeleton.height(), d2) {
    auto built = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(built);
    graph = std::move(*built);
  }
  [[nodiscard]] int nodes_of(node_kind k) const {
    int count = 0;
    graph.for_each_node([&](const perch::skeleton_node& n) { count += n.kind == k ? 1 : 0; });
    return count;
  }
  [[nodiscard]] int branches_of(branch_type t) const {
    int count = 0;
    graph.for_each_branch([&](const perch::skeleton_branch& b) { count += b.type == t ? 1 : 0; });
    return count;
  }
  [[nodiscard]] std::vector<float> lengths() const {
    std::vector<float> out;
    graph.for_each_branch([&](const perch::skeleton_branch& b) { out.push_back(b.length_px); });
    std::sort(out.begin(), out.end());
    return out;
  }
};

/// Checks what must hold for any freshly built graph of `skeleton`:
/// every skeleton pixel lies in exactly one branch polyline or is a junction / isolated pixel
/// owned by a node; polylines are 8-connected walks; Σ degree = 2·edges; lengths are the
/// polyline's arc length plus at most one attachment step at each end.
void check_invariants(const skeleton_graph& g, const perch::image<std::uint8_t>& skeleton) {
  const int w = skeleton.width();
  const int h = skeleton.height();
  std::vector<int> seen(static_cast<std::size_t>(w * h), 0);
  std::size_t pixels = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) pixels += skeleton(x, y) != 0 ? 1u : 0u;
  CHECK(g.skeleton_pixels() == pixels);
  std::size_t in_branches = 0;
  std::size_t in_nodes = 0;
  long long degree_sum = 0;
  g.for_each_branch([&](const perch::skeleton_branch& b) {
    REQUIRE(b.points.size() == b.radius_px.size());
    REQUIRE(!b.points.empty());
    in_branches += b.points.size();
    float arc = 0;
    for (std::size_t i = 0; i < b.points.size(); ++i) {
      const perch::pixel p = b.points[i];
      REQUIRE(skeleton.view().contains(p.x, p.y));
      CHECK(skeleton(p.x, p.y) != 0);
      CHECK(perch::skeleton_pixel_kind(skeleton.view(), p.x, p.y) != perch::pixel_kind::junction);
      ++seen[static_cast<std::size_t>(p.y * w + p.x)];
      if (i > 0) {
        const int dx = std::abs(p.x - b.points[i - 1].x);
        const int dy = std::abs(p.y - b.points[i - 1].y);
        CHECK(std::max(dx, dy) == 1);
        arc += dx + dy == 2 ? sqrt2 : 1.0f;
      }
    }
    CHECK(b.length_px >= arc - 1e-3f);
    CHECK(b.length_px <= arc + 2 * sqrt2 + 1e-3f);
    CHECK(b.component >= 0);
    CHECK(b.component < g.component_count());
    CHECK(g.node(b.from).component == b.component);
    CHECK(g.node(b.to).component == b.component);
  });
  g.for_each_node([&](const perch::skeleton_node& n) {
    in_nodes += n.pixel_count;
    degree_sum += n.degree;
    CHECK(skeleton(n.position.x, n.position.y) != 0);
  });
  CHECK(in_branches + in_nodes == pixels);
  CHECK(degree_sum == 2 * static_cast<long long>(g.branch_count()));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int s = seen[static_cast<std::size_t>(y * w + x)];
      CHECK(s <= 1);
      if (skeleton(x, y) != 0 && s == 0) {
        const auto k = perch::skeleton_pixel_kind(skeleton.view(), x, y);
        CHECK((k == perch::pixel_kind::junction || k == perch::pixel_kind::isolated));
      }
    }
  for (std::int32_t c = 0; c < g.component_count(); ++c) {
    const perch::node_id t = g.trunk(c);
    REQUIRE(g.contains_node(t));
    CHECK(g.node(t).component == c);
    CHECK(g.node(t).trunk);
  }
}

/// Number of 8-connected components of a mask (slow flood fill).
int count_components(const perch::image<std::uint8_t>& m) {
  const int w = m.width(), h = m.height();
  std::vector<int> label(static_cast<std::size_t>(w * h), 0);
  int count = 0;
  std::vector<std::pair<int, int>> stack;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (m(x, y) == 0 || label[static_cast<std::size_t>(y * w + x)] != 0) continue;
      ++count;
      stack.push_back({x, y});
      label[static_cast<std::size_t>(y * w + x)] = count;
      while (!stack.empty()) {
        auto [px, py] = stack.back();
        stack.pop_back();
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = px + dx, qy = py + dy;
            if (qx < 0 || qy < 0 || qx >= w || qy >= h || m(qx, qy) == 0) continue;
            int& l = label[static_cast<std::size_t>(qy * w + qx)];
            if (l == 0) {
              l = count;
              stack.push_back({qx, qy});
            }
          }
      }
    }
  return count;
}

}  // namespace

TEST_CASE("skeleton graph: a straight line is one tip-tip branch of exact length") {
  drawn d("##########");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.graph.node_count() == 2);
  CHECK(d.graph.branch_count() == 1);
  CHECK(d.nodes_of(node_kind::end) == 2);
  CHECK(d.branches_of(branch_type::tip_tip) == 1);
  const auto b = d.graph.branch(0);
  CHECK(b.points.size() == 10);
  CHECK(b.length_px == approx(9.0f));
  CHECK(b.mean_diameter_px == approx(3.0f));  // r = 2: 2r - 1
  CHECK(b.points.front() == perch::pixel{0, 0});
  CHECK(b.points.back() == perch::pixel{9, 0});
}

TEST_CASE("skeleton graph: a diagonal is 5·sqrt2 long, a vertical line 6, not doubled") {
  drawn diag(R"(
    #.....
    .#....
    ..#...
    ...#..
    ....#.
    .....#
  )");
  check_invariants(diag.graph, diag.skeleton);
  REQUIRE(diag.graph.branch_count() == 1);
  CHECK(diag.graph.branch(0).length_px == approx(5 * sqrt2));
  drawn vertical("#\n#\n#\n#\n#\n#\n#");
  REQUIRE(vertical.graph.branch_count() == 1);
  CHECK(vertical.graph.branch(0).length_px == approx(6.0f));
}

TEST_CASE("skeleton graph: a staircase is one branch through every pixel") {
  drawn d(R"(
    #.....
    ##....
    .##...
    ..##..
    ...##.
    ....##
  )");
  check_invariants(d.graph, d.skeleton);
  REQUIRE(d.graph.branch_count() == 1);
  CHECK(d.graph.branch(0).points.size() == 11);
  CHECK(d.graph.branch(0).length_px == approx(10.0f));
}

TEST_CASE("skeleton graph: an L is one branch") {
  drawn d(R"(
    #....
    #....
    #####
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.graph.branch_count() == 1);
  CHECK(d.graph.branch(0).length_px == approx(6.0f));
}

TEST_CASE("skeleton graph: T -> 1 junction, 3 ends, 3 tip-junction branches") {
  drawn d(R"(
    #######
    ...#...
    ...#...
    ...#...
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.nodes_of(node_kind::junction) == 1);
  CHECK(d.nodes_of(node_kind::end) == 3);
  CHECK(d.branches_of(branch_type::tip_junction) == 3);
  // Each arm: 3 pixels, 3 steps including the one into the junction pixel.
  CHECK(d.lengths() == std::vector<float>{3.0f, 3.0f, 3.0f});
}

TEST_CASE("skeleton graph: Y -> 1 junction, 3 ends, 3 branches") {
  drawn d(R"(
    #.....#
    .#...#.
    ..#.#..
    ...#...
    ...#...
    ...#...
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.graph.node_count() == 4);
  CHECK(d.nodes_of(node_kind::junction) == 1);
  CHECK(d.nodes_of(node_kind::end) == 3);
  CHECK(d.graph.branch_count() == 3);
  const auto lengths = d.lengths();
  CHECK(lengths[0] == approx(2.0f));  // stem: 2 pixels + the step into the junction
  CHECK(lengths[1] == approx(3 * sqrt2));
  CHECK(lengths[2] == approx(3 * sqrt2));
}

TEST_CASE("skeleton graph: a thin X and a + give 1 junction with 4 branches") {
  drawn x(R"(
    #.....#
    .#...#.
    ..#.#..
    ...#...
    ..#.#..
    .#...#.
    #.....#
  )");
  check_invariants(x.graph, x.skeleton);
  CHECK(x.nodes_of(node_kind::junction) == 1);
  CHECK(x.graph.branch_count() == 4);
  x.graph.for_each_node([](const perch::skeleton_node& n) {
    CHECK(n.degree == (n.kind == node_kind::junction ? 4 : 1));
  });
  drawn plus(R"(
    ...#...
    ...#...
    ...#...
    #######
    ...#...
    ...#...
    ...#...
  )");
  check_invariants(plus.graph, plus.skeleton);
  CHECK(plus.nodes_of(node_kind::junction) == 1);
  CHECK(plus.nodes_of(node_kind::end) == 4);
  CHECK(plus.graph.branch_count() == 4);
  CHECK(plus.lengths() == std::vector<float>{3.0f, 3.0f, 3.0f, 3.0f});
}

TEST_CASE("skeleton graph: a ring is one loop node with one cycle edge") {
  drawn d(R"(
    ..###..
    .#...#.
    #.....#
    #.....#
    #.....#
    .#...#.
    ..###..
  )");
  check_invariants(d.graph, d.skeleton);
  REQUIRE(d.graph.node_count() == 1);
  REQUIRE(d.graph.branch_count() == 1);
  const auto n = d.graph.node(d.graph.branch(0).from);
  CHECK(n.kind == node_kind::loop);
  CHECK(n.degree == 2);
  CHECK(n.position == perch::pixel{2, 0});  // first raster pixel
  const auto b = d.graph.branch(0);
  CHECK(b.type == branch_type::cycle);
  CHECK(b.from == b.to);
  CHECK(b.points.size() == 16);
  // 8 straight steps and 8 diagonal ones, the closing step included.
  CHECK(b.length_px == approx(8.0f + 8.0f * sqrt2));
  CHECK(d.graph.trunk(0) == b.from);
}

TEST_CASE("skeleton graph: two loops sharing a junction") {
  drawn d(R"(
    .###...###.
    #...#.#...#
    #....#....#
    #...#.#...#
    .###...###.
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.nodes_of(node_kind::junction) == 1);
  CHECK(d.graph.node_count() == 1);
  CHECK(d.branches_of(branch_type::cycle) == 2);
  d.graph.for_each_node([](const perch::skeleton_node& n) { CHECK(n.degree == 4); });
}

TEST_CASE("skeleton graph: a 2x2 block is one junction cluster of 4 pixels") {
  drawn block(R"(
    #.....
    .##...
    .##...
    ...#..
    ....#.
  )");
  check_invariants(block.graph, block.skeleton);
  CHECK(block.graph.node_count() == 3);
  CHECK(block.graph.branch_count() == 2);
  block.graph.for_each_node([](const perch::skeleton_node& n) {
    if (n.kind != node_kind::end) CHECK(n.pixel_count == 4);
  });
  drawn d(R"(
    #......#
    .#....#.
    ..####..
    ..####..
    .#....#.
    #......#
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.nodes_of(node_kind::end) == 4);
  // The two 2x2 blocks touch, so all 8 junction pixels form one cluster.
  REQUIRE(d.nodes_of(node_kind::junction) == 1);
  int big = 0;
  d.graph.for_each_node([&](const perch::skeleton_node& n) {
    if (n.kind == node_kind::junction) big += static_cast<int>(n.pixel_count);
  });
  CHECK(big == 8);
}

TEST_CASE("skeleton graph: one pixel, isolated pixels and two components") {
  drawn one("#");
  check_invariants(one.graph, one.skeleton);
  CHECK(one.graph.node_count() == 1);
  CHECK(one.graph.branch_count() == 0);
  CHECK(one.graph.node(0).kind == node_kind::isolated);
  CHECK(one.graph.node(0).pixel_count == 1);
  CHECK(one.graph.component_count() == 1);

  drawn two(R"(
    ......#
    ####..#
    ......#
    .#.....
  )");
  check_invariants(two.graph, two.skeleton);
  CHECK(two.graph.component_count() == 3);
  CHECK(two.graph.branch_count() == 2);
  // Components in raster order of their first pixel: the vertical line (6,0) first.
  two.graph.for_each_branch([&](const perch::skeleton_branch& b) {
    const bool vertical = b.points.front().x == 6;
    CHECK(b.component == (vertical ? 0 : 1));
  });
  two.graph.for_each_node([&](const perch::skeleton_node& n) {
    if (n.kind == node_kind::isolated) CHECK(n.component == 2);
  });
}

TEST_CASE("skeleton graph: skeletons touching every border") {
  drawn d(R"(
    ########
    #......#
    #......#
    ########
  )");
  check_invariants(d.graph, d.skeleton);
  CHECK(d.graph.branch_count() == 1);
  CHECK(d.branches_of(branch_type::cycle) == 1);
  CHECK(d.graph.branch(0).length_px == approx(20.0f));
}

TEST_CASE("skeleton graph: the trunk is the lowest wide end, not the thin tip at the border") {
  // A trunk rising from the bottom edge with a wide radius, a thin twig reaching lower on the
  // left. The twig's end is lower but its branch is thin: the trunk's end wins.
  const auto skeleton = mask_from_ascii(R"(
    ....#....
    ....#....
    ....#....
    ...###...
    ..#.#.#..
    .#..#..#.
    #...#....
    ....#....
  )");
  perch::image<std::uint32_t> dist2(skeleton.width(), skeleton.height(), 1);
  for (int y = 0; y < skeleton.height(); ++y) dist2(4, y) = 100;  // the trunk: r = 10
  dist2(4, 7) = 1;                                                // thin at the border pixel
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  const auto trunk = g->node(g->trunk(0));
  CHECK(trunk.position == perch::pixel{4, 7});
  CHECK(trunk.kind == node_kind::end);

  // Two equally wide ends at the same height: the left one.
  const auto u = mask_from_ascii(R"(
    #...#
    #...#
    #####
  )");
  perch::image<std::uint32_t> flat(u.width(), u.height(), 4);
  auto gu = perch::build_skeleton_graph(cview(u), cview(flat), ws);
  REQUIRE(gu);
  CHECK(gu->node(gu->trunk(0)).position == perch::pixel{0, 0});
}

TEST_CASE("skeleton graph: capacity and view errors") {
  const auto skeleton = mask_from_ascii(R"(
    #######
    ...#...
    ...#...
  )");
  perch::image<std::uint32_t> dist2(skeleton.width(), skeleton.height(), 4);
  perch::workspace ws;
  auto few_nodes = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws,
                                               perch::graph_options{.max_nodes = 2});
  REQUIRE(!few_nodes);
  CHECK(few_nodes.error().code == perch::errc::capacity_exceeded);
  auto few_branches = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws,
                                                  perch::graph_options{.max_branches = 2});
  REQUIRE(!few_branches);
  CHECK(few_branches.error().code == perch::errc::capacity_exceeded);
  perch::image<std::uint32_t> other(3, 3, 0);
  auto mismatch = perch::build_skeleton_graph(cview(skeleton), cview(other), ws);
  REQUIRE(!mismatch);
  CHECK(mismatch.error().code == perch::errc::size_mismatch);
  auto empty = perch::build_skeleton_graph(perch::image_view<const std::uint8_t>{}, cview(other), ws);
  REQUIRE(!empty);
  CHECK(empty.error().code == perch::errc::empty_image);
  // An all-zero skeleton is a valid, empty graph.
  perch::image<std::uint8_t> blank(5, 5, 0);
  perch::image<std::uint32_t> zero(5, 5, 0);
  auto none = perch::build_skeleton_graph(cview(blank), cview(zero), ws);
  REQUIRE(none);
  CHECK(none->node_count() == 0);
  CHECK(none->component_count() == 0);
}

TEST_CASE("skeleton graph: a borrowed workspace of the queried size suffices, and no "
          "allocation happens after warm-up") {
  const auto skeleton = mask_from_ascii(R"(
    #.....#....#
    .#...#....#.
    ..#.#....#..
    ...#....#...
    ...#...#....
    ...#####....
    ...#........
  )");
  perch::image<std::uint32_t> dist2(skeleton.width(), skeleton.height(), 9);
  std::size_t n = 0;
  for (int y = 0; y < skeleton.height(); ++y)
    for (int x = 0; x < skeleton.width(); ++x) n += skeleton(x, y) != 0 ? 1u : 0u;
  const std::size_t bytes =
      perch::skeleton_graph_workspace_bytes(skeleton.width(), skeleton.height(), n);
  std::vector<std::byte> buffer(bytes + perch::workspace::alignment);
  perch::workspace borrowed{std::span<std::byte>(buffer)};
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), borrowed);
  REQUIRE(g);
  CHECK(borrowed.high_water() <= bytes);

  perch::workspace ws;
  { auto warm = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws); REQUIRE(warm); }
  ws.reset();
  perch::test::allocation_scope scope;
  auto again = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(again);
  CHECK(scope.count() == 0);
}

TEST_CASE("skeleton graph: invariants on seeded random skeletons") {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 8 + static_cast<int>(rng() % 40);
    const int h = 8 + static_cast<int>(rng() % 40);
    perch::image<std::uint8_t> skeleton(w, h, 0);
    // Random 8-connected walks (thin curves that cross and touch) plus a few lone pixels.
    const int walks = 1 + static_cast<int>(rng() % 6);
    for (int k = 0; k < walks; ++k) {
      int x = static_cast<int>(rng() % static_cast<unsigned>(w));
      int y = static_cast<int>(rng() % static_cast<unsigned>(h));
      const int steps = 5 + static_cast<int>(rng() % 60);
      int dir = static_cast<int>(rng() % 8);
      for (int s = 0; s < steps; ++s) {
        skeleton(x, y) = 1;
        if (rng() % 4 == 0) dir = (dir + (rng() % 2 == 0 ? 1 : 7)) % 8;
        x = std::clamp(x + perch::neighbours8[dir].x, 0, w - 1);
        y = std::clamp(y + perch::neighbours8[dir].y, 0, h - 1);
      }
    }
    if (trial % 3 == 0)  // denser noise: blocks, blobs
      for (int k = 0; k < w * h / 10; ++k)
        skeleton(static_cast<int>(rng() % static_cast<unsigned>(w)),
                 static_cast<int>(rng() % static_cast<unsigned>(h))) = 1;
    perch::image<std::uint32_t> dist2(w, h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) dist2(x, y) = static_cast<std::uint32_t>(1 + rng() % 50);
    perch::workspace ws;
    auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    REQUIRE(g);
    check_invariants(*g, skeleton);
    CHECK(g->component_count() == count_components(skeleton));
  }
}

TEST_CASE("skeleton graph: scanning only the runs of a mask that contains the skeleton") {
  // find_perch hands the graph the runs of the mask a built-in skeletoniser thinned (the
  // skeleton lies inside it): scanning only them must give the same graph as scanning the view;
  // runs of an image of another size are ignored.
  std::mt19937 rng(20261126);
  auto fingerprint = [](const skeleton_graph& g) {
    std::vector<std::int64_t> out;
    g.for_each_node([&](const perch::skeleton_node& n) {
      out.insert(out.end(), {n.position.x, n.position.y, static_cast<std::int64_t>(n.kind),
                             n.degree, n.component, static_cast<std::int64_t>(n.pixel_count)});
    });
    g.for_each_branch([&](const perch::skeleton_branch& b) {
      out.insert(out.end(), {b.from, b.to, static_cast<std::int64_t>(b.type),
                             std::llround(1000.0 * static_cast<double>(b.length_px))});
      for (const perch::pixel p : b.points) out.insert(out.end(), {p.x, p.y});
    });
    return out;
  };
  int with_pixels = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 8 + static_cast<int>(rng() % 60);
    const int h = 8 + static_cast<int>(rng() % 40);
    perch::image<std::uint8_t> skeleton(w, h, 0), mask(w, h, 0);
    for (int k = 0; k < 1 + static_cast<int>(rng() % 5); ++k) {
      int x = static_cast<int>(rng() % static_cast<unsigned>(w));
      int y = static_cast<int>(rng() % static_cast<unsigned>(h));
      int dir = static_cast<int>(rng() % 8);
      for (int s = 0; s < 5 + static_cast<int>(rng() % 50); ++s) {
        skeleton(x, y) = 1;
        if (rng() % 4 == 0) dir = (dir + (rng() % 2 == 0 ? 1 : 7)) % 8;
        x = std::clamp(x + perch::neighbours8[dir].x, 0, w - 1);
        y = std::clamp(y + perch::neighbours8[dir].y, 0, h - 1);
      }
    }
    // The mask: the skeleton, some of its neighbours, and unrelated specks.
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (skeleton(x, y) != 0) {
          mask(x, y) = 1;
          if (x + 1 < w && rng() % 2 == 0) mask(x + 1, y) = 1;
          if (x > 0 && rng() % 3 == 0) mask(x - 1, y) = 1;
        } else if (rng() % 20 == 0) {
          mask(x, y) = 1;
        }
      }
    perch::image<std::uint32_t> dist2(w, h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) dist2(x, y) = static_cast<std::uint32_t>(1 + rng() % 50);
    perch::workspace ws;
    auto runs = perch::find_row_runs(cview(mask), ws, static_cast<std::size_t>(w * h));
    REQUIRE(runs);
    auto scanned = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
    auto listed = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws, {},
                                              *runs);
    REQUIRE(scanned);
    REQUIRE(listed);
    CHECK(listed->skeleton_pixels() == scanned->skeleton_pixels());
    CHECK(fingerprint(*listed) == fingerprint(*scanned));
    with_pixels += scanned->skeleton_pixels() > 0 ? 1 : 0;
    // Runs of a smaller image do not span the skeleton: scanned as without runs.
    perch::image<std::uint8_t> other(w - 1, h, 1);
    auto other_runs = perch::find_row_runs(cview(other), ws, static_cast<std::size_t>(w * h));
    REQUIRE(other_runs);
    auto ignored = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws, {},
                                               *other_runs);
    REQUIRE(ignored);
    CHECK(fingerprint(*ignored) == fingerprint(*scanned));
  }
  CHECK(with_pixels == 200);
}

TEST_CASE("count_set_pixels: equals a pixel-by-pixel count, over the whole view and inside runs") {
  std::mt19937 rng(11);
  perch::workspace ws;
  for (int round = 0; round < 200; ++round) {
    const int w = 1 + static_cast<int>(rng() % 150);
    const int h = 1 + static_cast<int>(rng() % 12);
    perch::image<std::uint8_t> big(w + 5, h + 2, 0xFF);  // ink around the sub-view must not count
    perch::image<std::uint8_t> inside(w, h, 0);          // the "mask": where the runs are
    std::size_t expected = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        inside(x, y) = rng() % 3 != 0 ? 1 : 0;
        const bool set = inside(x, y) != 0 && rng() % 4 == 0;  // sparse, as a skeleton
        big(x + 2, y + 1) = set ? static_cast<std::uint8_t>(1 + rng() % 255) : 0;
        expected += set ? 1 : 0;
      }
    const auto skeleton = perch::image_view<const std::uint8_t>(big.view().sub_view(2, 1, w, h));
    CHECK(perch::detail::count_set_pixels(skeleton, nullptr) == expected);
    ws.reset();
    const auto runs = perch::find_row_runs(cview(inside), ws, static_cast<std::size_t>(w * h));
    REQUIRE(runs);
    CHECK(perch::detail::count_set_pixels(skeleton, &*runs) == expected);
  }
}
