// SPDX-License-Identifier: BSL-1.0
/// \file
/// `count_topology`: the number of components and holes of a binary mask, the invariants a
/// topology-preserving skeleton must keep.
#pragma once

#include <cstddef>
#include <cstdint>

#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/union_find.hpp"
#include "perch/core/workspace.hpp"
#include "perch/label/components.hpp"
#include "perch/label/connectivity.hpp"
#include "perch/label/detail/scan.hpp"

namespace perch {

/// Components and holes of a binary mask.
struct topology_counts {
  std::int32_t components;  ///< 8-connected foreground components
  std::int32_t holes;       ///< 4-connected background components not touching the border
  friend constexpr bool operator==(const topology_counts&, const topology_counts&) = default;
};

/// Bytes `count_topology` takes from the workspace for a `width` × `height` mask: exactly
/// this, released when the call ends. 0 for an empty size.
[[nodiscard]] constexpr std::size_t topology_workspace_bytes(int width, int height) noexcept {
  if (width <= 0 || height <= 0) return 0;
  const std::size_t bound = detail::provisional_label_bound(width, height, connectivity::four);
  return workspace::footprint<std::int32_t>(static_cast<std::size_t>(width) *
                                            static_cast<std::size_t>(height)) +
         workspace::footprint<std::int32_t>(bound + 1) +
         workspace::footprint<std::uint8_t>(bound + 1);
}

/// Counts the 8-connected foreground components of `mask` and its holes: the 4-connected
/// background components that do not touch the image border (pixels outside the image count
/// as background, so a background region reaching the border is outside, not a hole).
///
/// Foreground and background use dual connectivities (8 and 4) so that a closed 8-connected
/// curve separates inside from outside, as digital topology requires (Rosenfeld, "Connectivity
/// in digital pictures", J. ACM 17 (1970) 146–160). With these, the Euler number is
/// components − holes, and a simple-point deletion (thinning) keeps both counts.
/// Errors: view errors of `mask` (`empty_image` for a zero size, `null_data`, ...);
/// `workspace_too_small` (with `needed`) / `out_of_memory` from the workspace.
/// Complexity: two first passes of the two-pass labeller of `label_components` (Wu, Otoo &
/// Suzuki 2009), O(width · height); `topology_workspace_bytes(width, height)` bytes of workspace,
/// released before returning. No heap allocation with a sufficient workspace.
template <BinaryView Mask>
[[nodiscard]] result<topology_counts> count_topology(const Mask& mask, workspace& ws) noexcept {
  PERCH_TRY(validate_non_empty(mask));
  const int width = mask.width();
  const int height = mask.height();
  const workspace::checkpoint start = ws.mark();
  const std::size_t bound = detail::provisional_label_bound(width, height, connectivity::four);
  auto label_pixels =
      ws.allocate<std::int32_t>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  PERCH_TRY(all_ok(label_pixels));
  auto parent = ws.allocate<std::int32_t>(bound + 1);
  if (auto ok = all_ok(parent); !ok) {
    ws.rewind(start);
    return unexpected{ok.error()};
  }
  auto outside = ws.allocate_zeroed<std::uint8_t>(bound + 1);
  if (auto ok = all_ok(outside); !ok) {
    ws.rewind(start);
    return unexpected{ok.error()};
  }
  const image_view<std::int32_t> labels(label_pixels->data(), width, height);

  // Foreground, 8-connected: the number of sets is all that is needed (no second pass).
  detail::union_find fg{parent->data(), 0, static_cast<std::int32_t>(bound)};
  detail::label_first_pass<detail::polarity::foreground, connectivity::eight>(mask, labels, fg);
  const std::int32_t components = fg.flatten();

  // Background, 4-connected; sets reaching the border are outside, the rest are holes.
  detail::union_find bg{parent->data(), 0, static_cast<std::int32_t>(bound)};
  detail::label_first_pass<detail::polarity::background, connectivity::four>(mask, labels, bg);
  const std::int32_t regions = bg.flatten();
  std::int32_t touching = 0;
  auto mark = [&](int x, int y) {
    const std::int32_t provisional = labels(x, y);
    if (provisional == 0) return;
    std::uint8_t& seen = (*outside)[static_cast<std::size_t>(bg.parent[provisional])];
    touching += seen == 0 ? 1 : 0;
    seen = 1;
  };
  for (int x = 0; x < width; ++x) {
    mark(x, 0);
    mark(x, height - 1);
  }
  for (int y = 0; y < height; ++y) {
    mark(0, y);
    mark(width - 1, y);
  }
  ws.rewind(start);
  return topology_counts{components, regions - touching};
}

}  // namespace perch
