// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/adjacency_list.hpp"

#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "allocation_counter.hpp"

using perch::adjacency_list;
using perch::edge_id;
using perch::edge_part;
using perch::errc;
using perch::node_id;
using perch::traversal;

namespace {

struct city {
  int population = 0;
};
/// A road with its mile markers in stored order, so joins can check the walking direction.
struct road {
  int first_marker = 0;
  int last_marker = 0;
  int length = 0;
};
using road_map = adjacency_list<city, road>;

std::vector<node_id> neighbours_of(const road_map& g, node_id n) {
  std::vector<node_id> out;
  for (const node_id m : g.neighbours(n)) out.push_back(m);
  return out;
}

/// Joins two roads in walking order: the result's markers run from the walk's start to its end.
road join_roads(const edge_part<road>& a, const city&, const edge_part<road>& b) {
  const int start = a.direction == traversal::forward ? a.data.first_marker : a.data.last_marker;
  const int end = b.direction == traversal::forward ? b.data.last_marker : b.data.first_marker;
  return road{start, end, a.data.length + b.data.length};
}

}  // namespace

TEST_CASE("adjacency_list: add, degree, neighbours, incidences in attachment order") {
  perch::workspace ws;
  auto made = road_map::make(ws, 8, 8);
  REQUIRE(made);
  road_map& g = *made;
  const node_id a = *g.add_node({1});
  const node_id b = *g.add_node({2});
  const node_id c = *g.add_node({3});
  CHECK(a == 0);
  CHECK(b == 1);
  CHECK(c == 2);
  const edge_id ab = *g.add_edge(a, b, {0, 10, 10});
  const edge_id bc = *g.add_edge(b, c, {10, 30, 20});
  const edge_id loop = *g.add_edge(c, c, {0, 5, 5});
  const edge_id ab2 = *g.add_edge(b, a, {0, 7, 7});  // parallel, stored the other way
  CHECK(g.node_count() == 3);
  CHECK(g.edge_count() == 4);
  CHECK(g.degree(a) == 2);
  CHECK(g.degree(b) == 3);
  CHECK(g.degree(c) == 3);  // a self-loop counts twice
  CHECK(neighbours_of(g, b) == std::vector<node_id>{a, c, a});
  CHECK(neighbours_of(g, c) == std::vector<node_id>{b, c, c});
  std::vector<perch::incidence> at_a;
  for (const perch::incidence i : g.incidences(a)) at_a.push_back(i);
  REQUIRE(at_a.size() == 2);
  CHECK(at_a[0].edge == ab);
  CHECK(at_a[0].direction == traversal::forward);
  CHECK(at_a[1].edge == ab2);
  CHECK(at_a[1].direction == traversal::backward);
  CHECK(g.opposite(bc, b) == c);
  CHECK(g.opposite(loop, c) == c);
  CHECK(g.node(b).population == 2);
  CHECK(g.edge(bc).length == 20);
  // Handshake lemma.
  int sum = 0;
  g.for_each_node([&](node_id n) { sum += g.degree(n); });
  CHECK(sum == 2 * static_cast<int>(g.edge_count()));
}

TEST_CASE("adjacency_list: removal keeps ids stable and never reuses them") {
  perch::workspace ws;
  auto made = road_map::make(ws, 4, 4);
  REQUIRE(made);
  road_map& g = *made;
  const node_id a = *g.add_node();
  const node_id b = *g.add_node();
  const node_id c = *g.add_node();
  const edge_id ab = *g.add_edge(a, b);
  const edge_id bc = *g.add_edge(b, c);
  g.remove_edge(ab);
  CHECK(!g.contains_edge(ab));
  CHECK(g.contains_edge(bc));
  CHECK(g.degree(a) == 0);
  CHECK(g.degree(b) == 1);
  const edge_id ca = *g.add_edge(c, a);
  CHECK(ca == 2);  // the id of the removed edge is not reused
  g.remove_node(c);
  CHECK(!g.contains_node(c));
  CHECK(!g.contains_edge(bc));
  CHECK(!g.contains_edge(ca));
  CHECK(g.edge_count() == 0);
  CHECK(g.node_count() == 2);
  CHECK(g.node_id_end() == 3);
  std::vector<node_id> alive;
  g.for_each_node([&](node_id n) { alive.push_back(n); });
  CHECK(alive == std::vector<node_id>{a, b});
}

TEST_CASE("adjacency_list: merging a degree-2 node joins its edges in walking order") {
  perch::workspace ws;
  auto made = road_map::make(ws, 8, 8);
  REQUIRE(made);
  road_map& g = *made;
  const node_id a = *g.add_node();
  const node_id m = *g.add_node();
  const node_id b = *g.add_node();
  // a ← m stored backwards (m → a), m ← b stored backwards too (b → m).
  const edge_id e1 = *g.add_edge(m, a, {5, 0, 5});    // markers run m(5) → a(0)
  const edge_id e2 = *g.add_edge(b, m, {9, 5, 4});    // markers run b(9) → m(5)
  auto joined = g.merge_node(m, join_roads);
  REQUIRE(joined);
  CHECK(*joined == e1);  // the smaller id survives
  CHECK(!g.contains_edge(e2));
  CHECK(!g.contains_node(m));
  CHECK(g.source(e1) == a);
  CHECK(g.target(e1) == b);
  CHECK(g.edge(e1).first_marker == 0);  // walking a → m → b
  CHECK(g.edge(e1).last_marker == 9);
  CHECK(g.edge(e1).length == 9);
  CHECK(g.degree(a) == 1);
  CHECK(g.degree(b) == 1);
}

TEST_CASE("adjacency_list: merging at parallel edges makes a self-loop; loops do not merge") {
  perch::workspace ws;
  auto made = road_map::make(ws, 4, 4);
  REQUIRE(made);
  road_map& g = *made;
  const node_id a = *g.add_node();
  const node_id m = *g.add_node();
  REQUIRE(g.add_edge(a, m, {0, 1, 1}));
  REQUIRE(g.add_edge(m, a, {1, 2, 1}));
  auto joined = g.merge_node(m, join_roads);
  REQUIRE(joined);
  CHECK(g.source(*joined) == a);
  CHECK(g.target(*joined) == a);
  CHECK(g.degree(a) == 2);
  CHECK(g.edge(*joined).first_marker == 0);
  CHECK(g.edge(*joined).last_marker == 2);
  // a now has only a self-loop: nothing to merge.
  auto refused = g.merge_node(a, join_roads);
  REQUIRE(!refused);
  CHECK(refused.error().code == errc::invalid_parameter);
  const node_id lone = *g.add_node();
  auto refused2 = g.merge_node(lone, join_roads);
  REQUIRE(!refused2);
  CHECK(refused2.error().code == errc::invalid_parameter);
  auto refused3 = g.merge_node(m, join_roads);  // removed node
  CHECK(!refused3);
}

TEST_CASE("adjacency_list: capacities are enforced with capacity_exceeded") {
  perch::workspace ws;
  auto made = road_map::make(ws, 2, 1);
  REQUIRE(made);
  road_map& g = *made;
  REQUIRE(g.add_node());
  REQUIRE(g.add_node());
  auto third = g.add_node();
  REQUIRE(!third);
  CHECK(third.error().code == errc::capacity_exceeded);
  CHECK(third.error().needed == 3);
  REQUIRE(g.add_edge(0, 1));
  auto second = g.add_edge(1, 0);
  REQUIRE(!second);
  CHECK(second.error().code == errc::capacity_exceeded);
  g.remove_edge(0);
  auto again = g.add_edge(1, 0);  // ids are never reused: still full
  CHECK(!again);
  g.clear();
  CHECK(g.node_count() == 0);
  CHECK(g.add_node());
}

TEST_CASE("adjacency_list: a borrowed buffer of workspace_bytes is enough; smaller fails") {
  const std::size_t bytes = road_map::workspace_bytes(10, 20);
  std::vector<std::byte> buffer(bytes + perch::workspace::alignment);
  perch::workspace exact(std::span<std::byte>(buffer.data(), buffer.size()));
  CHECK(road_map::make(exact, 10, 20));
  std::vector<std::byte> small(bytes / 2);
  perch::workspace tight{std::span<std::byte>(small)};
  auto fails = road_map::make(tight, 10, 20);
  REQUIRE(!fails);
  CHECK(fails.error().code == errc::workspace_too_small);
}

TEST_CASE("adjacency_list: editing allocates nothing after make") {
  perch::workspace ws;
  auto made = road_map::make(ws, 64, 64);
  REQUIRE(made);
  road_map& g = *made;
  perch::test::allocation_scope scope;
  for (int i = 0; i < 32; ++i) REQUIRE(g.add_node());
  for (node_id i = 0; i + 1 < 32; ++i) REQUIRE(g.add_edge(i, i + 1, {i, i + 1, 1}));
  for (node_id i = 1; i + 1 < 32; ++i) REQUIRE(g.merge_node(i, join_roads));
  CHECK(g.edge_count() == 1);
  CHECK(g.edge(0).length == 31);
  CHECK(g.edge(0).first_marker == 0);
  CHECK(g.edge(0).last_marker == 31);
  CHECK(scope.count() == 0);
}
