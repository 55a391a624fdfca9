// SPDX-License-Identifier: BSL-1.0
// A Cortex-M7 program as a firmware team would write it: a static mask, a static workspace
// buffer, one find_perch call, the best site written to a static struct. It names no allocator,
// so its image links no heap, no exception and no RTTI support (CI checks the symbols).
// board.hpp says how the result leaves the chip: semihosting under qemu here.
#include <cstddef>
#include <cstdint>

#include "board.hpp"
#include "perch/pli.hpp"

namespace {

constexpr int width = 160;
constexpr int height = 120;
constexpr float mm_per_px = 4.0f;

/// What the flight controller reads after the call.
struct perch_report {
  std::int32_t status = -1;   ///< 0: ok; else the perch::errc of the failure
  std::int32_t outcome = -1;  ///< perch::perch_outcome
  std::int32_t x = -1, y = -1;
  std::int32_t slope_decideg = 0;
  std::int32_t diameter_mm = 0;
  std::uint32_t windows = 0;
  std::uint32_t high_water = 0;  ///< workspace bytes the call needed at most
};

std::uint8_t mask[height][width];
/// What this camera's masks need at most (measured with `perch::measured_limits` on a corpus,
/// with margin; this tree needs 5 907 tree pixels, 210 skeleton pixels and 8 windows): any box,
/// a third of the frame on the tree. `find_perch` refuses a mask beyond them by name.
constexpr perch::perch_limits limits{.box_pixels = 0, .tree_pixels = 6400,
                                     .skeleton_pixels = 400, .windows = 64};
/// The workspace: enough for every mask within `limits`.
constexpr std::size_t buffer_bytes =
    perch::find_perch_workspace_bytes<perch::medial_axis>(width, height, limits);
static_assert(buffer_bytes > 0, "the limits do not fit this target");
alignas(perch::workspace::alignment) std::byte buffer[buffer_bytes];
perch_report report;

/// Fills the pixels within `r` of the segment (ax, ay)–(bx, by): integers only, so the mask is
/// the same on every target.
void capsule(int ax, int ay, int bx, int by, int r) {
  const std::int64_t dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::int64_t px = x - ax, py = y - ay;
      std::int64_t t = px * dx + py * dy;  // projection, scaled by len2
      t = t < 0 ? 0 : (t > len2 ? len2 : t);
      const std::int64_t ex = px * len2 - t * dx, ey = py * len2 - t * dy;
      if (ex * ex + ey * ey <= std::int64_t{r} * r * len2 * len2) mask[y][x] = 1;
    }
}

/// A trunk 150 mm wide rising from the bottom edge and a level limb 60 mm wide.
void draw_tree() {
  capsule(40, height + 10, 40, 20, 19);
  capsule(40, 60, width - 8, 60, 7);
}

void find() {
  perch::workspace ws{std::span<std::byte>(buffer)};
  const perch::image_view<const std::uint8_t> view(&mask[0][0], width, height);
  perch::perch_options options;
  options.limits = limits;
  auto found = perch::find_perch(view, perch::tendon_claw{}, perch::fixed_scale{mm_per_px},
                                 perch::medial_axis{}, ws, options);
  report.high_water = static_cast<std::uint32_t>(ws.high_water());
  if (!found) {
    report.status = static_cast<std::int32_t>(found.error().code);
    return;
  }
  report.status = 0;
  report.outcome = static_cast<std::int32_t>(found->outcome);
  report.windows = found->windows;
  if (found->sites.empty()) return;
  const perch::window_measures& best = found->sites.front().window;
  report.x = best.centre.x;
  report.y = best.centre.y;
  report.slope_decideg = static_cast<std::int32_t>(best.slope_deg * 10.0f);
  report.diameter_mm = static_cast<std::int32_t>(best.claw_diameter_mm);
}

}  // namespace

int main() {
  draw_tree();
  find();
  board::print("perch firmware: status ");
  board::print(report.status);
  board::print(" outcome ");
  board::print(report.outcome);
  board::print(" site ");
  board::print(report.x);
  board::print(",");
  board::print(report.y);
  board::print(" slope_decideg ");
  board::print(report.slope_decideg);
  board::print(" diameter_mm ");
  board::print(report.diameter_mm);
  board::print(" windows ");
  board::print(static_cast<std::int32_t>(report.windows));
  board::print(" high_water ");
  board::print(static_cast<std::int32_t>(report.high_water));
  board::print("\n");
  return report.status == 0 && report.outcome == 0 ? 0 : 1;
}
