// SPDX-License-Identifier: BSL-1.0
/// \file
/// Graph distances from each component's trunk node along the branches (Dijkstra), so each
/// branch can be oriented from the end nearer the trunk (where it leaves its parent) and arc
/// lengths can be measured from there (paper §"Analyse Branches", eq. 4's lever arm).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"
#include "perch/graph/adjacency_list.hpp"
#include "perch/graph/skeleton_graph.hpp"

namespace perch {

namespace detail {

/// A binary min-heap of node ids keyed by `key[id]` (ties: smaller id first), with decrease-key,
/// over caller memory: `heap` and `slot` hold one entry per node id.
class node_heap {
 public:
  node_heap(std::span<std::int32_t> heap, std::span<std::int32_t> slot,
            std::span<const float> key) noexcept
      : heap_(heap), slot_(slot), key_(key) {
    for (auto& s : slot_) s = -1;
  }
  [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
  /// Inserts `v` or moves it up after its key decreased.
  void push_or_decrease(std::int32_t v) noexcept {
    std::size_t i = 0;
    if (slot_[at(v)] < 0) {
      i = size_++;
      heap_[i] = v;
      slot_[at(v)] = static_cast<std::int32_t>(i);
    } else {
      i = static_cast<std::size_t>(slot_[at(v)]);
    }
    up(i);
  }
  [[nodiscard]] std::int32_t pop() noexcept {
    const std::int32_t top = heap_[0];
    slot_[at(top)] = -2;  // done
    --size_;
    if (size_ > 0) {
      heap_[0] = heap_[size_];
      slot_[at(heap_[0])] = 0;
      down(0);
    }
    return top;
  }
  [[nodiscard]] bool done(std::int32_t v) const noexcept { return slot_[at(v)] == -2; }

 private:
  static std::size_t at(std::int32_t v) noexcept { return static_cast<std::size_t>(v); }
  [[nodiscard]] bool less(std::int32_t a, std::int32_t b) const noexcept {
    return key_[at(a)] < key_[at(b)] || (key_[at(a)] == key_[at(b)] && a < b);
  }
  void place(std::size_t i, std::int32_t v) noexcept {
    heap_[i] = v;
    slot_[at(v)] = static_cast<std::int32_t>(i);
  }
  void up(std::size_t i) noexcept {
    const std::int32_t v = heap_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / 2;
      if (!less(v, heap_[parent])) break;
      place(i, heap_[parent]);
      i = parent;
    }
    place(i, v);
  }
  void down(std::size_t i) noexcept {
    const std::int32_t v = heap_[i];
    for (;;) {
      std::size_t child = 2 * i + 1;
      if (child >= size_) break;
      if (child + 1 < size_ && less(heap_[child + 1], heap_[child])) ++child;
      if (!less(heap_[child], v)) break;
      place(i, heap_[child]);
      i = child;
    }
    place(i, v);
  }

  std::span<std::int32_t> heap_;
  std::span<std::int32_t> slot_;
  std::span<const float> key_;
  std::size_t size_ = 0;
};

}  // namespace detail

/// Writes to `per_node_px[v]` the length (px) of the shortest walk along branches from the
/// trunk node of `v`'s component to node `v`, or +∞ for ids of removed nodes.
///
/// With it, a branch's origin (where it leaves its parent, toward the trunk) is its end whose
/// node is nearer the trunk, and the arc length from the trunk to any point of the branch is
/// that node's distance plus the arc length along the branch from that end.
/// Preconditions: none beyond a built graph. Errors: `size_mismatch` when `per_node_px` holds
/// fewer than `graph.topology().node_id_end()` values (`error::needed` says how many);
/// `workspace_too_small` for a borrowed workspace.
/// Complexity: O((nodes + branches) log nodes), Dijkstra's algorithm (1959) with a binary heap
/// in workspace memory (released before returning). Deterministic: ties go to smaller ids.
[[nodiscard]] inline status distances_to_trunk(const skeleton_graph& graph,
                                               std::span<float> per_node_px,
                                               workspace& ws) noexcept {
  const auto& g = graph.topology();
  const auto ids = static_cast<std::size_t>(g.node_id_end());
  if (per_node_px.size() < ids) return fail(errc::size_mismatch, "distances_to_trunk", ids);
  constexpr float infinity = std::numeric_limits<float>::infinity();
  for (float& d : per_node_px) d = infinity;
  const workspace::checkpoint scratch = ws.mark();
  auto heap = ws.allocate<std::int32_t>(ids);
  auto slot = ws.allocate<std::int32_t>(ids);
  if (auto ok = all_ok(heap, slot); !ok) {
    ws.rewind(scratch);
    return unexpected{ok.error()};
  }
  detail::node_heap queue(*heap, *slot, per_node_px.first(ids));
  for (std::int32_t c = 0; c < graph.component_count(); ++c) {
    const node_id t = graph.trunk(c);
    if (t == no_id || !g.contains_node(t)) continue;
    per_node_px[static_cast<std::size_t>(t)] = 0;
    queue.push_or_decrease(t);
  }
  while (!queue.empty()) {
    const node_id v = queue.pop();
    const float dv = per_node_px[static_cast<std::size_t>(v)];
    for (const incidence inc : g.incidences(v)) {
      if (inc.neighbour == v || queue.done(inc.neighbour)) continue;
      const float candidate = dv + g.edge(inc.edge).length_px;
      float& dn = per_node_px[static_cast<std::size_t>(inc.neighbour)];
      if (candidate < dn) {
        dn = candidate;
        queue.push_or_decrease(inc.neighbour);
      }
    }
  }
  ws.rewind(scratch);
  return {};
}

}  // namespace perch
