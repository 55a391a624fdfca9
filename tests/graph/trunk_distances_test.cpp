// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/trunk_distances.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/graph/prune.hpp"
#include "perch/graph/skeleton_graph.hpp"
#include "support/ascii_art.hpp"

namespace {

/// doctest::Approx of a float without an implicit promotion (-Wdouble-promotion).
doctest::Approx approx(float v) { return doctest::Approx(static_cast<double>(v)); }
perch::image_view<const std::uint32_t> cview(const perch::image<std::uint32_t>& d) {
  return {d.data(), d.width(), d.height()};
}
perch::image_view<const std::uint8_t> cview(const perch::image<std::uint8_t>& d) {
  return {d.data(), d.width(), d.height()};
}
}  // namespace

TEST_CASE("distances_to_trunk: along the branches from each component's trunk") {
  // A T standing on its stem (the trunk: lowest end) and a separate ring.
  const auto skeleton = perch::support::mask_from_ascii(R"(
    #######.....###.
    ...#.......#...#
    ...#.......#...#
    ...#........###.
    ...#............
  )");
  perch::image<std::uint32_t> dist2(skeleton.width(), skeleton.height(), 4);
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  REQUIRE(g->component_count() == 2);
  std::vector<float> d(g->node_capacity());
  REQUIRE(perch::distances_to_trunk(*g, d, ws));
  const perch::node_id trunk = g->trunk(0);
  CHECK(g->node(trunk).position == perch::pixel{3, 4});
  g->for_each_node([&](const perch::skeleton_node& n) {
    const float dn = d[static_cast<std::size_t>(n.id)];
    if (n.component == 1) {
      CHECK(dn == 0.0f);  // the ring's loop node is its own trunk
    } else if (n.position == perch::pixel{3, 4}) {
      CHECK(dn == 0.0f);
    } else if (n.kind == perch::node_kind::junction) {
      CHECK(dn == approx(4.0f));
    } else {
      CHECK(dn == approx(7.0f));  // 4 up the stem, 3 along an arm
    }
  });
  // Orientation: every branch's origin (the end nearer the trunk) is toward the stem.
  g->for_each_branch([&](const perch::skeleton_branch& b) {
    if (b.component != 0) return;
    const float from = d[static_cast<std::size_t>(b.from)];
    const float to = d[static_cast<std::size_t>(b.to)];
    CHECK(from != to);
  });
}

TEST_CASE("distances_to_trunk: removed nodes are infinite; a short output is an error") {
  const auto skeleton = perch::support::mask_from_ascii(R"(
    #######
    ...#...
    ...#...
    ...#...
    ...#...
    ...#...
  )");
  perch::image<std::uint32_t> dist2(skeleton.width(), skeleton.height(), 4);
  perch::workspace ws;
  auto g = perch::build_skeleton_graph(cview(skeleton), cview(dist2), ws);
  REQUIRE(g);
  REQUIRE(perch::prune_skeleton_graph(*g, 1.0f, ws));
  CHECK(g->branch_count() == 1);  // both 3-px arms are tip spurs at r = 2
  std::vector<float> d(g->node_capacity());
  perch::test::allocation_scope scope;
  REQUIRE(perch::distances_to_trunk(*g, d, ws));
  CHECK(scope.count() == 0);
  int finite = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(g->topology().node_id_end()); ++i) {
    const bool alive = g->contains_node(static_cast<perch::node_id>(i));
    CHECK(std::isfinite(d[i]) == alive);
    finite += alive ? 1 : 0;
  }
  CHECK(finite == 2);
  std::vector<float> small(1);
  auto r = perch::distances_to_trunk(*g, small, ws);
  REQUIRE(!r);
  CHECK(r.error().code == perch::errc::size_mismatch);
}
