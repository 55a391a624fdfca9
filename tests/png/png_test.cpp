// SPDX-License-Identifier: BSL-1.0
// Tests of the tiny PNG reader and writer (examples/png/png/png.hpp).
//
// Hand-made PNGs are built here with an independent, obviously-correct encoder (zlib's crc32
// and compress2, the Adam7 passes as loops over the spec's table, the five filters written
// from the spec's formulas), so decoding is checked against known pixel values and not against
// the writer under test.
#include "png/png.hpp"

#include <doctest/doctest.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace png = perch::png;

namespace {

using bytes = std::vector<std::uint8_t>;

// ---------------------------------------------------------------------------------------------
// An independent PNG builder.

void put32(bytes& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24U));
  out.push_back(static_cast<std::uint8_t>(v >> 16U));
  out.push_back(static_cast<std::uint8_t>(v >> 8U));
  out.push_back(static_cast<std::uint8_t>(v));
}

std::uint32_t get32(const bytes& b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24U) | (std::uint32_t{b[at + 1]} << 16U) |
         (std::uint32_t{b[at + 2]} << 8U) | std::uint32_t{b[at + 3]};
}

// One chunk, its CRC computed by zlib (independent of perch's table).
void put_chunk(bytes& out, std::string_view type, const bytes& data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  bytes typed(type.begin(), type.end());
  typed.insert(typed.end(), data.begin(), data.end());
  out.insert(out.end(), typed.begin(), typed.end());
  put32(out,
        static_cast<std::uint32_t>(::crc32(0L, typed.data(), static_cast<uInt>(typed.size()))));
}

bytes signature() { return {137, 80, 78, 71, 13, 10, 26, 10}; }

bytes ihdr_data(std::uint32_t w, std::uint32_t h, int depth, int colour, int interlaced,
                int compression = 0, int filter = 0) {
  bytes d;
  put32(d, w);
  put32(d, h);
  d.push_back(static_cast<std::uint8_t>(depth));
  d.push_back(static_cast<std::uint8_t>(colour));
  d.push_back(static_cast<std::uint8_t>(compression));
  d.push_back(static_cast<std::uint8_t>(filter));
  d.push_back(static_cast<std::uint8_t>(interlaced));
  return d;
}

bytes zlib_compress(const bytes& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  bytes out(size);
  REQUIRE(compress2(out.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 9) == Z_OK);
  out.resize(size);
  return out;
}

int samples_of(int colour) {
  switch (colour) {
    case 2:
      return 3;
    case 4:
      return 2;
    case 6:
      return 4;
    default:
      return 1;
  }
}

int paeth_reference(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a);
  const int pb = std::abs(p - b);
  const int pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  if (pb <= pc) return b;
  return c;
}

// Filters `row` with `type` given the previous (unfiltered) row, bpp bytes per complete pixel.
bytes filter_reference(int type, const bytes& row, const bytes& prev, int bpp) {
  bytes out(row.size());
  for (std::size_t i = 0; i < row.size(); ++i) {
    const bool has_left = i >= static_cast<std::size_t>(bpp);
    const int a = has_left ? row[i - static_cast<std::size_t>(bpp)] : 0;
    const int b = prev.empty() ? 0 : prev[i];
    const int c = has_left && !prev.empty() ? prev[i - static_cast<std::size_t>(bpp)] : 0;
    int predictor = 0;
    if (type == 1) predictor = a;
    if (type == 2) predictor = b;
    if (type == 3) predictor = (a + b) / 2;
    if (type == 4) predictor = paeth_reference(a, b, c);
    out[i] = static_cast<std::uint8_t>((row[i] - predictor) & 0xFF);
  }
  return out;
}

// The file's samples of a test image: w × h pixels × samples_of(colour), values < 2^depth
// (palette: indices).
struct test_image {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int depth = 8;
  int colour = 0;
  int interlaced = 0;
  std::vector<std::uint32_t> samples;
  std::vector<std::array<std::uint8_t, 3>> palette;
};

// Packs row pixels (x positions `xs` of row y) MSB first into bytes, as PNG spec §7.2 says.
bytes pack_row(const test_image& img, std::uint32_t y, const std::vector<std::uint32_t>& xs) {
  const int n = samples_of(img.colour);
  bytes out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const std::uint32_t x : xs) {
    for (int c = 0; c < n; ++c) {
      const std::uint32_t v =
          img.samples[(std::size_t{y} * img.width + x) * static_cast<std::size_t>(n) +
                      static_cast<std::size_t>(c)];
      if (img.depth == 16) {
        out.push_back(static_cast<std::uint8_t>(v >> 8U));
        out.push_back(static_cast<std::uint8_t>(v & 0xFFU));
      } else if (img.depth == 8) {
        out.push_back(static_cast<std::uint8_t>(v));
      } else {
        acc = (acc << static_cast<unsigned>(img.depth)) | v;
        bits += img.depth;
        if (bits == 8) {
          out.push_back(static_cast<std::uint8_t>(acc));
          acc = 0;
          bits = 0;
        }
      }
    }
  }
  if (bits > 0) out.push_back(static_cast<std::uint8_t>(acc << static_cast<unsigned>(8 - bits)));
  return out;
}

struct pass_spec {
  std::uint32_t x0, y0, dx, dy;
};
constexpr std::array<pass_spec, 7> adam7{{
    {0, 0, 8, 8},
    {4, 0, 8, 8},
    {0, 4, 4, 8},
    {2, 0, 4, 4},
    {0, 2, 2, 4},
    {1, 0, 2, 2},
    {0, 1, 1, 2},
}};

// The filtered scanlines of `img`; row k of the whole file uses filter type (k + shift) % 5, so
// every filter type occurs (or type `fixed` for every row when fixed >= 0).
bytes scanlines(const test_image& img, int shift = 0, int fixed = -1) {
  std::vector<pass_spec> passes;
  if (img.interlaced != 0)
    passes.assign(adam7.begin(), adam7.end());
  else
    passes.push_back({0, 0, 1, 1});
  const int bpp = std::max(1, samples_of(img.colour) * img.depth / 8);
  bytes out;
  int k = shift;
  for (const pass_spec& p : passes) {
    std::vector<std::uint32_t> xs;
    for (std::uint32_t x = p.x0; x < img.width; x += p.dx) xs.push_back(x);
    if (xs.empty()) continue;
    bytes prev;
    for (std::uint32_t y = p.y0; y < img.height; y += p.dy) {
      const bytes row = pack_row(img, y, xs);
      const int type = fixed >= 0 ? fixed : k % 5;
      ++k;
      out.push_back(static_cast<std::uint8_t>(type));
      const bytes f = filter_reference(type, row, prev, bpp);
      out.insert(out.end(), f.begin(), f.end());
      prev = row;
    }
  }
  return out;
}

// A whole file: IHDR, optional PLTE, an ancillary tEXt, IDAT split into `idat_pieces`, IEND.
bytes build_png(const test_image& img, const bytes& raw, int idat_pieces = 1) {
  bytes out = signature();
  put_chunk(out, "IHDR", ihdr_data(img.width, img.height, img.depth, img.colour, img.interlaced));
  put_chunk(out, "tEXt", bytes{'C', 'o', 'm', 'm', 'e', 'n', 't', 0, 'h', 'i'});
  if (!img.palette.empty()) {
    bytes plte;
    for (const auto& e : img.palette) plte.insert(plte.end(), e.begin(), e.end());
    put_chunk(out, "PLTE", plte);
    put_chunk(out, "tRNS", bytes{0, 128});
  }
  const bytes z = zlib_compress(raw);
  const std::size_t piece =
      std::max<std::size_t>(1, (z.size() + static_cast<std::size_t>(idat_pieces) - 1) /
                                   static_cast<std::size_t>(idat_pieces));
  for (std::size_t at = 0; at < z.size(); at += piece)
    put_chunk(out, "IDAT",
              bytes(z.begin() + static_cast<std::ptrdiff_t>(at),
                    z.begin() + static_cast<std::ptrdiff_t>(std::min(z.size(), at + piece))));
  put_chunk(out, "IEND", {});
  return out;
}

test_image random_image(std::uint32_t w, std::uint32_t h, int depth, int colour, int interlaced,
                        std::mt19937& rng) {
  test_image img{w, h, depth, colour, interlaced, {}, {}};
  std::uint32_t limit = (1U << static_cast<unsigned>(depth)) - 1U;
  if (colour == 3) {
    const std::uint32_t entries = depth == 8 ? 200U : limit + 1U;
    for (std::uint32_t i = 0; i < entries; ++i)
      img.palette.push_back({static_cast<std::uint8_t>(rng() & 0xFFU),
                             static_cast<std::uint8_t>(rng() & 0xFFU),
                             static_cast<std::uint8_t>(rng() & 0xFFU)});
    limit = entries - 1U;
  }
  const std::size_t n = std::size_t{w} * h * static_cast<std::size_t>(samples_of(colour));
  std::uniform_int_distribution<std::uint32_t> dist(0, limit);
  for (std::size_t i = 0; i < n; ++i) img.samples.push_back(dist(rng));
  return img;
}

// Expected decoded sample c of pixel (x, y), by the documented rules.
std::uint32_t expected_sample(const test_image& img, std::uint32_t x, std::uint32_t y, int c) {
  const auto n = static_cast<std::size_t>(samples_of(img.colour));
  const std::size_t base = (std::size_t{y} * img.width + x) * n;
  if (img.colour == 3) return img.palette[img.samples[base]][static_cast<std::size_t>(c)];
  const std::uint32_t v = img.samples[base + static_cast<std::size_t>(c)];
  if (img.depth < 8) return v * (255U / ((1U << static_cast<unsigned>(img.depth)) - 1U));
  return v;
}

void check_decoded(const test_image& img, const png::decoded_png& d) {
  REQUIRE(d.width == static_cast<int>(img.width));
  REQUIRE(d.height == static_cast<int>(img.height));
  REQUIRE(d.channels == (img.colour == 3 ? 3 : samples_of(img.colour)));
  REQUIRE(d.bit_depth == (img.depth == 16 ? 16 : 8));
  CHECK(d.source_bit_depth == img.depth);
  CHECK(static_cast<int>(d.source_colour_type) == img.colour);
  CHECK(static_cast<int>(d.source_interlace) == img.interlaced);
  int mismatches = 0;
  for (std::uint32_t y = 0; y < img.height; ++y)
    for (std::uint32_t x = 0; x < img.width; ++x)
      for (int c = 0; c < d.channels; ++c)
        if (d.sample(static_cast<int>(x), static_cast<int>(y), c) != expected_sample(img, x, y, c))
          ++mismatches;
  CHECK(mismatches == 0);
}

// Decoding must fail and the message must contain `needle`.
void check_rejected(const bytes& file, std::string_view needle) {
  const auto r = png::read_png(file);
  REQUIRE_FALSE(r.has_value());
  const std::string& m = r.error().message;
  INFO("message: ", m);
  CHECK_FALSE(m.empty());
  CHECK(m.find(needle) != std::string::npos);
}

// A small valid file for the corruption tests: 5 × 4 RGB, interlaced, several IDAT.
bytes small_valid_file() {
  std::mt19937 rng(7);
  const test_image img = random_image(5, 4, 8, 2, 1, rng);
  return build_png(img, scanlines(img), 3);
}

struct chunk_ref {
  std::size_t at;  // offset of the length field
  std::string type;
  std::uint32_t length;
};

std::vector<chunk_ref> list_chunks(const bytes& file) {
  std::vector<chunk_ref> out;
  std::size_t at = 8;
  while (at + 12 <= file.size()) {
    const std::uint32_t len = get32(file, at);
    out.push_back({at,
                   std::string(file.begin() + static_cast<std::ptrdiff_t>(at + 4),
                               file.begin() + static_cast<std::ptrdiff_t>(at + 8)),
                   len});
    at += 12 + len;
  }
  return out;
}

// Recomputes every chunk's CRC (after a test edited chunk data on purpose).
void fix_crcs(bytes& file) {
  for (const chunk_ref& c : list_chunks(file)) {
    if (c.at + 12 + c.length > file.size()) break;
    const auto crc = static_cast<std::uint32_t>(
        ::crc32(0L, file.data() + c.at + 4, static_cast<uInt>(c.length + 4)));
    for (int i = 0; i < 4; ++i)
      file[c.at + 8 + c.length + static_cast<std::size_t>(i)] =
          static_cast<std::uint8_t>(crc >> static_cast<unsigned>(24 - 8 * i));
  }
}

// Concatenates chunks: each given as (type, data).
bytes assemble(const std::vector<std::pair<std::string, bytes>>& chunks) {
  bytes out = signature();
  for (const auto& [type, data] : chunks) put_chunk(out, type, data);
  return out;
}

// The raw scanlines (filter byte 0) of a w × h 8-bit gray image of zeros.
bytes zero_gray_raw(std::uint32_t w, std::uint32_t h) {
  return bytes(static_cast<std::size_t>(h) * (w + 1U), 0);
}

}  // namespace

// =============================================================================================

TEST_CASE("png crc32: the spec's table matches known values and zlib") {
  const std::string_view iend = "IEND";
  const bytes b(iend.begin(), iend.end());
  CHECK(png::crc32(b) == 0xAE426082U);
  CHECK(png::crc32({}) == 0U);
  const std::string_view check = "123456789";
  CHECK(png::crc32(bytes(check.begin(), check.end())) == 0xCBF43926U);
  std::mt19937 rng(1);
  bytes data(1000);
  for (auto& v : data) v = static_cast<std::uint8_t>(rng() & 0xFFU);
  CHECK(png::crc32(data) == ::crc32(0L, data.data(), static_cast<uInt>(data.size())));
  const std::span<const std::uint8_t> all(data);
  CHECK(png::crc32_update(png::crc32(all.first(300)), all.subspan(300)) == png::crc32(all));
}

TEST_CASE("png read: every colour type and bit depth, plain and Adam7, odd sizes") {
  struct combo {
    int colour;
    int depth;
  };
  const std::array<combo, 15> combos{{{0, 1},
                                      {0, 2},
                                      {0, 4},
                                      {0, 8},
                                      {0, 16},
                                      {2, 8},
                                      {2, 16},
                                      {3, 1},
                                      {3, 2},
                                      {3, 4},
                                      {3, 8},
                                      {4, 8},
                                      {4, 16},
                                      {6, 8},
                                      {6, 16}}};
  const std::array<std::array<std::uint32_t, 2>, 12> sizes{{{1, 1},
                                                            {1, 7},
                                                            {7, 1},
                                                            {2, 2},
                                                            {3, 5},
                                                            {5, 3},
                                                            {8, 8},
                                                            {9, 9},
                                                            {13, 5},
                                                            {17, 3},
                                                            {33, 2},
                                                            {4, 11}}};
  std::mt19937 rng(2024);
  int decoded = 0;
  for (const combo& cb : combos)
    for (int interlaced = 0; interlaced <= 1; ++interlaced)
      for (const auto& s : sizes) {
        CAPTURE(cb.colour);
        CAPTURE(cb.depth);
        CAPTURE(interlaced);
        CAPTURE(s[0]);
        CAPTURE(s[1]);
        const test_image img = random_image(s[0], s[1], cb.depth, cb.colour, interlaced, rng);
        const int shift = static_cast<int>(rng() % 5U);
        const int pieces = 1 + static_cast<int>(rng() % 4U);
        const auto r = png::read_png(build_png(img, scanlines(img, shift), pieces));
        if (!r) FAIL(r.error().message);
        check_decoded(img, *r);
        ++decoded;
      }
  CHECK(decoded == 15 * 2 * 12);
}

TEST_CASE("png read: each of the five filter types alone, on every row") {
  std::mt19937 rng(5);
  for (int type = 0; type <= 4; ++type)
    for (int colour : {0, 2, 6})
      for (int depth : {8, 16}) {
        CAPTURE(type);
        CAPTURE(colour);
        CAPTURE(depth);
        const test_image img = random_image(11, 7, depth, colour, 0, rng);
        const auto r = png::read_png(build_png(img, scanlines(img, 0, type)));
        REQUIRE(r.has_value());
        check_decoded(img, *r);
      }
}

TEST_CASE("png read: IDAT split into one-byte chunks, ancillary chunks skipped") {
  std::mt19937 rng(6);
  const test_image img = random_image(6, 5, 4, 3, 1, rng);
  const bytes raw = scanlines(img);
  const auto r = png::read_png(build_png(img, raw, 10000));
  REQUIRE(r.has_value());
  check_decoded(img, *r);
}

TEST_CASE("png read: known pixel values of 1-bit gray and palette") {
  // 10 × 2, 1-bit gray: row 0 = 1010110000, row 1 = 0000000001.
  test_image img{10, 2, 1, 0, 0, {1, 0, 1, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}, {}};
  bytes raw{0, 0b10101100, 0b00000000, 0, 0b00000000, 0b01000000};
  CHECK(raw == scanlines(img, 0, 0));
  const auto r = png::read_png(build_png(img, raw));
  REQUIRE(r.has_value());
  CHECK(r->sample(0, 0, 0) == 255);
  CHECK(r->sample(1, 0, 0) == 0);
  CHECK(r->sample(5, 0, 0) == 255);
  CHECK(r->sample(9, 1, 0) == 255);
  const auto mask = png::to_mask(*r);
  CHECK(mask(0, 0) == 1);
  CHECK(mask(1, 0) == 0);
  CHECK(mask(9, 1) == 1);
  CHECK(mask(8, 1) == 0);

  // 3 × 1, 2-bit palette: indices 2, 0, 1.
  test_image pal{3, 1, 2, 3, 0, {2, 0, 1}, {{{10, 20, 30}}, {{40, 50, 60}}, {{70, 80, 90}}}};
  const auto p = png::read_png(build_png(pal, bytes{0, 0b10000100}));
  REQUIRE(p.has_value());
  CHECK(p->channels == 3);
  CHECK(png::to_rgb8(*p)(0, 0) == png::rgb8{70, 80, 90});
  CHECK(png::to_rgb8(*p)(1, 0) == png::rgb8{10, 20, 30});
  CHECK(png::to_rgb8(*p)(2, 0) == png::rgb8{40, 50, 60});
}

TEST_CASE("png read: Adam7 on sizes smaller than the 8 × 8 tile leaves passes empty") {
  std::mt19937 rng(8);
  for (std::uint32_t w = 1; w <= 9; ++w)
    for (std::uint32_t h = 1; h <= 9; ++h) {
      const test_image img = random_image(w, h, 8, 0, 1, rng);
      const auto r = png::read_png(build_png(img, scanlines(img)));
      REQUIRE(r.has_value());
      check_decoded(img, *r);
    }
}

// =============================================================================================
// Converters.

TEST_CASE("png converters: gray8, mask, gray16, rgb8") {
  // RGB 8-bit: red, green, blue, black.
  test_image rgb{4, 1, 8, 2, 0, {255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 0, 0}, {}};
  const auto r = png::read_png(build_png(rgb, scanlines(rgb)));
  REQUIRE(r.has_value());
  const auto g8 = png::to_gray8(*r);
  CHECK(g8(0, 0) == 76);   // (299·255 + 500) / 1000
  CHECK(g8(1, 0) == 150);  // (587·255 + 500) / 1000
  CHECK(g8(2, 0) == 29);   // (114·255 + 500) / 1000
  CHECK(g8(3, 0) == 0);
  const auto m = png::to_mask(*r);
  CHECK(m(0, 0) == 1);
  CHECK(m(2, 0) == 1);
  CHECK(m(3, 0) == 0);
  CHECK(png::to_rgb8(*r)(1, 0) == png::rgb8{0, 255, 0});
  CHECK(png::to_gray16(*r)(0, 0) == 76);

  // Gray+alpha: alpha is ignored everywhere.
  test_image ga{2, 1, 8, 4, 0, {0, 255, 9, 0}, {}};
  const auto a = png::read_png(build_png(ga, scanlines(ga)));
  REQUIRE(a.has_value());
  CHECK(png::to_mask(*a)(0, 0) == 0);
  CHECK(png::to_mask(*a)(1, 0) == 1);
  CHECK(png::to_gray8(*a)(1, 0) == 9);
  CHECK(png::to_rgb8(*a)(1, 0) == png::rgb8{9, 9, 9});

  // 16-bit gray: depth in mm kept, scaled for gray8.
  test_image d{3, 1, 16, 0, 0, {0, 1234, 65535}, {}};
  const auto dr = png::read_png(build_png(d, scanlines(d)));
  REQUIRE(dr.has_value());
  const auto g16 = png::to_gray16(*dr);
  CHECK(g16(1, 0) == 1234);
  CHECK(g16(2, 0) == 65535);
  CHECK(png::to_gray8(*dr)(2, 0) == 255);
  CHECK(png::to_gray8(*dr)(1, 0) == 5);  // 1234·255/65535 = 4.8
  CHECK(png::to_mask(*dr)(1, 0) == 1);
  CHECK(png::to_mask(*dr)(0, 0) == 0);

  // 8-bit gray promoted unchanged to 16 bits.
  test_image g{2, 1, 8, 0, 0, {7, 200}, {}};
  const auto gr = png::read_png(build_png(g, scanlines(g)));
  REQUIRE(gr.has_value());
  CHECK(png::to_gray16(*gr)(1, 0) == 200);

  // An empty decoded image converts to empty images.
  CHECK(png::to_gray8(png::decoded_png{}).width() == 0);
}

// =============================================================================================
// Round trips through the writer.

TEST_CASE("png round trip: gray8, rgb8, gray16 at odd sizes, both filter choices") {
  std::mt19937 rng(99);
  const std::array<std::array<int, 2>, 8> sizes{
      {{1, 1}, {1, 13}, {13, 1}, {2, 3}, {7, 5}, {64, 3}, {3, 64}, {131, 37}}};
  for (const png::filter_choice filter :
       {png::filter_choice::none, png::filter_choice::minimum_sum})
    for (const auto& s : sizes) {
      CAPTURE(s[0]);
      CAPTURE(s[1]);
      const png::write_options opt{.filter = filter};
      perch::image<std::uint8_t> g(s[0], s[1]);
      perch::image<png::rgb8> c(s[0], s[1]);
      perch::image<std::uint16_t> d(s[0], s[1]);
      for (int y = 0; y < s[1]; ++y)
        for (int x = 0; x < s[0]; ++x) {
          // Smooth plus noise, so several filter types win.
          g(x, y) =
              static_cast<std::uint8_t>((x * 3 + y * 5 + static_cast<int>(rng() % 4U)) & 0xFF);
          c(x, y) = {static_cast<std::uint8_t>(rng() & 0xFFU), static_cast<std::uint8_t>(x),
                     static_cast<std::uint8_t>(y)};
          d(x, y) = static_cast<std::uint16_t>(rng() & 0xFFFFU);
        }
      const auto eg = png::encode_png(g, opt);
      const auto ec = png::encode_png(c, opt);
      const auto ed = png::encode_png(d, opt);
      REQUIRE(eg.has_value());
      REQUIRE(ec.has_value());
      REQUIRE(ed.has_value());
      const auto rg = png::read_png(*eg);
      const auto rc = png::read_png(*ec);
      const auto rd = png::read_png(*ed);
      REQUIRE(rg.has_value());
      REQUIRE(rc.has_value());
      REQUIRE(rd.has_value());
      CHECK(rg->channels == 1);
      CHECK(rg->bit_depth == 8);
      CHECK(rc->channels == 3);
      CHECK(rd->bit_depth == 16);
      const auto bg = png::to_gray8(*rg);
      const auto bc = png::to_rgb8(*rc);
      const auto bd = png::to_gray16(*rd);
      int bad = 0;
      for (int y = 0; y < s[1]; ++y)
        for (int x = 0; x < s[0]; ++x)
          bad += (bg(x, y) != g(x, y)) + (bc(x, y) != c(x, y)) + (bd(x, y) != d(x, y));
      CHECK(bad == 0);
    }
}

TEST_CASE("png write: a strided view encodes like its dense copy, deterministically") {
  std::mt19937 rng(3);
  perch::image<std::uint8_t> big(40, 30);
  perch::image<std::uint16_t> big16(40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      big(x, y) = static_cast<std::uint8_t>(rng() & 0xFFU);
      big16(x, y) = static_cast<std::uint16_t>(rng() & 0xFFFFU);
    }
  const auto sub = big.view().sub_view(3, 2, 17, 11);
  const auto sub16 = big16.view().sub_view(5, 1, 1, 29);
  REQUIRE(sub.stride() == 40);
  perch::image<std::uint8_t> dense(17, 11);
  perch::image<std::uint16_t> dense16(1, 29);
  perch::copy(sub, dense.view());
  perch::copy(sub16, dense16.view());
  const auto a = png::encode_png(perch::image_view<const std::uint8_t>(sub));
  const auto b = png::encode_png(dense);
  const auto b2 = png::encode_png(dense);
  REQUIRE(a.has_value());
  REQUIRE(b.has_value());
  CHECK(*a == *b);
  CHECK(*b == *b2);
  const auto a16 = png::encode_png(perch::image_view<const std::uint16_t>(sub16));
  REQUIRE(a16.has_value());
  CHECK(*a16 == *png::encode_png(dense16));
  const auto back = png::read_png(*a);
  REQUIRE(back.has_value());
  const auto img = png::to_gray8(*back);
  int bad = 0;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 17; ++x) bad += img(x, y) != sub(x, y);
  CHECK(bad == 0);
}

TEST_CASE("png write: minimum_sum uses several filter types, none uses only type 0") {
  perch::image<std::uint8_t> g(50, 40);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 50; ++x)
      g(x, y) = static_cast<std::uint8_t>(y < 10 ? x * 5 : y < 20 ? y * 6 : y < 30 ? (x * y) : 77);
  auto filter_types = [](const bytes& file) {
    bytes z;
    for (const chunk_ref& c : list_chunks(file))
      if (c.type == "IDAT")
        z.insert(z.end(), file.begin() + static_cast<std::ptrdiff_t>(c.at + 8),
                 file.begin() + static_cast<std::ptrdiff_t>(c.at + 8 + c.length));
    bytes raw(40 * 51);
    uLongf size = static_cast<uLongf>(raw.size());
    REQUIRE(uncompress(raw.data(), &size, z.data(), static_cast<uLong>(z.size())) == Z_OK);
    REQUIRE(size == raw.size());
    std::array<int, 5> seen{};
    for (std::size_t y = 0; y < 40; ++y) {
      REQUIRE(raw[y * 51] <= 4);
      ++seen[raw[y * 51]];
    }
    return seen;
  };
  const auto adaptive = filter_types(*png::encode_png(g));
  int kinds = 0;
  for (const int n : adaptive) kinds += n > 0;
  CHECK(kinds >= 2);
  const auto plain = filter_types(*png::encode_png(g, {.filter = png::filter_choice::none}));
  CHECK(plain[0] == 40);
}

TEST_CASE("png write: invalid views are refused with a message") {
  const std::uint8_t px[4] = {1, 2, 3, 4};
  const auto empty = png::encode_png(perch::image_view<const std::uint8_t>(px, 0, 2));
  REQUIRE_FALSE(empty.has_value());
  CHECK(empty.error().message.find("zero") != std::string::npos);
  const auto stride = png::encode_png(perch::image_view<const std::uint8_t>(px, 2, 2, 1));
  REQUIRE_FALSE(stride.has_value());
  CHECK(stride.error().message.find("stride") != std::string::npos);
  const auto null = png::encode_png(perch::image_view<const std::uint8_t>(nullptr, 2, 2));
  REQUIRE_FALSE(null.has_value());
  CHECK(null.error().message.find("null") != std::string::npos);
  // More than 2^28 pixels: refused before any pixel is read.
  const auto huge = png::encode_png(perch::image_view<const std::uint8_t>(px, 1 << 15, 1 << 14, 0));
  REQUIRE_FALSE(huge.has_value());
  CHECK_FALSE(huge.error().message.empty());
  const auto huge2 = png::encode_png(
      perch::image_view<const std::uint8_t>(px, 1 << 15, 1 << 14, std::ptrdiff_t{1} << 15));
  REQUIRE_FALSE(huge2.has_value());
  CHECK(huge2.error().message.find("too large") != std::string::npos);
}

TEST_CASE("png files: write then read; missing files and directories are reported") {
  const auto dir = std::filesystem::temp_directory_path() / "perch_png_test";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  REQUIRE_FALSE(ec);
  perch::image<png::rgb8> c(5, 3, png::rgb8{1, 2, 3});
  c(4, 2) = {200, 100, 50};
  perch::image<std::uint8_t> g(3, 5, 9);
  perch::image<std::uint16_t> d(2, 2, 4000);
  REQUIRE(png::write_png(dir / "c.png", c).has_value());
  REQUIRE(png::write_png(dir / "g.png", g).has_value());
  REQUIRE(png::write_png(dir / "d.png", d).has_value());
  const auto rc = png::read_png_file(dir / "c.png");
  const auto rg = png::read_png_file(dir / "g.png");
  const auto rd = png::read_png_file(dir / "d.png");
  REQUIRE(rc.has_value());
  REQUIRE(rg.has_value());
  REQUIRE(rd.has_value());
  CHECK(png::to_rgb8(*rc)(4, 2) == png::rgb8{200, 100, 50});
  CHECK(png::to_gray8(*rg)(2, 4) == 9);
  CHECK(png::to_gray16(*rd)(1, 1) == 4000);

  const auto missing = png::read_png_file(dir / "no_such_file.png");
  REQUIRE_FALSE(missing.has_value());
  CHECK(missing.error().message.find("no_such_file.png") != std::string::npos);
  const auto unwritable = png::write_png(dir / "no_such_dir" / "x.png", g);
  REQUIRE_FALSE(unwritable.has_value());
  CHECK(unwritable.error().message.find("no_such_dir") != std::string::npos);

  // A corrupt file on disk: the message names the problem and the file.
  bytes file = *png::encode_png(g);
  file[file.size() - 1] ^= 1U;
  {
    std::FILE* f = std::fopen((dir / "bad.png").string().c_str(), "wb");
    REQUIRE(f != nullptr);
    CHECK(std::fwrite(file.data(), 1, file.size(), f) == file.size());
    CHECK(std::fclose(f) == 0);
  }
  const auto bad = png::read_png_file(dir / "bad.png");
  REQUIRE_FALSE(bad.has_value());
  CHECK(bad.error().message.find("CRC") != std::string::npos);
  CHECK(bad.error().message.find("bad.png") != std::string::npos);
  std::filesystem::remove_all(dir, ec);
}

// =============================================================================================
// Corrupt files: every case is an error with a message naming the problem, never a crash.

TEST_CASE("png corrupt: truncation at every byte offset is reported as truncated") {
  const bytes file = small_valid_file();
  REQUIRE(png::read_png(file).has_value());
  for (std::size_t n = 0; n < file.size(); ++n) {
    CAPTURE(n);
    check_rejected(bytes(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(n)), "truncated");
  }
}

TEST_CASE("png corrupt: flipping any single byte is detected") {
  const bytes file = small_valid_file();
  for (std::size_t i = 0; i < file.size(); ++i)
    for (const std::uint8_t flip : {std::uint8_t{0x01}, std::uint8_t{0x80}, std::uint8_t{0xFF}}) {
      CAPTURE(i);
      CAPTURE(int{flip});
      bytes bad = file;
      bad[i] ^= flip;
      const auto r = png::read_png(bad);
      REQUIRE_FALSE(r.has_value());
      CHECK_FALSE(r.error().message.empty());
    }
}

TEST_CASE("png corrupt: not a PNG, and a bad CRC") {
  check_rejected({}, "signature");
  check_rejected(bytes{'G', 'I', 'F', '8', '9', 'a', 0, 0, 0, 0, 0, 0}, "signature");
  bytes file = small_valid_file();
  file[8 + 8 + 13] ^= 0x10U;  // the IHDR CRC
  check_rejected(file, "CRC");
  bytes data_flip = small_valid_file();
  data_flip[8 + 8 + 3] ^= 0x01U;  // IHDR width: covered by the CRC
  check_rejected(data_flip, "bad CRC");
}

TEST_CASE("png corrupt: wrong chunk order") {
  const bytes ihdr = ihdr_data(2, 2, 8, 0, 0);
  const bytes z = zlib_compress(zero_gray_raw(2, 2));
  const bytes plte{1, 2, 3};
  // The valid reference file.
  REQUIRE(png::read_png(assemble({{"IHDR", ihdr}, {"IDAT", z}, {"IEND", {}}})).has_value());
  check_rejected(assemble({{"IDAT", z}, {"IHDR", ihdr}, {"IEND", {}}}), "IHDR");
  check_rejected(assemble({{"IDAT", z}, {"IHDR", ihdr}, {"IEND", {}}}), "order");
  check_rejected(assemble({{"IHDR", ihdr}, {"IHDR", ihdr}, {"IDAT", z}, {"IEND", {}}}), "order");
  const bytes first(z.begin(), z.begin() + 4);
  const bytes rest(z.begin() + 4, z.end());
  check_rejected(
      assemble({{"IHDR", ihdr}, {"IDAT", first}, {"tEXt", {'a', 0}}, {"IDAT", rest}, {"IEND", {}}}),
      "consecutive");
  check_rejected(assemble({{"IHDR", ihdr}, {"IEND", {}}}), "IDAT");
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", z}}), "IEND");
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", z}, {"IEND", {1}}}), "IEND");
  // Palette images: PLTE is required before IDAT, once.
  const bytes pihdr = ihdr_data(2, 2, 8, 3, 0);
  REQUIRE(png::read_png(assemble({{"IHDR", pihdr}, {"PLTE", plte}, {"IDAT", z}, {"IEND", {}}}))
              .has_value());
  check_rejected(assemble({{"IHDR", pihdr}, {"IDAT", z}, {"IEND", {}}}), "PLTE");
  check_rejected(assemble({{"IHDR", pihdr}, {"IDAT", z}, {"PLTE", plte}, {"IEND", {}}}), "PLTE");
  check_rejected(
      assemble({{"IHDR", pihdr}, {"PLTE", plte}, {"PLTE", plte}, {"IDAT", z}, {"IEND", {}}}),
      "duplicate");
  check_rejected(assemble({{"IHDR", pihdr}, {"PLTE", {1, 2}}, {"IDAT", z}, {"IEND", {}}}), "PLTE");
  check_rejected(assemble({{"IHDR", ihdr}, {"PLTE", plte}, {"IDAT", z}, {"IEND", {}}}), "gray");
  // Unknown critical chunks are refused, unknown ancillary ones skipped.
  check_rejected(assemble({{"IHDR", ihdr}, {"ABCD", {}}, {"IDAT", z}, {"IEND", {}}}), "critical");
  CHECK(png::read_png(assemble({{"IHDR", ihdr}, {"abCD", {9}}, {"IDAT", z}, {"IEND", {}}}))
            .has_value());
  // A chunk type that is not letters.
  check_rejected(assemble({{"IHDR", ihdr}, {"ab1D", {}}, {"IDAT", z}, {"IEND", {}}}), "letters");
}

TEST_CASE("png corrupt: zero and huge declared sizes, rejected before allocation") {
  const bytes z = zlib_compress(zero_gray_raw(1, 1));
  check_rejected(assemble({{"IHDR", ihdr_data(0, 5, 8, 0, 0)}, {"IDAT", z}, {"IEND", {}}}), "zero");
  check_rejected(assemble({{"IHDR", ihdr_data(5, 0, 8, 0, 0)}, {"IDAT", z}, {"IEND", {}}}), "zero");
  check_rejected(assemble({{"IHDR", ihdr_data(65536, 65536, 8, 6, 0)}, {"IDAT", z}, {"IEND", {}}}),
                 "too large");
  check_rejected(
      assemble({{"IHDR", ihdr_data(0xFFFFFFFFU, 1, 8, 0, 0)}, {"IDAT", z}, {"IEND", {}}}), "2^31");
  check_rejected(assemble({{"IHDR", ihdr_data(16385, 16384, 8, 0, 0)}, {"IDAT", z}, {"IEND", {}}}),
                 "too large");
  // Exactly 2^28 pixels is allowed, but the tiny stream is far too short; the reader fails on
  // the data, having grown its buffer only to what was decompressed.
  check_rejected(assemble({{"IHDR", ihdr_data(16384, 16384, 16, 6, 1)}, {"IDAT", z}, {"IEND", {}}}),
                 "too short");
  // A caller's lower limit.
  const bytes small = assemble({{"IHDR", ihdr_data(100, 100, 8, 0, 0)}, {"IDAT", z}, {"IEND", {}}});
  const auto limited = png::read_png(small, {.max_pixels = 9999});
  REQUIRE_FALSE(limited.has_value());
  CHECK(limited.error().message.find("too large") != std::string::npos);
  // A chunk length above 2^31-1.
  bytes long_chunk = signature();
  put32(long_chunk, 0x80000000U);
  for (const char c : std::string_view("IHDR")) long_chunk.push_back(static_cast<std::uint8_t>(c));
  long_chunk.resize(long_chunk.size() + 20, 0);
  check_rejected(long_chunk, "2^31");
}

TEST_CASE("png corrupt: bad header fields") {
  const bytes z = zlib_compress(zero_gray_raw(2, 2));
  auto with = [&](const bytes& ihdr) {
    return assemble({{"IHDR", ihdr}, {"IDAT", z}, {"IEND", {}}});
  };
  struct bad {
    int depth, colour;
  };
  for (const bad b : {bad{3, 0}, bad{16, 3}, bad{4, 2}, bad{1, 6}, bad{2, 4}, bad{0, 0}, bad{32, 0},
                      bad{8, 1}, bad{8, 5}, bad{8, 7}}) {
    CAPTURE(b.depth);
    CAPTURE(b.colour);
    check_rejected(with(ihdr_data(2, 2, b.depth, b.colour, 0)),
                   b.colour == 1 || b.colour == 5 || b.colour == 7 ? "colour type" : "bit depth");
  }
  check_rejected(with(ihdr_data(2, 2, 8, 0, 0, 1)), "compression");
  check_rejected(with(ihdr_data(2, 2, 8, 0, 0, 0, 1)), "filter method");
  check_rejected(with(ihdr_data(2, 2, 8, 0, 2)), "interlace");
  bytes short_ihdr = ihdr_data(2, 2, 8, 0, 0);
  short_ihdr.pop_back();
  check_rejected(with(short_ihdr), "13");
}

TEST_CASE("png corrupt: bad zlib stream, too little and too much data") {
  const bytes ihdr = ihdr_data(3, 3, 8, 0, 0);
  const bytes good_raw = zero_gray_raw(3, 3);
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", {1, 2, 3, 4, 5, 6}}, {"IEND", {}}}), "zlib");
  bytes z = zlib_compress(good_raw);
  z[z.size() - 1] ^= 0xFFU;  // the Adler-32 checksum
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", z}, {"IEND", {}}}), "zlib");
  const bytes full = zlib_compress(good_raw);
  check_rejected(
      assemble({{"IHDR", ihdr}, {"IDAT", bytes(full.begin(), full.end() - 3)}, {"IEND", {}}}),
      "truncated");
  check_rejected(
      assemble({{"IHDR", ihdr}, {"IDAT", zlib_compress(zero_gray_raw(3, 2))}, {"IEND", {}}}),
      "too short");
  check_rejected(
      assemble({{"IHDR", ihdr}, {"IDAT", zlib_compress(zero_gray_raw(3, 4))}, {"IEND", {}}}),
      "more than");
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", {}}, {"IEND", {}}}), "too short");
  // A preset dictionary (FDICT bit) is forbidden in PNG.
  bytes dict{0x78, 0xBB, 0, 0, 0, 1, 0x03, 0x00};
  dict[1] = static_cast<std::uint8_t>(dict[1] + (31 - ((dict[0] * 256 + dict[1]) % 31)) % 31);
  check_rejected(assemble({{"IHDR", ihdr}, {"IDAT", dict}, {"IEND", {}}}), "dictionary");
}

TEST_CASE("png corrupt: bad filter byte and palette index out of range") {
  // Filter type 5 on row 1.
  bytes raw = zero_gray_raw(3, 3);
  raw[4] = 5;
  check_rejected(
      assemble({{"IHDR", ihdr_data(3, 3, 8, 0, 0)}, {"IDAT", zlib_compress(raw)}, {"IEND", {}}}),
      "filter type 5");
  // Interlaced: the message names the pass.
  std::mt19937 rng(4);
  test_image img = random_image(9, 9, 8, 0, 1, rng);
  bytes lines = scanlines(img);
  lines[0] = 200;
  check_rejected(build_png(img, lines), "pass 1");

  // 2-bit palette with 3 entries; pixel (1, 0) uses index 3.
  test_image pal{2, 1, 2, 3, 0, {0, 3}, {{{1, 1, 1}}, {{2, 2, 2}}, {{3, 3, 3}}}};
  check_rejected(build_png(pal, scanlines(pal)), "palette index 3");
  // Interlaced 8-bit palette with index beyond a 200-entry palette, somewhere in pass 7.
  test_image pal8 = random_image(5, 6, 8, 3, 1, rng);
  pal8.samples[std::size_t{1} * 5 + 4] = 250;  // pixel (4, 1): pass 7
  check_rejected(build_png(pal8, scanlines(pal8)), "out of range");
}

TEST_CASE("png corrupt: random edits with repaired CRCs never crash") {
  // Edits header fields, filter bytes, palette indices and samples, then rebuilds valid chunks
  // around them, so the deep decoding paths see hostile data. Run under ASan/UBSan too.
  std::mt19937 rng(12345);
  struct combo {
    int colour, depth;
  };
  const std::array<combo, 8> combos{
      {{0, 1}, {0, 4}, {0, 16}, {2, 8}, {3, 2}, {3, 8}, {4, 16}, {6, 8}}};
  int failures = 0;
  int successes = 0;
  for (int iteration = 0; iteration < 1500; ++iteration) {
    const combo cb = combos[rng() % combos.size()];
    const auto w = static_cast<std::uint32_t>(1 + rng() % 12U);
    const auto h = static_cast<std::uint32_t>(1 + rng() % 12U);
    test_image img = random_image(w, h, cb.depth, cb.colour, static_cast<int>(rng() % 2U), rng);
    if (!img.palette.empty() && rng() % 2U == 0) img.palette.resize(1 + rng() % img.palette.size());
    bytes raw = scanlines(img, static_cast<int>(rng() % 5U));
    const int edits = static_cast<int>(rng() % 4U);
    for (int e = 0; e < edits && !raw.empty(); ++e)
      raw[rng() % raw.size()] = static_cast<std::uint8_t>(rng() & 0xFFU);
    if (rng() % 4U == 0) raw.resize(rng() % (raw.size() + 1));
    if (rng() % 8U == 0) raw.push_back(0);
    bytes file = build_png(img, raw, 1 + static_cast<int>(rng() % 3U));
    if (rng() % 3U == 0) {
      file[16 + rng() % 13U] = static_cast<std::uint8_t>(rng() & 0xFFU);  // an IHDR field
      fix_crcs(file);
    }
    const auto r = png::read_png(file);
    if (r) {
      ++successes;
      CHECK(r->width >= 1);
      CHECK(static_cast<std::size_t>(r->width) * static_cast<std::size_t>(r->height) *
                static_cast<std::size_t>(r->channels) ==
            (r->bit_depth == 16 ? r->samples16.size() : r->samples8.size()));
      CHECK(png::to_mask(*r).width() == r->width);
    } else {
      ++failures;
      CHECK_FALSE(r.error().message.empty());
    }
  }
  CHECK(successes > 100);
  CHECK(failures > 100);
}

// ---------------------------------------------------------------------------------------------
// The APNG writer (png::apng_encoder), read back with this file's chunk walker, zlib's CRC and
// the reader under test for each frame's pixels.

namespace {

using rgb_image = perch::image<png::rgb8>;

rgb_image apng_test_frame(int w, int h, int seed) {
  rgb_image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img(x, y) = png::rgb8{static_cast<std::uint8_t>(x * 9 + seed), static_cast<std::uint8_t>(y * 13),
                            static_cast<std::uint8_t>((x ^ y) + 3 * seed)};
  return img;
}

bool same_pixels(const rgb_image& a, const rgb_image& b) {
  if (a.width() != b.width() || a.height() != b.height()) return false;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if (a(x, y) != b(x, y)) return false;
  return true;
}

struct apng_frame_control {
  std::uint32_t sequence, width, height, x, y;
  std::uint32_t delay_num, delay_den;
  std::uint8_t dispose, blend;
};

/// Checks an APNG's structure (every CRC, chunk order, sequence numbers 0, 1, 2, ... over fcTL
/// and fdAT, acTL's frame count) and replays it: returns every frame's full picture.
std::vector<rgb_image> replay_apng(const bytes& file, std::vector<apng_frame_control>& controls) {
  std::vector<rgb_image> frames;
  REQUIRE(file.size() > 8);
  REQUIRE(bytes(file.begin(), file.begin() + 8) == signature());
  const std::vector<chunk_ref> chunks = list_chunks(file);
  REQUIRE(chunks.size() >= 5);
  std::size_t end = 8;
  for (const chunk_ref& c : chunks) {
    const auto crc = static_cast<std::uint32_t>(::crc32(0L, file.data() + c.at + 4, static_cast<uInt>(c.length + 4)));
    CHECK_MESSAGE(get32(file, c.at + 8 + c.length) == crc, "bad CRC on " << c.type);
    end = c.at + 12 + c.length;
  }
  CHECK(end == file.size());
  CHECK(chunks.front().type == "IHDR");
  CHECK(chunks[1].type == "acTL");
  CHECK(chunks.back().type == "IEND");
  const bytes ihdr(file.begin() + static_cast<std::ptrdiff_t>(chunks[0].at + 8),
                   file.begin() + static_cast<std::ptrdiff_t>(chunks[0].at + 8 + chunks[0].length));
  const std::uint32_t num_frames = get32(file, chunks[1].at + 8);
  CHECK(get32(file, chunks[1].at + 12) == 0);  // plays forever
  std::uint32_t next_sequence = 0;
  bool idat_seen = false;
  for (std::size_t i = 2; i + 1 < chunks.size(); ++i) {
    const chunk_ref& c = chunks[i];
    const std::size_t data = c.at + 8;
    if (c.type == "IDAT") {
      CHECK(controls.size() == 1);  // the default image is frame 0
      idat_seen = true;
      continue;
    }
    REQUIRE((c.type == "fcTL" || c.type == "fdAT"));
    CHECK(get32(file, data) == next_sequence);
    ++next_sequence;
    if (c.type == "fdAT") continue;
    REQUIRE(c.length == 26);
    controls.push_back({get32(file, data), get32(file, data + 4), get32(file, data + 8), get32(file, data + 12),
                        get32(file, data + 16), (std::uint32_t{file[data + 20]} << 8U) | file[data + 21],
                        (std::uint32_t{file[data + 22]} << 8U) | file[data + 23], file[data + 24], file[data + 25]});
  }
  CHECK(idat_seen);
  CHECK(controls.size() == num_frames);
  // Frame 0 is the default image: what read_png sees.
  const auto first = png::read_png(file);
  REQUIRE(first.has_value());
  rgb_image canvas = png::to_rgb8(*first);
  frames.push_back(canvas);
  // Frame k: its fdAT payloads (sequence numbers stripped) are a zlib stream of its region.
  std::size_t frame = 0;
  bytes stream;
  const auto flush = [&](std::size_t k) {
    if (k == 0) return;
    const apng_frame_control& f = controls[k];
    const bytes region_png = assemble({{"IHDR", ihdr_data(f.width, f.height, 8, 2, 0)}, {"IDAT", stream}, {"IEND", {}}});
    const auto region = png::read_png(region_png);
    REQUIRE(region.has_value());
    REQUIRE(f.x + f.width <= static_cast<std::uint32_t>(canvas.width()));
    REQUIRE(f.y + f.height <= static_cast<std::uint32_t>(canvas.height()));
    const rgb_image pixels = png::to_rgb8(*region);
    for (int y = 0; y < pixels.height(); ++y)
      for (int x = 0; x < pixels.width(); ++x)
        canvas(static_cast<int>(f.x) + x, static_cast<int>(f.y) + y) = pixels(x, y);  // blend_op source
    frames.push_back(canvas);
    stream.clear();
  };
  for (std::size_t i = 2; i + 1 < chunks.size(); ++i) {
    const chunk_ref& c = chunks[i];
    if (c.type == "fcTL") {
      if (frame > 0 || !stream.empty()) flush(frame);
      frame = static_cast<std::size_t>(get32(file, c.at + 8)) == 0 ? 0 : frame + 1;
    } else if (c.type == "fdAT") {
      stream.insert(stream.end(), file.begin() + static_cast<std::ptrdiff_t>(c.at + 12),
                    file.begin() + static_cast<std::ptrdiff_t>(c.at + 8 + c.length));
    }
  }
  flush(frame);
  return frames;
}

}  // namespace

TEST_CASE("apng: frame 0 is the default image, CRCs and sequence numbers right, every frame replays") {
  const int w = 23, h = 17;
  std::vector<rgb_image> input = {apng_test_frame(w, h, 0), apng_test_frame(w, h, 0), apng_test_frame(w, h, 0),
                                  apng_test_frame(w, h, 5)};
  for (int y = 4; y < 9; ++y)
    for (int x = 6; x < 11; ++x) input[1](x, y) = png::rgb8{255, 0, 0};  // a changed block
  input[2] = input[1];                                                   // no change at all
  const std::uint16_t delays[] = {100, 250, 0, 65535};
  for (const bool crop : {true, false}) {
    CAPTURE(crop);
    png::apng_encoder encoder({.crop_to_changes = crop});
    for (std::size_t i = 0; i < input.size(); ++i) REQUIRE(encoder.add(input[i].view(), delays[i]).has_value());
    CHECK(encoder.frames() == input.size());
    const auto file = encoder.finish();
    REQUIRE(file.has_value());
    std::vector<apng_frame_control> controls;
    const std::vector<rgb_image> frames = replay_apng(*file, controls);
    REQUIRE(controls.size() == input.size());
    REQUIRE(frames.size() == input.size());
    for (std::size_t i = 0; i < input.size(); ++i) {
      CAPTURE(i);
      CHECK(same_pixels(frames[i], input[i]));
      CHECK(controls[i].delay_num == delays[i]);
      CHECK(controls[i].delay_den == 1000);
      CHECK(controls[i].dispose == 0);
      CHECK(controls[i].blend == 0);
    }
    CHECK(controls[0].width == static_cast<std::uint32_t>(w));  // frame 0 is the whole image
    CHECK(controls[0].height == static_cast<std::uint32_t>(h));
    CHECK(controls[0].x + controls[0].y == 0);
    if (crop) {  // frame 1 stores only the changed block, frame 2 one pixel
      CHECK(controls[1].x == 6);
      CHECK(controls[1].y == 4);
      CHECK(controls[1].width == 5);
      CHECK(controls[1].height == 5);
      CHECK(controls[2].width * controls[2].height == 1);
    } else {
      for (const apng_frame_control& c : controls) CHECK(c.width * c.height == static_cast<std::uint32_t>(w * h));
    }
  }
}

TEST_CASE("apng: a frame of another size and an empty animation are errors") {
  png::apng_encoder encoder;
  CHECK_FALSE(encoder.finish().has_value());
  const rgb_image a = apng_test_frame(8, 6, 1), b = apng_test_frame(6, 8, 1);
  REQUIRE(encoder.add(a.view(), 40).has_value());
  const png::png_status wrong = encoder.add(b.view(), 40);
  REQUIRE_FALSE(wrong.has_value());
  CHECK(wrong.error().message.find("first frame") != std::string::npos);
  CHECK(encoder.frames() == 1);
  const auto file = encoder.finish();
  REQUIRE(file.has_value());
  std::vector<apng_frame_control> controls;
  CHECK(replay_apng(*file, controls).size() == 1);
  const std::filesystem::path unwritable = std::filesystem::temp_directory_path() / "perch-no-such-dir" / "a.png";
  const png::png_status written = png::write_apng(unwritable, encoder);
  REQUIRE_FALSE(written.has_value());
  CHECK(written.error().message.find("cannot open") != std::string::npos);
}
