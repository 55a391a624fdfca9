// SPDX-License-Identifier: BSL-1.0
// Reading a tree mask for the perch tool: a PNG file or standard input ("-"), binarised as
// the user said (--threshold, --invert), with warnings when it is probably not a tree mask.
#include <algorithm>
#include <array>
#include <cstdio>

#include "tool.hpp"

namespace perch::tool {
namespace {

/// Every byte of standard input.
std::string read_stdin(std::vector<std::uint8_t>& bytes) {
  std::array<std::uint8_t, 1 << 16> chunk{};
  while (true) {
    const std::size_t n = std::fread(chunk.data(), 1, chunk.size(), stdin);
    bytes.insert(bytes.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(n));
    if (n < chunk.size()) break;
  }
  if (std::ferror(stdin) != 0) return "cannot read standard input";
  return {};
}

png::png_result<png::decoded_png> read_mask_png(const std::filesystem::path& path) {
  if (path.native() != stdin_name) return png::read_png_file(path);
  std::vector<std::uint8_t> bytes;
  if (std::string e = read_stdin(bytes); !e.empty()) return png::png_error{std::move(e)};
  auto decoded = png::read_png(bytes);
  if (!decoded) return png::png_error{decoded.error().message + " (in standard input)"};
  return decoded;
}

bool has_colour(const png::decoded_png& png) {
  if (png.channels < 3) return false;
  for (int y = 0; y < png.height; ++y)
    for (int x = 0; x < png.width; ++x) {
      const std::uint16_t r = png.sample(x, y, 0);
      if (png.sample(x, y, 1) != r || png.sample(x, y, 2) != r) return true;
    }
  return false;
}

int grey_levels(const image<std::uint8_t>& gray) {
  std::array<bool, 256> seen{};
  for (int y = 0; y < gray.height(); ++y)
    for (int x = 0; x < gray.width(); ++x) seen[gray(x, y)] = true;
  return static_cast<int>(std::count(seen.begin(), seen.end(), true));
}

/// The tree pixels as the user asked: above the threshold, or any non-zero colour sample.
image<std::uint8_t> binarise(const png::decoded_png& png, const mask_reading& reading) {
  image<std::uint8_t> mask = png::to_mask(png);
  if (reading.threshold) {
    const image<std::uint8_t> gray = png::to_gray8(png);
    for (int y = 0; y < mask.height(); ++y)
      for (int x = 0; x < mask.width(); ++x) mask(x, y) = gray(x, y) > *reading.threshold ? 1 : 0;
  }
  if (reading.invert)
    for (int y = 0; y < mask.height(); ++y)
      for (int x = 0; x < mask.width(); ++x) mask(x, y) = mask(x, y) != 0 ? 0 : 1;
  return mask;
}

/// Tree pixels on each border of `mask`: top, bottom, left, right.
std::array<std::size_t, 4> border_tree_pixels(const image<std::uint8_t>& mask) {
  const int w = mask.width(), h = mask.height();
  std::array<std::size_t, 4> n{};
  for (int x = 0; x < w; ++x) {
    n[0] += mask(x, 0) != 0 ? 1u : 0u;
    n[1] += mask(x, h - 1) != 0 ? 1u : 0u;
  }
  for (int y = 0; y < h; ++y) {
    n[2] += mask(0, y) != 0 ? 1u : 0u;
    n[3] += mask(w - 1, y) != 0 ? 1u : 0u;
  }
  return n;
}

/// Why a binary mask looks inverted (tree on more than half of it, or along all four borders:
/// on more than half of each, where a tree's trunk and limbs only cross them), or an empty
/// string.
std::string inverted_sign(const image<std::uint8_t>& mask) {
  const auto w = static_cast<std::size_t>(mask.width()), h = static_cast<std::size_t>(mask.height());
  std::size_t tree = 0;
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x) tree += mask(x, y) != 0 ? 1u : 0u;
  if (2 * tree > w * h) return std::to_string(100 * tree / (w * h)) + " % of it is tree";
  const std::array<std::size_t, 4> border = border_tree_pixels(mask);
  if (2 * border[0] > w && 2 * border[1] > w && 2 * border[2] > h && 2 * border[3] > h)
    return "the tree runs along all four borders";
  return {};
}

}  // namespace

void add_mask_options(support::arg_parser& args) {
  args.add_option("threshold", "T", "tree = gray level above T (0-255; RGB as luma, 16-bit scaled to 8)");
  args.add_flag("invert", "tree = the pixels that would be background (a black tree on white)");
}

std::string read_mask_options(const support::arg_parser& args, mask_reading& reading) {
  const auto threshold = args.get_int("threshold", 0, 0, 254);
  if (!threshold) return threshold.error;
  if (args.has("threshold")) reading.threshold = static_cast<std::uint8_t>(threshold.value);
  reading.invert = args.flag("invert");
  return {};
}

std::string load_mask(const std::filesystem::path& path, const mask_reading& reading, loaded_mask& out) {
  auto png = read_mask_png(path);
  if (!png) return png.error().message;
  out.pixels = binarise(*png, reading);
  out.warnings.clear();
  if (!reading.threshold) {
    if (has_colour(*png))
      out.warnings.emplace_back("a colour image, not a tree mask: every pixel with any colour is tree; "
                                "give a mask, or --threshold T to binarise its luma");
    else if (const int levels = grey_levels(png::to_gray8(*png)); levels > 2)
      out.warnings.push_back(std::to_string(levels) + " grey levels, not 2: every non-zero pixel is tree; "
                             "give --threshold T to binarise it");
  }
  if (const std::string sign = inverted_sign(out.pixels); !sign.empty())
    out.warnings.push_back("the mask looks inverted (" + sign + "): tree must be non-zero on a zero "
                           "background; --invert flips it");
  return {};
}

void report_warnings(std::string_view command, const std::filesystem::path& path,
                     std::span<const std::string> warnings) {
  for (const std::string& w : warnings)
    std::fprintf(stderr, "perch %.*s: warning: %s: %s\n", static_cast<int>(command.size()), command.data(),
                 path.string().c_str(), w.c_str());
}

}  // namespace perch::tool
