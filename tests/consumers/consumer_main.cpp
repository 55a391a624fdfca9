// SPDX-License-Identifier: BSL-1.0
// A user's program: includes the one perch header and runs the library on a small mask.
// Returns 0 when perch behaves, non-zero otherwise (the test checks the exit code).
#include <perch/pli.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

int main() {
  std::array<std::uint8_t, 12 * 8> pixels{};
  for (int x = 1; x < 11; ++x) pixels[static_cast<std::size_t>(4 * 12 + x)] = 1;
  const perch::image_view<const std::uint8_t> mask(pixels.data(), 12, 8);
  if (!perch::validate_non_empty(mask)) return 1;
  std::array<std::byte, 1 << 14> buffer{};
  perch::workspace ws{std::span<std::byte>(buffer)};
  auto scratch = ws.allocate<std::int32_t>(mask.size());
  if (!scratch || scratch->size() != mask.size()) return 2;
  const perch::image_view<const std::uint8_t> bad(nullptr, 4, 4);
  if (perch::validate(bad).error().code != perch::errc::null_data) return 3;
  return 0;
}
