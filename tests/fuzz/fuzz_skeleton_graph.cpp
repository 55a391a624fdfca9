// SPDX-License-Identifier: BSL-1.0
// Fuzz target: the skeleton graph on arbitrary skeletons (not necessarily thin or connected)
// with arbitrary radii, then weighting, pruning at an arbitrary scale and trunk distances.
// Checks the graph's invariants: each skeleton pixel in exactly one branch or node, the
// handshake lemma, spans inside the image; never a crash, UB or an endless loop.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/graph.hpp"

namespace {
void check(bool ok) {
  if (!ok) __builtin_trap();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) return 0;
  const int w = 1 + data[0] % 64;
  const int h = 1 + data[1] % 64;
  const float mm_per_px = 0.05f + static_cast<float>(data[2]) / 8.0f;
  perch::image<std::uint8_t> skeleton(w, h);
  perch::image<std::uint32_t> dist2(w, h);
  std::size_t pixels = 0;
  for (int i = 0; i < w * h; ++i) {
    const std::size_t at = 3 + static_cast<std::size_t>(i) / 2;
    const std::uint8_t byte = at < size ? data[at] : 0;
    const std::uint8_t nibble = (i % 2 == 0) ? (byte & 15) : (byte >> 4);
    skeleton.data()[i] = (nibble & 1) != 0 ? 1 : 0;
    dist2.data()[i] = skeleton.data()[i] != 0 ? 1u + nibble * nibble : 0u;
    pixels += skeleton.data()[i];
  }
  static perch::workspace ws;
  ws.reset();
  auto graph = perch::build_skeleton_graph(skeleton.view(), dist2.view(), ws);
  if (!graph) return 0;
  std::size_t owned = 0;
  std::int64_t degrees = 0;
  graph->for_each_node([&](const perch::skeleton_node& n) {
    owned += n.pixel_count;
    degrees += n.degree;
    check(skeleton.view().contains(n.position.x, n.position.y));
  });
  graph->for_each_branch([&](const perch::skeleton_branch& b) {
    owned += b.points.size();
    check(b.points.size() == b.radius_px.size());
    for (const perch::pixel p : b.points) check(skeleton(p.x, p.y) != 0);
  });
  check(owned == pixels);
  check(degrees == 2 * static_cast<std::int64_t>(graph->branch_count()));
  auto report = perch::prune_skeleton_graph(*graph, mm_per_px, ws);
  check(report.has_value());
  std::vector<float> distance(static_cast<std::size_t>(graph->topology().node_id_end()));
  check(perch::distances_to_trunk(*graph, distance, ws).has_value());
  std::int64_t after = 0;
  graph->for_each_node([&](const perch::skeleton_node& n) { after += n.degree; });
  check(after == 2 * static_cast<std::int64_t>(graph->branch_count()));
  return 0;
}
