// SPDX-License-Identifier: BSL-1.0
/// \file
/// `perch_limits`: what a caller states its masks need at most, so that a fixed buffer can be
/// sized for them (`find_perch_workspace_bytes`) and `find_perch` holds every mask to them.
#pragma once

#include <cstddef>

#include "perch/core/result.hpp"

namespace perch {

/// The most a mask may need of what `find_perch`'s memory grows with, beyond the frame's size.
/// `find_perch` fails with `capacity_exceeded` (`error::detail` naming the field,
/// `error::needed` the count it met) on a mask that needs more, before taking memory for it: a
/// buffer of `find_perch_workspace_bytes` for these limits then never runs short.
/// Measure them on your own masks with `measured_limits(result)`.
struct perch_limits {
  /// Pixels of the analysed box: the tree's bounding box at `downscale`, with a one-pixel
  /// border (`perch_result::mask.pixels`); 0: no limit (the whole frame).
  std::size_t box_pixels = 0;
  /// Tree pixels of the analysed box, pinholes filled (`perch_result::mask.tree_pixels`); 0: no
  /// limit.
  std::size_t tree_pixels = 0;
  /// Skeleton pixels of the analysed mask (`perch_result::graph.skeleton_pixels()`, counted
  /// before pruning); 0: no limit (at most every pixel of the analysed frame).
  std::size_t skeleton_pixels = 0;
  /// Nodes of the skeleton graph as built (`perch_result::graph.topology().node_id_end()`:
  /// pruning removes nodes and adds none); 0: no limit (one per skeleton pixel). Everything
  /// from the graph on grows with it and `graph_branches`, far less than with the pixels on a
  /// bushy tree.
  std::size_t graph_nodes = 0;
  /// Branches of the skeleton graph as built (`perch_result::graph.topology().edge_id_end()`:
  /// pruning's merges reuse ids); 0: no limit (one per skeleton pixel).
  std::size_t graph_branches = 0;
  /// Windows held at once over the whole tree (`perch_result::windows_held`; never 0).
  std::size_t windows = std::size_t{1} << 18;

  [[nodiscard]] constexpr status validate() const noexcept {
    if (windows == 0) return fail(errc::invalid_parameter, "perch_options.limits.windows");
    return {};
  }
};

}  // namespace perch
