// SPDX-License-Identifier: BSL-1.0
// site_hash: one line per mask and downscale, `name factor outcome sites hash`, where the hash (FNV-1a, 64
// bits) covers what find_perch decided: the outcome, the window counts, and every site's pixel
// and rank. Equal lines on two targets mean the same sites. Masks: synthetic trees (built here,
// integer-exact on every IEEE-754 target) and the PGM files named on the command line.
// `--pgm DIR file.png...` (host build, with the PNG reader) writes the PNGs as PGM for targets
// without zlib, then hashes them.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "support/find_perch_instances.hpp"
#include "support/synthetic_tree.hpp"
#ifdef PERCH_SITE_HASH_PNG
#include "png/png.hpp"
#endif

namespace {

struct fnv1a {
  std::uint64_t value = 0xcbf29ce484222325u;
  void add(std::uint64_t word) {
    for (int i = 0; i < 8; ++i) {
      value ^= (word >> (8 * i)) & 0xffu;
      value *= 0x100000001b3u;
    }
  }
};

/// `outcome sites hash` of one call (`error code` when it fails).
template <class Scale>
std::string hash_call(const perch::image<std::uint8_t>& mask, const Scale& scale,
                      float downscale, perch::workspace& ws) {
  perch::perch_options options;
  options.downscale = downscale;
  fnv1a h;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, scale, ws, options);
  if (!found) return "error " + std::to_string(static_cast<int>(found.error().code));
  h.add(static_cast<std::uint64_t>(found->outcome));
  h.add(found->windows);
  h.add(found->viable);
  for (const perch::perch_site& site : found->sites) {
    h.add(static_cast<std::uint32_t>(site.window.centre.x));
    h.add(static_cast<std::uint32_t>(site.window.centre.y));
    h.add(site.rank);
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h.value));
  return std::to_string(static_cast<int>(found->outcome)) + " " +
         std::to_string(found->sites.size()) + " " + hex;
}

template <class Scale>
void report(const std::string& name, const perch::image<std::uint8_t>& mask, const Scale& scale,
            perch::workspace& ws) {
  for (const float downscale : {1.0f, 0.5f})
    std::printf("%s %.1f %s\n", name.c_str(), static_cast<double>(downscale),
                hash_call(mask, scale, downscale, ws).c_str());
}

/// A binary PGM (P5, maxval 255); an empty image if the file is not one.
perch::image<std::uint8_t> read_pgm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int width = 0, height = 0, maxval = 0;
  in >> magic >> width >> height >> maxval;
  in.get();
  if (!in || magic != "P5" || width <= 0 || height <= 0 || maxval != 255) return {};
  perch::image<std::uint8_t> mask(width, height);
  for (int y = 0; y < height; ++y)
    in.read(reinterpret_cast<char*>(&mask(0, y)), width);
  return in ? mask : perch::image<std::uint8_t>{};
}

#ifdef PERCH_SITE_HASH_PNG
void write_pgm(const std::string& path, const perch::image<std::uint8_t>& mask) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << mask.width() << ' ' << mask.height() << "\n255\n";
  for (int y = 0; y < mask.height(); ++y)
    out.write(reinterpret_cast<const char*>(&mask(0, y)), mask.width());
}
#endif

std::string stem(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string file = slash == std::string::npos ? path : path.substr(slash + 1);
  return file.substr(0, file.find_last_of('.'));
}

}  // namespace

int main(int argc, char** argv) {
  perch::workspace ws;
  for (const std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    const auto noise = seed % 2 == 0 ? perch::support::tree_noise::noisy
                                     : perch::support::tree_noise::clean;
    perch::support::tree_options o = perch::support::benchmark_tree_options(800, 600, noise);
    o.seed = seed;
    report("synthetic-" + std::to_string(seed), perch::support::make_tree(o).mask,
           perch::fixed_scale{o.mm_per_px}, ws);
  }
  int first = 1;
  std::string pgm_dir;
  if (argc > 2 && std::string(argv[1]) == "--pgm") {
    pgm_dir = argv[2];
    first = 3;
  }
  int status = 0;
  for (int i = first; i < argc; ++i) {
    const std::string path = argv[i];
    perch::image<std::uint8_t> mask;
#ifdef PERCH_SITE_HASH_PNG
    if (!pgm_dir.empty()) {
      auto png = perch::png::read_png_file(path);
      if (png) {
        mask = perch::png::to_mask(*png);
        write_pgm(pgm_dir + "/" + stem(path) + ".pgm", mask);
      }
    } else {
      mask = read_pgm(path);
    }
#else
    mask = read_pgm(path);
#endif
    if (mask.width() == 0) {
      std::fprintf(stderr, "site_hash: cannot read %s\n", path.c_str());
      status = 1;
      continue;
    }
    report(stem(path), mask, perch::trunk_prior{}, ws);
  }
  return status;
}
