// SPDX-License-Identifier: BSL-1.0
// A user's program that loads its mask with perch::png, as the README shows, and runs
// find_perch on it. Returns 0 when a perch is found on the file named by argv[1].
#include <perch/pli.hpp>
#include <png/png.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) return 1;
  auto png = perch::png::read_png_file(argv[1]);
  if (!png) {
    std::fprintf(stderr, "%s\n", png.error().message.c_str());
    return 2;
  }
  const perch::image<std::uint8_t> mask = perch::png::to_mask(*png);  // 1 where any sample is non-zero
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::trunk_prior{}, ws);
  if (!found) return 3;
  return found->outcome == perch::perch_outcome::found ? 0 : 4;
}
