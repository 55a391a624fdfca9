// SPDX-License-Identifier: BSL-1.0
/// \file
/// `adjacency_list<NodeData, EdgeData>`: a generic undirected multigraph over workspace memory,
/// with fixed capacities, stable ids, parallel edges and self-loops, and the one structural edit
/// skeleton pruning needs beyond removal: merging a node of degree 2 into one edge.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>
#include <type_traits>
#include <utility>

#include "perch/core/assert.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// Id of a node of an `adjacency_list` (and of a `skeleton_graph`): 0, 1, 2, ... in order of
/// creation, never reused. `std::int32_t` like the branch and component ids of the analysis stage.
using node_id = std::int32_t;
/// Id of an edge of an `adjacency_list` (a branch of a `skeleton_graph`), like `node_id`.
using edge_id = std::int32_t;
/// "No node" / "no edge".
inline constexpr std::int32_t no_id = -1;

/// How a walk passes along an edge relative to the edge's stored direction (source → target).
enum class traversal : std::uint8_t {
  forward,   ///< from the edge's source to its target
  backward,  ///< from the edge's target to its source
};

/// The opposite traversal.
[[nodiscard]] constexpr traversal reversed(traversal t) noexcept {
  return t == traversal::forward ? traversal::backward : traversal::forward;
}

/// One end of an edge seen from a node: the edge, the node at its other end, and whether the
/// edge is stored leaving this node (`forward`) or entering it (`backward`). A self-loop is
/// seen twice from its node, once each way.
struct incidence {
  edge_id edge = no_id;
  node_id neighbour = no_id;
  traversal direction = traversal::forward;
};

/// One of the two edges joined by `adjacency_list::merge_node`, with the direction in which the
/// joined walk passes along it (first: toward the merged node; second: away from it).
template <class EdgeData>
struct edge_part {
  const EdgeData& data;
  traversal direction;
};

/// An undirected multigraph whose nodes carry `NodeData` and edges `EdgeData`.
///
/// - Memory: every array comes from a `workspace` at `make` with the capacities given there;
///   nothing is allocated afterwards. Adding past a capacity is `errc::capacity_exceeded`.
/// - Ids: nodes and edges are numbered 0, 1, 2, ... in order of creation and never reused, so an
///   id stays valid (and means the same element) until that element is removed; capacities
///   count ids ever issued. `merge_node` keeps the smaller of the two edge ids for the joined edge.
/// - Edges are stored with a direction (source → target) only so that data ordered along the
///   edge (e.g. a polyline) can be read the right way; the graph itself is undirected.
///   Parallel edges and self-loops are allowed; a self-loop adds 2 to its node's degree.
/// - Incidences of a node are kept in a doubly linked list in order of attachment, so degree,
///   edge removal and merging are O(1) and iteration is O(degree).
/// `NodeData` and `EdgeData` must be trivially destructible and copy-assignable (workspace
/// memory never runs destructors). Copying the list is disabled (it is a handle over workspace
/// memory); moving is cheap. Not thread-safe.
template <class NodeData, class EdgeData>
class adjacency_list {
  static_assert(std::is_trivially_destructible_v<NodeData> && std::is_copy_assignable_v<NodeData>,
                "adjacency_list: NodeData must be trivially destructible and copy-assignable");
  static_assert(std::is_trivially_destructible_v<EdgeData> && std::is_copy_assignable_v<EdgeData>,
                "adjacency_list: EdgeData must be trivially destructible and copy-assignable");

  static constexpr std::int32_t none = -1;

  struct node_slot {
    NodeData data;
    std::int32_t head;  // first half-edge attached here
    std::int32_t tail;  // last half-edge attached here
    std::int32_t degree;
    bool alive;
  };
  struct edge_slot {
    EdgeData data;
    node_id end[2];  // source, target
    bool alive;
  };

 public:
  using node_data_type = NodeData;
  using edge_data_type = EdgeData;

  /// Bytes `make(ws, nodes, edges)` takes from a workspace.
  [[nodiscard]] static constexpr std::size_t workspace_bytes(std::size_t nodes,
                                                             std::size_t edges) noexcept {
    return workspace::footprint<node_slot>(nodes) + workspace::footprint<edge_slot>(edges) +
           2 * workspace::footprint<std::int32_t>(2 * edges);
  }

  /// An empty list with room for `node_capacity` nodes and `edge_capacity` edges, drawn from `ws`.
  /// Errors: `invalid_parameter` if a capacity exceeds 2^30; the workspace's own errors.
  [[nodiscard]] static result<adjacency_list> make(workspace& ws, std::size_t node_capacity,
                                                   std::size_t edge_capacity) noexcept {
    constexpr std::size_t limit = std::size_t{1} << 30;
    if (node_capacity > limit || edge_capacity > limit)
      return fail(errc::invalid_parameter, "adjacency_list capacity above 2^30");
    adjacency_list g;
    auto nodes = ws.allocate<node_slot>(node_capacity);
    PERCH_TRY(all_ok(nodes));
    auto edges = ws.allocate<edge_slot>(edge_capacity);
    PERCH_TRY(all_ok(edges));
    auto next = ws.allocate<std::int32_t>(2 * edge_capacity);
    PERCH_TRY(all_ok(next));
    auto prev = ws.allocate<std::int32_t>(2 * edge_capacity);
    PERCH_TRY(all_ok(prev));
    g.nodes_ = *nodes;
    g.edges_ = *edges;
    g.next_ = *next;
    g.prev_ = *prev;
    return g;
  }

  adjacency_list() noexcept = default;
  adjacency_list(const adjacency_list&) = delete;
  adjacency_list& operator=(const adjacency_list&) = delete;
  adjacency_list(adjacency_list&&) noexcept = default;
  adjacency_list& operator=(adjacency_list&&) noexcept = default;
  ~adjacency_list() = default;

  /// Adds a node. Errors: `capacity_exceeded` (needed = nodes issued + 1). O(1).
  [[nodiscard]] result<node_id> add_node(const NodeData& data = {}) noexcept {
    if (node_end_ == nodes_.size())
      return fail(errc::capacity_exceeded, "adjacency_list nodes", node_end_ + 1);
    const auto id = static_cast<node_id>(node_end_++);
    nodes_[index(id)] = node_slot{data, none, none, 0, true};
    ++live_nodes_;
    return id;
  }

  /// Adds an edge `from` → `to` (equal for a self-loop). Precondition: both nodes alive.
  /// Errors: `capacity_exceeded` (needed = edges issued + 1). O(1).
  [[nodiscard]] result<edge_id> add_edge(node_id from, node_id to,
                                         const EdgeData& data = {}) noexcept {
    PERCH_ASSERT(contains_node(from) && contains_node(to), "add_edge: node not in the graph");
    if (edge_end_ == edges_.size())
      return fail(errc::capacity_exceeded, "adjacency_list edges", edge_end_ + 1);
    const auto id = static_cast<edge_id>(edge_end_++);
    edges_[index(id)] = edge_slot{data, {from, to}, true};
    link(2 * id, from);
    link(2 * id + 1, to);
    ++live_edges_;
    return id;
  }

  /// Removes edge `e` (precondition: alive). Its end nodes stay. O(1).
  void remove_edge(edge_id e) noexcept {
    PERCH_ASSERT(contains_edge(e), "remove_edge: edge not in the graph");
    unlink(2 * e);
    unlink(2 * e + 1);
    edges_[index(e)].alive = false;
    --live_edges_;
  }

  /// Removes node `n` and every edge incident to it (precondition: alive). O(degree).
  void remove_node(node_id n) noexcept {
    PERCH_ASSERT(contains_node(n), "remove_node: node not in the graph");
    while (nodes_[index(n)].head != none) remove_edge(nodes_[index(n)].head / 2);
    nodes_[index(n)].alive = false;
    --live_nodes_;
  }

  /// Replaces node `n` of degree 2 and its two edges by one edge joining their far ends.
  ///
  /// The two edges are ordered by id: `first` (smaller id) and `second`. The joined edge runs from
  /// `first`'s far end through `n` to `second`'s far end, keeps `first`'s id, and carries
  /// `join(edge_part{first data, direction along first toward n}, n's data,
  ///       edge_part{second data, direction along second away from n})`, which must return an
  /// `EdgeData`. `second`'s id dies, and so does `n`. Two parallel edges make a self-loop.
  /// Errors: `invalid_parameter` when `n` is not alive, its degree is not 2, or its two ends
  /// belong to one self-loop (a cycle has nothing to merge). O(1) plus the callback.
  template <class Join>
    requires std::is_convertible_v<std::invoke_result_t<Join&, const edge_part<EdgeData>&,
                                                        const NodeData&,
                                                        const edge_part<EdgeData>&>,
                                   EdgeData>
  [[nodiscard]] result<edge_id> merge_node(node_id n, Join&& join) noexcept {
    if (!contains_node(n)) return fail(errc::invalid_parameter, "merge_node: no such node");
    const node_slot& slot = nodes_[index(n)];
    if (slot.degree != 2) return fail(errc::invalid_parameter, "merge_node: degree is not 2");
    std::int32_t h1 = slot.head;
    std::int32_t h2 = next_[index(h1)];
    if (h1 / 2 == h2 / 2) return fail(errc::invalid_parameter, "merge_node: a self-loop");
    if (h2 / 2 < h1 / 2) std::swap(h1, h2);
    const edge_id e1 = h1 / 2;
    const edge_id e2 = h2 / 2;
    // Half-edge 2e sits at the source, 2e+1 at the target: the walk enters n along e1 forward
    // iff n is e1's target, and leaves along e2 forward iff n is e2's source.
    const traversal d1 = (h1 % 2 == 1) ? traversal::forward : traversal::backward;
    const traversal d2 = (h2 % 2 == 0) ? traversal::forward : traversal::backward;
    const node_id far1 = edges_[index(e1)].end[1 - h1 % 2];
    const node_id far2 = edges_[index(e2)].end[1 - h2 % 2];
    EdgeData joined = static_cast<EdgeData>(join(edge_part<EdgeData>{edges_[index(e1)].data, d1},
                                                 slot.data,
                                                 edge_part<EdgeData>{edges_[index(e2)].data, d2}));
    remove_edge(e2);
    remove_edge(e1);
    nodes_[index(n)].alive = false;
    --live_nodes_;
    edges_[index(e1)] = edge_slot{joined, {far1, far2}, true};
    link(2 * e1, far1);
    link(2 * e1 + 1, far2);
    ++live_edges_;
    return e1;
  }

  /// Forgets every node and edge (keeps the memory and capacities).
  void clear() noexcept {
    node_end_ = edge_end_ = live_nodes_ = live_edges_ = 0;
  }

  // --- size and ids -----------------------------------------------------------------------

  [[nodiscard]] std::size_t node_count() const noexcept { return live_nodes_; }
  [[nodiscard]] std::size_t edge_count() const noexcept { return live_edges_; }
  [[nodiscard]] std::size_t node_capacity() const noexcept { return nodes_.size(); }
  [[nodiscard]] std::size_t edge_capacity() const noexcept { return edges_.size(); }
  /// One past the largest node id issued: ids in [0, node_id_end()) are alive or removed.
  [[nodiscard]] node_id node_id_end() const noexcept { return static_cast<node_id>(node_end_); }
  /// One past the largest edge id issued.
  [[nodiscard]] edge_id edge_id_end() const noexcept { return static_cast<edge_id>(edge_end_); }
  [[nodiscard]] bool contains_node(node_id n) const noexcept {
    return n >= 0 && static_cast<std::size_t>(n) < node_end_ && nodes_[index(n)].alive;
  }
  [[nodiscard]] bool contains_edge(edge_id e) const noexcept {
    return e >= 0 && static_cast<std::size_t>(e) < edge_end_ && edges_[index(e)].alive;
  }

  // --- elements ---------------------------------------------------------------------------

  /// Data of a live node / edge (checked by `PERCH_ASSERT`).
  [[nodiscard]] NodeData& node(node_id n) noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return nodes_[index(n)].data;
  }
  [[nodiscard]] const NodeData& node(node_id n) const noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return nodes_[index(n)].data;
  }
  [[nodiscard]] EdgeData& edge(edge_id e) noexcept {
    PERCH_ASSERT(contains_edge(e), "adjacency_list: edge not in the graph");
    return edges_[index(e)].data;
  }
  [[nodiscard]] const EdgeData& edge(edge_id e) const noexcept {
    PERCH_ASSERT(contains_edge(e), "adjacency_list: edge not in the graph");
    return edges_[index(e)].data;
  }
  /// Where edge `e` is stored leaving from / arriving at.
  [[nodiscard]] node_id source(edge_id e) const noexcept {
    PERCH_ASSERT(contains_edge(e), "adjacency_list: edge not in the graph");
    return edges_[index(e)].end[0];
  }
  [[nodiscard]] node_id target(edge_id e) const noexcept {
    PERCH_ASSERT(contains_edge(e), "adjacency_list: edge not in the graph");
    return edges_[index(e)].end[1];
  }
  /// The end of `e` that is not `n` (`n` itself for a self-loop). Precondition: `n` is an end.
  [[nodiscard]] node_id opposite(edge_id e, node_id n) const noexcept {
    PERCH_ASSERT(source(e) == n || target(e) == n, "opposite: node is not an end of the edge");
    return source(e) == n ? target(e) : source(e);
  }
  /// Number of edge ends at `n` (a self-loop counts twice).
  [[nodiscard]] std::int32_t degree(node_id n) const noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return nodes_[index(n)].degree;
  }

  // --- iteration --------------------------------------------------------------------------

  /// Forward range over the incidences of one node, in order of attachment.
  template <class Projection>
  class incidence_range {
   public:
    class iterator {
     public:
      using iterator_category = std::forward_iterator_tag;
      using value_type = std::invoke_result_t<Projection, incidence>;
      using difference_type = std::ptrdiff_t;
      iterator() noexcept = default;
      iterator(const adjacency_list* g, std::int32_t half) noexcept : g_(g), half_(half) {}
      [[nodiscard]] value_type operator*() const noexcept {
        const std::int32_t side = half_ % 2;
        const edge_id e = half_ / 2;
        return Projection{}(incidence{e, g_->edges_[index(e)].end[1 - side],
                                      side == 0 ? traversal::forward : traversal::backward});
      }
      iterator& operator++() noexcept {
        half_ = g_->next_[index(half_)];
        return *this;
      }
      iterator operator++(int) noexcept {
        iterator old = *this;
        ++*this;
        return old;
      }
      friend bool operator==(const iterator& a, const iterator& b) noexcept {
        return a.half_ == b.half_;
      }

     private:
      const adjacency_list* g_ = nullptr;
      std::int32_t half_ = none;
    };
    incidence_range(const adjacency_list* g, std::int32_t head) noexcept : g_(g), head_(head) {}
    [[nodiscard]] iterator begin() const noexcept { return {g_, head_}; }
    [[nodiscard]] iterator end() const noexcept { return {g_, none}; }

   private:
    const adjacency_list* g_;
    std::int32_t head_;
  };

  struct whole_incidence {
    constexpr incidence operator()(incidence i) const noexcept { return i; }
  };
  struct neighbour_of {
    constexpr node_id operator()(incidence i) const noexcept { return i.neighbour; }
  };
  struct edge_of {
    constexpr edge_id operator()(incidence i) const noexcept { return i.edge; }
  };

  /// The incidences of live node `n` (a self-loop appears twice). Valid until the next edit.
  [[nodiscard]] incidence_range<whole_incidence> incidences(node_id n) const noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return {this, nodes_[index(n)].head};
  }
  /// The neighbours of `n`, one per incidence (with repeats for parallel edges and self-loops).
  [[nodiscard]] incidence_range<neighbour_of> neighbours(node_id n) const noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return {this, nodes_[index(n)].head};
  }
  /// The edges incident to `n`, one per incidence (a self-loop twice).
  [[nodiscard]] incidence_range<edge_of> incident_edges(node_id n) const noexcept {
    PERCH_ASSERT(contains_node(n), "adjacency_list: node not in the graph");
    return {this, nodes_[index(n)].head};
  }

  /// Calls `f(node_id)` for every live node, in id order.
  template <class F>
  void for_each_node(F&& f) const {
    for (std::size_t i = 0; i < node_end_; ++i)
      if (nodes_[i].alive) f(static_cast<node_id>(i));
  }
  /// Calls `f(edge_id)` for every live edge, in id order.
  template <class F>
  void for_each_edge(F&& f) const {
    for (std::size_t i = 0; i < edge_end_; ++i)
      if (edges_[i].alive) f(static_cast<edge_id>(i));
  }

 private:
  static constexpr std::size_t index(std::int32_t i) noexcept { return static_cast<std::size_t>(i); }

  void link(std::int32_t half, node_id n) noexcept {
    node_slot& s = nodes_[index(n)];
    next_[index(half)] = none;
    prev_[index(half)] = s.tail;
    if (s.tail == none)
      s.head = half;
    else
      next_[index(s.tail)] = half;
    s.tail = half;
    ++s.degree;
  }
  void unlink(std::int32_t half) noexcept {
    const node_id n = edges_[index(half / 2)].end[half % 2];
    node_slot& s = nodes_[index(n)];
    const std::int32_t p = prev_[index(half)];
    const std::int32_t q = next_[index(half)];
    if (p == none)
      s.head = q;
    else
      next_[index(p)] = q;
    if (q == none)
      s.tail = p;
    else
      prev_[index(q)] = p;
    --s.degree;
  }

  std::span<node_slot> nodes_{};
  std::span<edge_slot> edges_{};
  std::span<std::int32_t> next_{};
  std::span<std::int32_t> prev_{};
  std::size_t node_end_ = 0;
  std::size_t edge_end_ = 0;
  std::size_t live_nodes_ = 0;
  std::size_t live_edges_ = 0;
};

}  // namespace perch
