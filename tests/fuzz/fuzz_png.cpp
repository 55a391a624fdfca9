// SPDX-License-Identifier: BSL-1.0
// Fuzz target: the PNG reader must reject any byte string cleanly (a message, no crash, no UB)
// and decode what it accepts consistently. Chunk CRCs are repaired first on odd-length inputs,
// so the fuzzer also reaches the header, zlib, filter and palette code behind the CRC check.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "png/png.hpp"

namespace {

void repair_crcs(std::vector<std::uint8_t>& b) {
  std::size_t at = 8;  // after the signature
  while (at + 12 <= b.size()) {
    const std::uint32_t length = (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
                                 (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
    if (length > b.size() - at - 12) break;
    const std::uint32_t crc = perch::png::crc32(std::span<const std::uint8_t>(b.data() + at + 4, length + 4));
    for (std::size_t i = 0; i < 4; ++i)
      b[at + 8 + length + i] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
    at += 12 + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  if (size % 2 == 1) repair_crcs(bytes);
  auto decoded = perch::png::read_png(bytes, {.max_pixels = std::int64_t{1} << 20});
  if (!decoded) {
    if (decoded.error().message.empty()) __builtin_trap();  // every rejection says why
    return 0;
  }
  // Whatever decodes converts, and its mask round-trips through the writer.
  const auto mask = perch::png::to_mask(*decoded);
  const auto depth = perch::png::to_gray16(*decoded);
  const auto colour = perch::png::to_rgb8(*decoded);
  if (mask.width() != decoded->width || depth.height() != decoded->height ||
      colour.width() != decoded->width)
    __builtin_trap();
  auto encoded = perch::png::encode_png(perch::image_view<const std::uint8_t>(mask.view()));
  if (!encoded) __builtin_trap();
  auto again = perch::png::read_png(*encoded);
  if (!again || again->width != decoded->width || again->height != decoded->height) __builtin_trap();
  return 0;
}
