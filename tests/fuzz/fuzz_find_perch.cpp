// SPDX-License-Identifier: BSL-1.0
// Fuzz target: find_perch on arbitrary masks and parameters. The input bytes choose the size,
// the platform, the scale (fixed, trunk prior, or a depth image that may be a column too wide
// and have invalid samples) and the options (including NaN, zero and negative values, and the
// widest gap bridged), then the pixels. Any input must give a status or a result whose sites
// lie on the mask with finite values and whose bridges lie in the image; never a crash, UB, an
// assert or an endless loop.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"

namespace {

float pick_float(std::uint8_t b) {
  switch (b % 8) {
    case 0:
      return std::numeric_limits<float>::quiet_NaN();
    case 1:
      return 0.0f;
    case 2:
      return -1.0f;
    case 3:
      return std::numeric_limits<float>::infinity();
    default:
      return 0.25f + static_cast<float>(b) / 16.0f;
  }
}

void check(bool ok) {
  if (!ok) __builtin_trap();
}

template <class Platform, class Scale>
void run(const perch::image<std::uint8_t>& mask, const Platform& platform, const Scale& scale,
         const perch::perch_options& options) {
  static perch::workspace ws;
  auto found = perch::find_perch(mask.view(), platform, scale, ws, options);
  if (!found) {
    check(!found.error().message().empty());
    return;
  }
  check(found->sites.size() <= options.ranking.top_k);
  for (const perch::perch_site& s : found->sites) {
    const perch::window_measures& m = s.window;
    check(mask.view().contains(m.centre.x, m.centre.y));
    if (options.downscale == 1.0f) check(mask(m.centre.x, m.centre.y) != 0);
    for (const float v : {s.penalty, m.slope_deg, m.claw_diameter_mm, m.curvature_max_per_mm,
                          m.mm_per_px, m.diameter_min_mm, m.diameter_max_mm})
      check(std::isfinite(v));
    check(m.slope_deg >= 0.0f && m.slope_deg <= 90.0f);
    if (m.has_position) check(m.position_m.allFinite());
  }
  for (const perch::perch_bridge& b : found->bridges) {
    check(mask.view().contains(b.from.x, b.from.y) && mask.view().contains(b.to.x, b.to.y));
    check(std::isfinite(b.gap_px) && b.gap_px >= 0.0f);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 6) return 0;
  const int w = 1 + data[0] % 80;
  const int h = 1 + data[1] % 80;
  const std::uint8_t choice = data[2];
  perch::perch_options options;
  options.downscale = (choice & 1) != 0 ? 0.5f : 1.0f;
  options.stride_mm = (data[3] & 0x80) != 0 ? pick_float(data[3]) : 20.0f;
  options.camera.roll_deg = (data[4] & 0x80) != 0 ? pick_float(data[4]) - 4.0f : 0.0f;
  options.ranking.top_k = 1 + data[4] % 6;
  const float scale_value = pick_float(data[5]);
  if ((data[5] & 0x80) != 0) options.bridging.max_gap_px = 4.0f * pick_float(data[5] >> 3);

  perch::image<std::uint8_t> mask(w, h);
  const std::size_t bits = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const std::uint8_t* pixels = data + 6;
  const std::size_t available = (size - 6) * 8;
  for (std::size_t i = 0; i < bits && i < available; ++i)
    mask.data()[i] = (pixels[i / 8] >> (i % 8)) & 1;

  const int scale_kind = (choice >> 1) & 1;
  switch ((choice >> 2) % 6) {
    case 0:
      scale_kind == 0 ? run(mask, perch::tendon_claw{}, perch::fixed_scale{scale_value}, options)
                      : run(mask, perch::tendon_claw{}, perch::trunk_prior{scale_value * 40}, options);
      break;
    case 1:
      run(mask, perch::tensile_tether{}, perch::fixed_scale{scale_value}, options);
      break;
    case 2:
      run(mask, perch::metamorphic_quadrotor{}, perch::fixed_scale{scale_value}, options);
      break;
    case 3:
      run(mask, perch::ornithopter{}, perch::trunk_prior{scale_value * 40}, options);
      break;
    case 4:
      run(mask, perch::treecreeper{}, perch::fixed_scale{scale_value}, options);
      break;
    default: {
      // Depth in mm from the pixel bytes (0 = invalid), sometimes one column wider than the mask.
      const int depth_w = w + (choice >> 7);
      perch::image<std::uint16_t> depth(depth_w, h);
      for (int i = 0; i < depth_w * h && size > 6; ++i)
        depth.data()[i] = static_cast<std::uint16_t>(pixels[static_cast<std::size_t>(i) % (size - 6)] * 16);
      const float f = scale_value * 400.0f;
      const perch::pinhole intrinsics{f, f, static_cast<float>(w) / 2, static_cast<float>(h) / 2};
      run(mask, perch::tendon_claw{}, perch::depth_scale{depth.view(), intrinsics}, options);
      break;
    }
  }
  return 0;
}
