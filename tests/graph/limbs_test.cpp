// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/limbs.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace {

/// A hand-drawn skeleton with its squared distance map: lines of given radius.
struct drawn_skeleton {
  perch::image<std::uint8_t> skeleton;
  perch::image<std::uint32_t> dist2;
  drawn_skeleton(int w, int h) : skeleton(w, h, 0), dist2(w, h, 0) {}
  void line(int x0, int y0, int x1, int y1, std::uint32_t radius) {
    const int steps = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
    for (int i = 0; i <= steps; ++i) {
      const int x = x0 + (steps == 0 ? 0 : (x1 - x0) * i / steps);
      const int y = y0 + (steps == 0 ? 0 : (y1 - y0) * i / steps);
      skeleton(x, y) = 1;
      if (dist2(x, y) < radius * radius) dist2(x, y) = radius * radius;
    }
  }
};

struct traced {
  perch::workspace ws;
  perch::skeleton_graph graph;
  std::vector<std::int32_t> next;
  std::span<const perch::skeleton_limb> limbs;
};

/// Builds the graph of `d`, its continuations and its limbs.
void trace(const drawn_skeleton& d, traced& t, const perch::limb_options& options = {},
           float twig_radius_px = 0) {
  auto g = perch::build_skeleton_graph(
      perch::image_view<const std::uint8_t>(d.skeleton.data(), d.skeleton.width(), d.skeleton.height()),
      perch::image_view<const std::uint32_t>(d.dist2.data(), d.dist2.width(), d.dist2.height()), t.ws);
  REQUIRE(g);
  t.graph = std::move(*g);
  t.next.assign(2 * static_cast<std::size_t>(t.graph.topology().edge_id_end()), 0);
  perch::limb_continuations(t.graph, perch::edge_continuations(t.next), options, twig_radius_px);
  auto limbs = perch::trace_limbs(t.graph, perch::edge_continuations(t.next), t.ws);
  REQUIRE(limbs);
  t.limbs = *limbs;
}

/// The limb with the most points.
const perch::skeleton_limb& longest(const traced& t) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < t.limbs.size(); ++i)
    if (t.limbs[i].points.size() > t.limbs[best].points.size()) best = i;
  return t.limbs[best];
}

}  // namespace

TEST_CASE("limbs: a limb runs on through the junction where a side twig leaves") {
  drawn_skeleton d(120, 40);
  d.line(0, 30, 119, 30, 8);   // the limb, 15-16 px thick
  d.line(60, 29, 60, 0, 1);    // a twig leaving it upward, ending in a tip
  traced t;
  trace(d, t);
  REQUIRE(t.graph.branch_count() == 3);
  REQUIRE(t.limbs.size() == 2);  // the limb (two edges) and the twig
  const perch::skeleton_limb& limb = longest(t);
  // Every point of the limb's row, in order, the junction's node pixel included.
  REQUIRE(limb.points.size() == 120);
  const int step = limb.points.front().x == 0 ? 1 : -1;
  for (std::size_t i = 0; i < limb.points.size(); ++i) {
    CHECK(limb.points[i].y == 30);
    CHECK(limb.points[i].x == limb.points.front().x + step * static_cast<int>(i));
    CHECK(limb.radius_px[i] == 8.0f);
  }
  // Its ends face its two tips; the edge under each point is one of the two limb edges.
  CHECK(perch::edge_of_end(limb.first_end) != perch::edge_of_end(limb.last_end));
  CHECK(t.next[limb.first_end] == -1);
  CHECK(t.next[limb.last_end] == -1);
  for (const perch::edge_id e : limb.edge_at)
    CHECK((e == perch::edge_of_end(limb.first_end) ||
           e == perch::edge_of_end(limb.last_end)));
  // The continuation is symmetric.
  for (std::size_t end = 0; end < t.next.size(); ++end)
    if (t.next[end] >= 0) CHECK(t.next[static_cast<std::size_t>(t.next[end])] == static_cast<std::int32_t>(end));
}

TEST_CASE("limbs: a side limb, a bend, or a thin edge to another junction ends the limb") {
  const auto limbs_of = [](const drawn_skeleton& d, const perch::limb_options& options = {},
                           float twig_radius_px = 0) {
    traced t;
    trace(d, t, options, twig_radius_px);
    CHECK(t.limbs.size() <= t.graph.branch_count());
    return t.limbs.size();
  };
  drawn_skeleton twig(120, 40);  // the twig of the case above
  twig.line(0, 30, 119, 30, 8);
  twig.line(60, 29, 60, 0, 1);
  perch::limb_options never;
  never.side_area_share_max = 0.0f;
  CHECK(limbs_of(twig) == 2);
  CHECK(limbs_of(twig, never) == 3);

  drawn_skeleton side(120, 40);  // a side limb half as thick: a quarter of the cross-section
  side.line(0, 30, 119, 30, 8);
  side.line(60, 29, 60, 0, 4);
  CHECK(limbs_of(side) == 3);
  // ... unless it is known to be a twig by the platform's measure (a radius under
  // `twig_radius_px`): compliant, no obstacle, and the limb runs on past it.
  CHECK(limbs_of(side, {}, 4.5f) == 2);
  CHECK(limbs_of(side, {}, 4.0f) == 3);

  drawn_skeleton bend(120, 120);  // a twig where the limb turns by 90°
  bend.line(0, 60, 60, 60, 8);
  bend.line(60, 61, 60, 119, 8);
  bend.line(61, 59, 119, 0, 1);
  CHECK(limbs_of(bend) == 3);

  drawn_skeleton bridge(120, 60);  // a thin edge that reaches another limb, not a tip
  bridge.line(0, 50, 119, 50, 8);
  bridge.line(60, 49, 60, 11, 1);
  bridge.line(0, 10, 119, 10, 8);
  CHECK(limbs_of(bridge) == 5);
}

TEST_CASE("limbs: the axis of an edge leaving a junction is its straight chord, or none") {
  drawn_skeleton d(80, 40);
  d.line(0, 10, 79, 10, 2);   // a line with two edges leaving it downward:
  d.line(20, 11, 20, 39, 2);  // straight,
  d.line(60, 11, 60, 16, 2);  // and bent by 90° after 6 px (the medial axis of a cut limb)
  d.line(61, 16, 79, 16, 2);
  traced t;
  trace(d, t);
  int straight = 0, bent = 0;
  t.graph.for_each_node([&](const perch::skeleton_node& node) {
    if (node.kind != perch::node_kind::junction) return;
    for (const perch::incidence in : t.graph.topology().incidences(node.id)) {
      const perch::skeleton_branch edge = t.graph.branch(in.edge);
      const perch::detail::leaving_axis axis = perch::detail::leaving_axis_of(edge, in.direction, node);
      const perch::pixel far = in.direction == perch::traversal::forward ? edge.points.back()
                                                                         : edge.points.front();
      if (far.y == 39) {
        ++straight;
        CHECK(axis.valid);
        CHECK(axis.direction.y() == doctest::Approx(1.0));
        CHECK(axis.radius_px == 2.0f);
      } else if (far.y == 16) {
        ++bent;
        CHECK_FALSE(axis.valid);
      }
    }
  });
  CHECK(straight == 1);
  CHECK(bent == 1);
}

TEST_CASE("limbs: options are validated") {
  CHECK(perch::limb_options{}.validate());
  perch::limb_options bad;
  bad.side_area_share_max = std::nanf("");
  CHECK(bad.validate().error().code == perch::errc::invalid_parameter);
  bad = {};
  bad.max_turn_deg = -1.0f;
  CHECK_FALSE(bad.validate());
  bad = {};
  bad.through_thickness_ratio_min = 2.0f;
  CHECK_FALSE(bad.validate());
}
