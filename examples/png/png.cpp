// SPDX-License-Identifier: BSL-1.0
// The tiny PNG reader and writer (see png/png.hpp). Written from the PNG specification
// (ISO/IEC 15948:2003, W3C PNG Second Edition): chunk layout §5, CRC Annex D, header §11.2.2,
// filters §9, Adam7 §8.2, scanline packing §7.2. zlib (RFC 1950/1951) does inflate/deflate.
#define ZLIB_CONST
#include "png/png.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string_view>
#include <system_error>

namespace perch::png {
namespace {

constexpr std::array<std::uint8_t, 8> png_signature{137, 80, 78, 71, 13, 10, 26, 10};

// PNG spec Annex D: the table of CRCs of all 8-bit messages.
constexpr std::array<std::uint32_t, 256> make_crc_table() noexcept {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1U) : c >> 1U;
    table[n] = c;
  }
  return table;
}
constexpr std::array<std::uint32_t, 256> crc_table = make_crc_table();

png_error make_error(std::string message) { return png_error{"png: " + std::move(message)}; }

std::string hex32(std::uint32_t v) {
  constexpr std::string_view digits = "0123456789abcdef";
  std::string s = "0x";
  for (int shift = 28; shift >= 0; shift -= 4)
    s += digits[(v >> static_cast<unsigned>(shift)) & 0xFU];
  return s;
}

std::uint32_t read_u32(const std::uint8_t* p) noexcept {
  return (std::uint32_t{p[0]} << 24U) | (std::uint32_t{p[1]} << 16U) | (std::uint32_t{p[2]} << 8U) |
         std::uint32_t{p[3]};
}

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24U));
  out.push_back(static_cast<std::uint8_t>(v >> 16U));
  out.push_back(static_cast<std::uint8_t>(v >> 8U));
  out.push_back(static_cast<std::uint8_t>(v));
}

bool is_letter(std::uint8_t c) noexcept { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

// A chunk type as text for messages: 'IDAT', or its bytes in hex when not four letters.
std::string type_name(const std::uint8_t* t) {
  if (is_letter(t[0]) && is_letter(t[1]) && is_letter(t[2]) && is_letter(t[3]))
    return "'" + std::string(reinterpret_cast<const char*>(t), 4) + "'";
  return hex32(read_u32(t));
}

bool type_is(const std::uint8_t* t, std::string_view name) noexcept {
  return std::equal(name.begin(), name.end(), t,
                    [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
}

// ---------------------------------------------------------------------------------------------
// Header (PNG spec §11.2.2).

struct header {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int bit_depth = 0;
  colour_type colour = colour_type::gray;
  interlace method = interlace::none;
  int samples = 0;         // samples per pixel in the file (palette: 1 index)
  int bits_per_pixel = 0;  // samples × bit_depth
};

bool depth_allowed(int colour, int depth) noexcept {
  switch (colour) {
    case 0:
      return depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16;
    case 3:
      return depth == 1 || depth == 2 || depth == 4 || depth == 8;
    case 2:
    case 4:
    case 6:
      return depth == 8 || depth == 16;
    default:
      return false;
  }
}

png_result<header> parse_header(std::span<const std::uint8_t> d, const read_options& options) {
  if (d.size() != 13)
    return make_error("IHDR chunk has " + std::to_string(d.size()) +
                      " data bytes, the PNG spec requires 13: the header is corrupt");
  header h;
  h.width = read_u32(d.data());
  h.height = read_u32(d.data() + 4);
  const int depth = d[8];
  const int colour = d[9];
  if (h.width == 0 || h.height == 0)
    return make_error("image size is " + std::to_string(h.width) + " x " +
                      std::to_string(h.height) + ": zero width or height is not a valid PNG");
  if (h.width > 0x7FFFFFFFU || h.height > 0x7FFFFFFFU)
    return make_error("image size " + std::to_string(h.width) + " x " + std::to_string(h.height) +
                      " exceeds the PNG limit of 2^31-1 per side: the header is corrupt");
  const std::int64_t limit = std::clamp<std::int64_t>(options.max_pixels, 0, max_png_pixels);
  const std::int64_t pixels = std::int64_t{h.width} * std::int64_t{h.height};
  if (pixels > limit)
    return make_error("image size " + std::to_string(h.width) + " x " + std::to_string(h.height) +
                      " (" + std::to_string(pixels) + " pixels) is larger than the limit of " +
                      std::to_string(limit) + " pixels: too large, downscale it first");
  if (colour != 0 && colour != 2 && colour != 3 && colour != 4 && colour != 6)
    return make_error("colour type " + std::to_string(colour) +
                      " is not one of 0, 2, 3, 4, 6: the header is corrupt");
  if (!depth_allowed(colour, depth))
    return make_error("bit depth " + std::to_string(depth) + " is not allowed with colour type " +
                      std::to_string(colour) +
                      " (gray: 1/2/4/8/16, palette: 1/2/4/8, RGB, gray+alpha, RGBA: 8/16)");
  if (d[10] != 0)
    return make_error("compression method " + std::to_string(d[10]) + " is unknown (only 0)");
  if (d[11] != 0)
    return make_error("filter method " + std::to_string(d[11]) + " is unknown (only 0)");
  if (d[12] > 1)
    return make_error("interlace method " + std::to_string(d[12]) +
                      " is unknown (0 none, 1 Adam7)");
  h.bit_depth = depth;
  h.colour = static_cast<colour_type>(colour);
  h.method = static_cast<interlace>(d[12]);
  h.samples = colour == 0 || colour == 3 ? 1 : colour == 2 ? 3 : colour == 4 ? 2 : 4;
  h.bits_per_pixel = h.samples * depth;
  return h;
}

// ---------------------------------------------------------------------------------------------
// Adam7 (PNG spec §8.2): pass origins and steps; a non-interlaced image is one pass.

struct pass_geometry {
  std::uint32_t x0, y0, dx, dy;
};
constexpr std::array<pass_geometry, 7> adam7_passes{{
    {0, 0, 8, 8},
    {4, 0, 8, 8},
    {0, 4, 4, 8},
    {2, 0, 4, 4},
    {0, 2, 2, 4},
    {1, 0, 2, 2},
    {0, 1, 1, 2},
}};
constexpr std::array<pass_geometry, 1> single_pass{{{0, 0, 1, 1}}};

std::span<const pass_geometry> passes_of(interlace method) noexcept {
  if (method == interlace::adam7) return adam7_passes;
  return single_pass;
}

std::uint64_t pass_extent(std::uint32_t size, std::uint32_t origin, std::uint32_t step) noexcept {
  return size > origin ? (std::uint64_t{size} - origin + step - 1) / step : 0;
}

std::uint64_t row_bytes(std::uint64_t pixels, int bits_per_pixel) noexcept {
  return (pixels * static_cast<std::uint64_t>(bits_per_pixel) + 7) / 8;
}

// Bytes of filtered scanline data the header promises (filter bytes included).
std::uint64_t expected_raw_size(const header& h) noexcept {
  std::uint64_t total = 0;
  for (const pass_geometry& p : passes_of(h.method)) {
    const std::uint64_t w = pass_extent(h.width, p.x0, p.dx);
    const std::uint64_t rows = pass_extent(h.height, p.y0, p.dy);
    if (w == 0 || rows == 0) continue;
    total += rows * (1 + row_bytes(w, h.bits_per_pixel));
  }
  return total;
}

// ---------------------------------------------------------------------------------------------
// Streaming inflate of the concatenated IDAT data into a buffer of exactly the promised size.
// The buffer grows with the data actually decompressed, so a huge header over a tiny stream
// never allocates the huge size.

class inflater {
 public:
  explicit inflater(std::size_t expected) : expected_(expected) {}
  inflater(const inflater&) = delete;
  inflater& operator=(const inflater&) = delete;
  ~inflater() {
    if (started_) inflateEnd(&stream_);
  }

  // Feeds one IDAT chunk's data; returns an error message or nothing.
  std::optional<png_error> feed(std::span<const std::uint8_t> data) {
    if (!started_) {
      stream_ = z_stream{};
      if (inflateInit(&stream_) != Z_OK) return make_error("zlib could not start inflating");
      started_ = true;
    }
    if (ended_) return std::nullopt;  // bytes after the end of the zlib stream are ignored
    stream_.next_in = data.data();
    stream_.avail_in = static_cast<uInt>(data.size());
    while (stream_.avail_in > 0 && !ended_) {
      std::uint8_t probe = 0;
      bool probing = false;
      if (produced_ == out_.size()) {
        if (out_.size() < expected_) {
          const std::size_t grown = std::max<std::size_t>(out_.size() * 2, std::size_t{1} << 16);
          out_.resize(std::min(grown, expected_));
        } else {
          probing = true;  // all promised bytes are here: only the stream's end may follow
        }
      }
      const std::size_t room =
          probing ? 1 : std::min<std::size_t>(out_.size() - produced_, 1U << 30U);
      stream_.next_out = probing ? &probe : out_.data() + produced_;
      stream_.avail_out = static_cast<uInt>(room);
      const uInt in_before = stream_.avail_in;
      const int ret = inflate(&stream_, Z_NO_FLUSH);
      const std::size_t made = room - stream_.avail_out;
      if (ret == Z_NEED_DICT)
        return make_error(
            "the zlib stream asks for a preset dictionary, which PNG forbids: "
            "the image data is corrupt");
      if (ret == Z_DATA_ERROR)
        return make_error(std::string("corrupt zlib stream in IDAT (") +
                          (stream_.msg != nullptr ? stream_.msg : "invalid data") +
                          "): the image data is damaged");
      if (ret == Z_MEM_ERROR) return make_error("zlib ran out of memory while inflating");
      if (ret != Z_OK && ret != Z_STREAM_END && ret != Z_BUF_ERROR)
        return make_error("zlib failed while inflating (code " + std::to_string(ret) + ")");
      if (probing && made > 0)
        return make_error("the IDAT data decompresses to more than the " +
                          std::to_string(expected_) +
                          " bytes the header promises: the image data is corrupt");
      if (!probing) produced_ += made;
      if (ret == Z_STREAM_END) ended_ = true;
      if (!ended_ && made == 0 && stream_.avail_in == in_before)
        return make_error("zlib made no progress on the IDAT data: the stream is corrupt");
    }
    return std::nullopt;
  }

  // After the last IDAT: the stream must have ended with exactly the promised bytes.
  std::optional<png_error> finish() const {
    if (produced_ < expected_)
      return make_error("image data too short: the IDAT data decompresses to only " +
                        std::to_string(produced_) + " of the " + std::to_string(expected_) +
                        " bytes the header promises: truncated or corrupt image data");
    if (!ended_)
      return make_error(
          "the zlib stream in IDAT does not end (missing end of stream or "
          "checksum): truncated or corrupt image data");
    return std::nullopt;
  }

  std::vector<std::uint8_t>& data() noexcept { return out_; }

 private:
  z_stream stream_{};
  bool started_ = false;
  bool ended_ = false;
  std::size_t expected_ = 0;
  std::size_t produced_ = 0;
  std::vector<std::uint8_t> out_;
};

// ---------------------------------------------------------------------------------------------
// Filters (PNG spec §9.2, §9.4).

std::uint8_t paeth(std::uint8_t a, std::uint8_t b, std::uint8_t c) noexcept {
  const int p = int{a} + int{b} - int{c};
  const int pa = std::abs(p - int{a});
  const int pb = std::abs(p - int{b});
  const int pc = std::abs(p - int{c});
  if (pa <= pb && pa <= pc) return a;
  if (pb <= pc) return b;
  return c;
}

// Reverses filter `type` on `cur` in place; `prev` is the reconstructed previous row of the
// pass (all zero for its first row).
void unfilter(int type, std::uint8_t* cur, const std::uint8_t* prev, std::size_t n,
              std::size_t bpp) noexcept {
  switch (type) {
    case 1:
      for (std::size_t i = bpp; i < n; ++i)
        cur[i] = static_cast<std::uint8_t>(cur[i] + cur[i - bpp]);
      break;
    case 2:
      for (std::size_t i = 0; i < n; ++i) cur[i] = static_cast<std::uint8_t>(cur[i] + prev[i]);
      break;
    case 3:
      for (std::size_t i = 0; i < n; ++i) {
        const int a = i >= bpp ? cur[i - bpp] : 0;
        cur[i] = static_cast<std::uint8_t>(cur[i] + ((a + prev[i]) >> 1));
      }
      break;
    case 4:
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t a = i >= bpp ? cur[i - bpp] : 0;
        const std::uint8_t c = i >= bpp ? prev[i - bpp] : 0;
        cur[i] = static_cast<std::uint8_t>(cur[i] + paeth(a, prev[i], c));
      }
      break;
    default:
      break;
  }
}

// Writes filter `type` of `cur` (previous row `prev`) into `out`.
void apply_filter(int type, const std::uint8_t* cur, const std::uint8_t* prev, std::size_t n,
                  std::size_t bpp, std::uint8_t* out) noexcept {
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t a = i >= bpp ? cur[i - bpp] : 0;
    const std::uint8_t b = prev[i];
    const std::uint8_t c = i >= bpp ? prev[i - bpp] : 0;
    std::uint8_t predictor = 0;
    switch (type) {
      case 1:
        predictor = a;
        break;
      case 2:
        predictor = b;
        break;
      case 3:
        predictor = static_cast<std::uint8_t>((int{a} + int{b}) >> 1);
        break;
      case 4:
        predictor = paeth(a, b, c);
        break;
      default:
        break;
    }
    out[i] = static_cast<std::uint8_t>(cur[i] - predictor);
  }
}

// ---------------------------------------------------------------------------------------------
// Decoding.

struct chunk_state {
  bool seen_plte = false;
  bool seen_idat = false;
  bool idat_run_over = false;  // a non-IDAT chunk came after IDAT
};

// Unpacks reconstructed row `row` (pass pixel count `n`) into the output at (x0 + i·dx, y).
std::optional<png_error> unpack_row(const header& h, const std::vector<rgb8>& palette,
                                    const std::uint8_t* row, std::uint64_t n, std::uint64_t x0,
                                    std::uint64_t dx, std::uint64_t y, decoded_png& out) {
  const std::uint64_t width = h.width;
  const auto channels = static_cast<std::uint64_t>(out.channels);
  if (h.bit_depth == 16) {
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::size_t dst = static_cast<std::size_t>(((y * width) + x0 + i * dx) * channels);
      for (std::uint64_t c = 0; c < channels; ++c) {
        const std::size_t src = static_cast<std::size_t>((i * channels + c) * 2);
        out.samples16[dst + c] =
            static_cast<std::uint16_t>((unsigned{row[src]} << 8U) | unsigned{row[src + 1]});
      }
    }
    return std::nullopt;
  }
  if (h.bit_depth == 8 && h.colour != colour_type::palette) {
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::size_t dst = static_cast<std::size_t>(((y * width) + x0 + i * dx) * channels);
      const std::size_t src = static_cast<std::size_t>(i * channels);
      for (std::uint64_t c = 0; c < channels; ++c) out.samples8[dst + c] = row[src + c];
    }
    return std::nullopt;
  }
  // One sample per pixel of 1, 2, 4 or 8 bits: gray (scaled to 8 bits) or a palette index.
  const auto depth = static_cast<unsigned>(h.bit_depth);
  const unsigned mask = (1U << depth) - 1U;
  const unsigned scale = 255U / mask;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::uint64_t bit = i * depth;
    const auto shift = static_cast<unsigned>(8U - depth - (bit & 7U));
    const unsigned v = (unsigned{row[bit >> 3U]} >> shift) & mask;
    const std::size_t dst = static_cast<std::size_t>(((y * width) + x0 + i * dx) * channels);
    if (h.colour == colour_type::palette) {
      if (v >= palette.size())
        return make_error("pixel (" + std::to_string(x0 + i * dx) + ", " + std::to_string(y) +
                          ") has palette index " + std::to_string(v) + " but PLTE has only " +
                          std::to_string(palette.size()) +
                          " entries: palette index out of range, the file is corrupt");
      out.samples8[dst] = palette[v].r;
      out.samples8[dst + 1] = palette[v].g;
      out.samples8[dst + 2] = palette[v].b;
    } else {
      out.samples8[dst] = static_cast<std::uint8_t>(v * scale);
    }
  }
  return std::nullopt;
}

png_result<decoded_png> reconstruct(const header& h, const std::vector<rgb8>& palette,
                                    std::vector<std::uint8_t>& raw) {
  decoded_png out;
  out.width = static_cast<int>(h.width);
  out.height = static_cast<int>(h.height);
  out.channels = h.colour == colour_type::palette ? 3 : h.samples;
  out.bit_depth = h.bit_depth == 16 ? 16 : 8;
  out.source_colour_type = h.colour;
  out.source_bit_depth = h.bit_depth;
  out.source_interlace = h.method;
  const std::size_t count =
      std::size_t{h.width} * std::size_t{h.height} * static_cast<std::size_t>(out.channels);
  if (out.bit_depth == 16)
    out.samples16.assign(count, 0);
  else
    out.samples8.assign(count, 0);

  const auto bpp = static_cast<std::size_t>(std::max(1, h.bits_per_pixel / 8));
  std::vector<std::uint8_t> zero_row(static_cast<std::size_t>(row_bytes(h.width, h.bits_per_pixel)),
                                     0);
  std::size_t offset = 0;
  int pass_number = 0;
  for (const pass_geometry& p : passes_of(h.method)) {
    ++pass_number;
    const std::uint64_t w = pass_extent(h.width, p.x0, p.dx);
    const std::uint64_t rows = pass_extent(h.height, p.y0, p.dy);
    if (w == 0 || rows == 0) continue;
    const auto n = static_cast<std::size_t>(row_bytes(w, h.bits_per_pixel));
    const std::uint8_t* prev = zero_row.data();
    for (std::uint64_t r = 0; r < rows; ++r) {
      const int type = raw[offset];
      if (type > 4) {
        std::string where = "row " + std::to_string(r);
        if (h.method == interlace::adam7) where += " of Adam7 pass " + std::to_string(pass_number);
        return make_error(where + " has filter type " + std::to_string(type) +
                          ", only 0..4 exist: bad filter byte, the image data is corrupt");
      }
      std::uint8_t* cur = raw.data() + offset + 1;
      unfilter(type, cur, prev, n, bpp);
      if (auto e = unpack_row(h, palette, cur, w, p.x0, p.dx, p.y0 + r * p.dy, out)) return *e;
      prev = cur;
      offset += 1 + n;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Encoding.

struct raw_image {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int colour = 0;
  int bit_depth = 0;
  std::size_t bytes_per_pixel = 0;
};

std::optional<png_error> check_view(int width, int height, status valid) {
  if (!valid.has_value())
    return make_error("cannot encode this image: " + std::string(to_string(valid.error().code)));
  if (std::int64_t{width} * std::int64_t{height} > max_png_pixels)
    return make_error("cannot encode a " + std::to_string(width) + " x " + std::to_string(height) +
                      " image: more than 2^28 pixels, too large");
  return std::nullopt;
}

void put_chunk(std::vector<std::uint8_t>& out, std::string_view type,
               std::span<const std::uint8_t> data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  for (char c : type) out.push_back(static_cast<std::uint8_t>(c));
  out.insert(out.end(), data.begin(), data.end());
  put_u32(out, crc32(std::span<const std::uint8_t>(out.data() + start, out.size() - start)));
}

// `row_at(y, dst)` writes row y's unfiltered bytes (big-endian samples) into dst. Returns the
// zlib stream of the filtered rows (what IDAT, or an APNG frame's fdAT, carries).
template <class RowFn>
png_result<std::vector<std::uint8_t>> deflate_rows(const raw_image& img, const write_options& options,
                                                   RowFn row_at) {
  const std::size_t n = std::size_t{img.width} * img.bytes_per_pixel;
  const std::size_t bpp = img.bytes_per_pixel;
  std::vector<std::uint8_t> filtered;
  filtered.reserve((n + 1) * img.height);
  std::vector<std::uint8_t> prev(n, 0);
  std::vector<std::uint8_t> cur(n, 0);
  std::vector<std::uint8_t> candidate(n, 0);
  std::vector<std::uint8_t> best(n, 0);
  for (std::uint32_t y = 0; y < img.height; ++y) {
    row_at(y, cur.data());
    int best_type = 0;
    if (options.filter == filter_choice::none) {
      best = cur;
    } else {
      std::uint64_t best_sum = std::numeric_limits<std::uint64_t>::max();
      for (int type = 0; type <= 4; ++type) {
        apply_filter(type, cur.data(), prev.data(), n, bpp, candidate.data());
        std::uint64_t sum = 0;
        for (const std::uint8_t v : candidate) sum += v < 128 ? v : 256U - v;
        if (sum < best_sum) {
          best_sum = sum;
          best_type = type;
          best.swap(candidate);
        }
      }
    }
    filtered.push_back(static_cast<std::uint8_t>(best_type));
    filtered.insert(filtered.end(), best.begin(), best.end());
    prev.swap(cur);
  }

  z_stream z{};
  const int level = std::clamp(options.compression_level, 0, 9);
  if (deflateInit(&z, level) != Z_OK) return make_error("zlib could not start deflating");
  std::vector<std::uint8_t> compressed(
      std::max<std::size_t>(deflateBound(&z, static_cast<uLong>(filtered.size())), 64));
  std::size_t in_done = 0;
  std::size_t out_done = 0;
  int ret = Z_OK;
  while (ret != Z_STREAM_END) {
    if (out_done == compressed.size()) compressed.resize(compressed.size() * 2);
    const std::size_t in_chunk = std::min<std::size_t>(filtered.size() - in_done, 1U << 30U);
    const std::size_t out_chunk = std::min<std::size_t>(compressed.size() - out_done, 1U << 30U);
    z.next_in = filtered.data() + in_done;
    z.avail_in = static_cast<uInt>(in_chunk);
    z.next_out = compressed.data() + out_done;
    z.avail_out = static_cast<uInt>(out_chunk);
    const bool last = in_done + in_chunk == filtered.size();
    ret = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
    if (ret != Z_OK && ret != Z_STREAM_END && ret != Z_BUF_ERROR) {
      deflateEnd(&z);
      return make_error("zlib failed while deflating (code " + std::to_string(ret) + ")");
    }
    in_done += in_chunk - z.avail_in;
    out_done += out_chunk - z.avail_out;
  }
  deflateEnd(&z);
  compressed.resize(out_done);
  return compressed;
}

// Data chunks are split at a fixed size: deterministic output.
constexpr std::size_t data_chunk_size = std::size_t{1} << 20;

// The signature and IHDR of `img`.
std::vector<std::uint8_t> file_start(const raw_image& img) {
  std::vector<std::uint8_t> png(png_signature.begin(), png_signature.end());
  std::vector<std::uint8_t> ihdr;
  put_u32(ihdr, img.width);
  put_u32(ihdr, img.height);
  ihdr.push_back(static_cast<std::uint8_t>(img.bit_depth));
  ihdr.push_back(static_cast<std::uint8_t>(img.colour));
  ihdr.push_back(0);  // compression: deflate
  ihdr.push_back(0);  // filter method 0
  ihdr.push_back(0);  // no interlace
  put_chunk(png, "IHDR", ihdr);
  return png;
}

// `compressed` as IDAT chunks.
void put_idat(std::vector<std::uint8_t>& png, std::span<const std::uint8_t> compressed) {
  for (std::size_t at = 0; at < compressed.size(); at += data_chunk_size)
    put_chunk(png, "IDAT", compressed.subspan(at, std::min(data_chunk_size, compressed.size() - at)));
}

template <class RowFn>
png_result<std::vector<std::uint8_t>> encode_rows(const raw_image& img,
                                                  const write_options& options, RowFn row_at) {
  png_result<std::vector<std::uint8_t>> compressed = deflate_rows(img, options, row_at);
  if (!compressed) return compressed.error();
  std::vector<std::uint8_t> png = file_start(img);
  put_idat(png, *compressed);
  put_chunk(png, "IEND", {});
  return png;
}

png_status write_file(const std::filesystem::path& path,
                      const png_result<std::vector<std::uint8_t>>& encoded) {
  if (!encoded) return encoded.error();
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file)
    return make_error("cannot open '" + path.string() +
                      "' for writing: check the directory "
                      "exists and is writable");
  const std::vector<std::uint8_t>& bytes = *encoded;
  file.write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) return make_error("writing '" + path.string() + "' failed (disk full?)");
  return {};
}

// An RGB row as the file's bytes.
void pack_rgb_row(std::span<const rgb8> row, std::uint8_t* dst) noexcept {
  for (const rgb8& p : row) {
    *dst++ = p.r;
    *dst++ = p.g;
    *dst++ = p.b;
  }
}

std::uint8_t scale16_to_8(std::uint16_t v) noexcept {
  return static_cast<std::uint8_t>((std::uint32_t{v} * 255U + 32767U) / 65535U);
}

std::uint32_t luma(std::uint32_t r, std::uint32_t g, std::uint32_t b) noexcept {
  return (299U * r + 587U * g + 114U * b + 500U) / 1000U;
}

template <class T, class PixelFn>
image<T> convert(const decoded_png& png, PixelFn pixel) {
  if (png.width <= 0 || png.height <= 0 || png.channels <= 0) return {};
  image<T> out(png.width, png.height);
  for (int y = 0; y < png.height; ++y) {
    const auto r = out.row(y);
    for (int x = 0; x < png.width; ++x) r[static_cast<std::size_t>(x)] = pixel(x, y);
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes) noexcept {
  std::uint32_t c = crc ^ 0xFFFFFFFFU;
  for (const std::uint8_t b : bytes) c = crc_table[(c ^ b) & 0xFFU] ^ (c >> 8U);
  return c ^ 0xFFFFFFFFU;
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept { return crc32_update(0, bytes); }

png_result<decoded_png> read_png(std::span<const std::uint8_t> bytes, const read_options& options) {
  if (bytes.size() < png_signature.size() ||
      !std::equal(png_signature.begin(), png_signature.end(), bytes.begin()))
    return make_error(
        bytes.size() < png_signature.size()
            ? "file is " + std::to_string(bytes.size()) +
                  " bytes, shorter than the 8-byte PNG signature: truncated or not a PNG"
            : std::string("file does not start with the PNG signature: not a PNG "
                          "(or damaged by a text-mode transfer)"));
  std::size_t pos = png_signature.size();
  std::optional<header> h;
  std::optional<inflater> z;
  std::vector<rgb8> palette;
  chunk_state state;
  while (true) {
    const std::size_t left = bytes.size() - pos;
    if (left == 0)
      return make_error("file ends after " + std::to_string(pos) +
                        " bytes without an IEND chunk: truncated");
    if (left < 12)
      return make_error("file ends inside the chunk at byte " + std::to_string(pos) + " (only " +
                        std::to_string(left) + " bytes left): truncated");
    const std::uint8_t* c = bytes.data() + pos;
    const std::uint32_t length = read_u32(c);
    const std::uint8_t* type = c + 4;
    const std::string name = type_name(type);
    if (length > 0x7FFFFFFFU)
      return make_error("chunk " + name + " at byte " + std::to_string(pos) + " declares length " +
                        std::to_string(length) + ", above the PNG limit of 2^31-1: corrupt file");
    if (left - 12 < length)
      return make_error("chunk " + name + " at byte " + std::to_string(pos) + " declares " +
                        std::to_string(length) + " data bytes but the file has only " +
                        std::to_string(left - 12) + " left: truncated");
    if (!(is_letter(type[0]) && is_letter(type[1]) && is_letter(type[2]) && is_letter(type[3])))
      return make_error("chunk at byte " + std::to_string(pos) + " has type " + name +
                        ", which is not four ASCII letters: corrupt file");
    const std::uint32_t stored = read_u32(c + 8 + length);
    const std::uint32_t computed =
        crc32(std::span<const std::uint8_t>(type, std::size_t{length} + 4));
    if (stored != computed)
      return make_error("chunk " + name + " at byte " + std::to_string(pos) + " has CRC " +
                        hex32(stored) + " but its contents give " + hex32(computed) +
                        ": bad CRC, the file is corrupt");
    const std::span<const std::uint8_t> data(c + 8, length);
    const std::size_t at = pos;
    pos += std::size_t{length} + 12;

    if (!h) {
      if (!type_is(type, "IHDR"))
        return make_error("first chunk is " + name +
                          " but a PNG must start with IHDR: wrong chunk order");
      auto parsed = parse_header(data, options);
      if (!parsed) return parsed.error();
      h = *parsed;
      continue;
    }
    const bool is_idat = type_is(type, "IDAT");
    if (state.seen_idat && !is_idat) state.idat_run_over = true;
    if (is_idat) {
      if (state.idat_run_over)
        return make_error("IDAT chunk at byte " + std::to_string(at) +
                          " comes after another chunk ended the IDAT sequence: IDAT chunks "
                          "must be consecutive, wrong chunk order");
      if (h->colour == colour_type::palette && !state.seen_plte)
        return make_error(
            "palette image has no PLTE chunk before its IDAT data: wrong chunk "
            "order or missing palette");
      if (!z) z.emplace(static_cast<std::size_t>(expected_raw_size(*h)));
      state.seen_idat = true;
      if (auto e = z->feed(data)) return *e;
    } else if (type_is(type, "IEND")) {
      if (!state.seen_idat)
        return make_error("IEND reached without any IDAT chunk: the file has no image data");
      if (length != 0)
        return make_error("IEND chunk has " + std::to_string(length) +
                          " data bytes, it must be empty: corrupt file");
      if (auto e = z->finish()) return *e;
      return reconstruct(*h, palette, z->data());
    } else if (type_is(type, "IHDR")) {
      return make_error("second IHDR chunk at byte " + std::to_string(at) +
                        ": a PNG has exactly one header, wrong chunk order");
    } else if (type_is(type, "PLTE")) {
      if (state.seen_idat)
        return make_error("PLTE chunk at byte " + std::to_string(at) +
                          " comes after IDAT: wrong chunk order");
      if (state.seen_plte)
        return make_error("second PLTE chunk at byte " + std::to_string(at) +
                          ": duplicate palette, wrong chunk order");
      if (h->colour == colour_type::gray || h->colour == colour_type::gray_alpha)
        return make_error("PLTE chunk in a gray image: the PNG spec forbids it, corrupt file");
      if (length == 0 || length % 3 != 0 || length > 768)
        return make_error(
            "PLTE chunk has " + std::to_string(length) +
            " bytes; it must hold 1..256 RGB entries (a multiple of 3): corrupt palette");
      state.seen_plte = true;
      if (h->colour == colour_type::palette) {
        palette.clear();
        for (std::size_t i = 0; i + 2 < data.size(); i += 3)
          palette.push_back(rgb8{data[i], data[i + 1], data[i + 2]});
      }
    } else if ((type[0] & 0x20U) == 0) {
      return make_error("unknown critical chunk " + name + " at byte " + std::to_string(at) +
                        ": this reader cannot decode the file safely");
    }
    // Other ancillary chunks (tRNS, gAMA, tEXt, ...) are skipped after their CRC check.
  }
}

png_result<decoded_png> read_png_file(const std::filesystem::path& path,
                                      const read_options& options) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found)
    return make_error("'" + path.string() + "' does not exist");
  if (status.type() == std::filesystem::file_type::directory)
    return make_error("'" + path.string() + "' is a directory, not a PNG file");
  if (!ec && status.type() != std::filesystem::file_type::regular)
    return make_error("'" + path.string() + "' is not a regular file (a device, pipe or socket)");
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file)
    return make_error("cannot open '" + path.string() + "': check the path and permissions");
  const std::streamoff size = file.tellg();
  if (size < 0) return make_error("cannot read the size of '" + path.string() + "'");
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  file.seekg(0);
  file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!file) return make_error("reading '" + path.string() + "' failed");
  auto decoded = read_png(bytes, options);
  if (!decoded) return png_error{decoded.error().message + " (in '" + path.string() + "')"};
  return decoded;
}

image<std::uint8_t> to_gray8(const decoded_png& png) {
  return convert<std::uint8_t>(png, [&png](int x, int y) -> std::uint8_t {
    const auto s = [&](int c) -> std::uint32_t {
      const std::uint16_t v = png.sample(x, y, c);
      return png.bit_depth == 16 ? scale16_to_8(v) : v;
    };
    if (png.channels >= 3) return static_cast<std::uint8_t>(luma(s(0), s(1), s(2)));
    return static_cast<std::uint8_t>(s(0));
  });
}

image<std::uint8_t> to_mask(const decoded_png& png) {
  return convert<std::uint8_t>(png, [&png](int x, int y) -> std::uint8_t {
    const int colours = png.channels >= 3 ? 3 : 1;
    for (int c = 0; c < colours; ++c)
      if (png.sample(x, y, c) != 0) return 1;
    return 0;
  });
}

image<std::uint16_t> to_gray16(const decoded_png& png) {
  return convert<std::uint16_t>(png, [&png](int x, int y) -> std::uint16_t {
    if (png.channels >= 3)
      return static_cast<std::uint16_t>(
          luma(png.sample(x, y, 0), png.sample(x, y, 1), png.sample(x, y, 2)));
    return png.sample(x, y, 0);
  });
}

image<rgb8> to_rgb8(const decoded_png& png) {
  return convert<rgb8>(png, [&png](int x, int y) -> rgb8 {
    const auto s = [&](int c) -> std::uint8_t {
      const std::uint16_t v = png.sample(x, y, c);
      return png.bit_depth == 16 ? scale16_to_8(v) : static_cast<std::uint8_t>(v);
    };
    if (png.channels >= 3) return rgb8{s(0), s(1), s(2)};
    const std::uint8_t g = s(0);
    return rgb8{g, g, g};
  });
}

png_result<std::vector<std::uint8_t>> encode_png(image_view<const std::uint8_t> gray,
                                                 const write_options& options) {
  if (auto e = check_view(gray.width(), gray.height(), validate_non_empty(gray))) return *e;
  const raw_image img{static_cast<std::uint32_t>(gray.width()),
                      static_cast<std::uint32_t>(gray.height()), 0, 8, 1};
  return encode_rows(img, options, [&gray](std::uint32_t y, std::uint8_t* dst) {
    const auto row = gray.row(static_cast<int>(y));
    std::copy(row.begin(), row.end(), dst);
  });
}

png_result<std::vector<std::uint8_t>> encode_png(image_view<const rgb8> rgb,
                                                 const write_options& options) {
  if (auto e = check_view(rgb.width(), rgb.height(), validate_non_empty(rgb))) return *e;
  const raw_image img{static_cast<std::uint32_t>(rgb.width()),
                      static_cast<std::uint32_t>(rgb.height()), 2, 8, 3};
  return encode_rows(img, options, [&rgb](std::uint32_t y, std::uint8_t* dst) {
    pack_rgb_row(rgb.row(static_cast<int>(y)), dst);
  });
}

png_result<std::vector<std::uint8_t>> encode_png(image_view<const std::uint16_t> gray,
                                                 const write_options& options) {
  if (auto e = check_view(gray.width(), gray.height(), validate_non_empty(gray))) return *e;
  const raw_image img{static_cast<std::uint32_t>(gray.width()),
                      static_cast<std::uint32_t>(gray.height()), 0, 16, 2};
  return encode_rows(img, options, [&gray](std::uint32_t y, std::uint8_t* dst) {
    for (const std::uint16_t v : gray.row(static_cast<int>(y))) {
      *dst++ = static_cast<std::uint8_t>(v >> 8U);
      *dst++ = static_cast<std::uint8_t>(v & 0xFFU);
    }
  });
}

png_status write_png(const std::filesystem::path& path, image_view<const std::uint8_t> gray,
                     const write_options& options) {
  return write_file(path, encode_png(gray, options));
}

png_status write_png(const std::filesystem::path& path, image_view<const rgb8> rgb,
                     const write_options& options) {
  return write_file(path, encode_png(rgb, options));
}

png_status write_png(const std::filesystem::path& path, image_view<const std::uint16_t> gray,
                     const write_options& options) {
  return write_file(path, encode_png(gray, options));
}

// ---------------------------------------------------------------------------------------------
// APNG (Animated PNG 1.0, https://wiki.mozilla.org/APNG_Specification): acTL after IHDR, then
// per frame an fcTL and its data, IDAT for frame 0 (the default image) and fdAT for the others;
// fcTL and fdAT share one sequence number counter from 0.

png_status apng_encoder::add(image_view<const rgb8> frame, std::uint16_t delay_ms) {
  if (auto e = check_view(frame.width(), frame.height(), validate_non_empty(frame))) return *e;
  if (!frames_.empty() && (frame.width() != width_ || frame.height() != height_))
    return make_error("animation frame " + std::to_string(frames_.size()) + " is " +
                      std::to_string(frame.width()) + " x " + std::to_string(frame.height()) +
                      ", the first frame is " + std::to_string(width_) + " x " + std::to_string(height_) +
                      ": every frame of an animation must have the first frame's size");
  // The rectangle where the frame differs from the one before (all of it for the first).
  int x0 = 0, y0 = 0, x1 = frame.width() - 1, y1 = frame.height() - 1;
  if (!frames_.empty() && options_.crop_to_changes) {
    x0 = frame.width();
    y0 = frame.height();
    x1 = y1 = -1;
    for (int y = 0; y < frame.height(); ++y) {
      const auto row = frame.row(y);
      const rgb8* before = previous_.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width_);
      for (int x = 0; x < frame.width(); ++x)
        if (row[static_cast<std::size_t>(x)] != before[x]) {
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
          y0 = std::min(y0, y);
          y1 = std::max(y1, y);
        }
    }
    if (x1 < 0) x0 = y0 = x1 = y1 = 0;  // the same picture: one pixel, unchanged
  }
  const image_view<const rgb8> region = frame.sub_view(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
  const raw_image img{static_cast<std::uint32_t>(region.width()), static_cast<std::uint32_t>(region.height()),
                      2, 8, 3};
  png_result<std::vector<std::uint8_t>> compressed =
      deflate_rows(img, options_.png, [&region](std::uint32_t y, std::uint8_t* dst) {
        pack_rgb_row(region.row(static_cast<int>(y)), dst);
      });
  if (!compressed) return compressed.error();
  width_ = frame.width();
  height_ = frame.height();
  previous_.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  for (int y = 0; y < height_; ++y) {
    const auto row = frame.row(y);
    std::copy(row.begin(), row.end(), previous_.begin() + static_cast<std::ptrdiff_t>(y) * width_);
  }
  frames_.push_back(stored_frame{static_cast<std::uint32_t>(x0), static_cast<std::uint32_t>(y0),
                                 img.width, img.height, delay_ms, std::move(*compressed)});
  return {};
}

png_result<std::vector<std::uint8_t>> apng_encoder::finish() const {
  if (frames_.empty()) return make_error("an animation needs at least one frame");
  if (frames_.size() > 0x7FFFFFFFU) return make_error("too many animation frames");
  std::vector<std::uint8_t> png =
      file_start(raw_image{static_cast<std::uint32_t>(width_), static_cast<std::uint32_t>(height_), 2, 8, 3});
  std::vector<std::uint8_t> data;
  put_u32(data, static_cast<std::uint32_t>(frames_.size()));  // num_frames
  put_u32(data, options_.plays);                              // num_plays, 0: forever
  put_chunk(png, "acTL", data);
  std::uint32_t sequence = 0;
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const stored_frame& f = frames_[i];
    data.clear();
    put_u32(data, sequence++);
    put_u32(data, f.width);
    put_u32(data, f.height);
    put_u32(data, f.x);
    put_u32(data, f.y);
    data.push_back(static_cast<std::uint8_t>(f.delay_ms >> 8U));  // delay_num (ms)
    data.push_back(static_cast<std::uint8_t>(f.delay_ms & 0xFFU));
    data.push_back(static_cast<std::uint8_t>(1000U >> 8U));       // delay_den: 1000
    data.push_back(static_cast<std::uint8_t>(1000U & 0xFFU));
    data.push_back(0);  // dispose_op: none (the next frame draws over this one)
    data.push_back(0);  // blend_op: source (the region is replaced, not blended)
    put_chunk(png, "fcTL", data);
    const std::span<const std::uint8_t> compressed(f.compressed);
    if (i == 0) {
      put_idat(png, compressed);
      continue;
    }
    for (std::size_t at = 0; at < compressed.size(); at += data_chunk_size) {
      data.clear();
      put_u32(data, sequence++);
      const auto piece = compressed.subspan(at, std::min(data_chunk_size, compressed.size() - at));
      data.insert(data.end(), piece.begin(), piece.end());
      put_chunk(png, "fdAT", data);
    }
  }
  put_chunk(png, "IEND", {});
  return png;
}

png_status write_apng(const std::filesystem::path& path, const apng_encoder& encoder) {
  return write_file(path, encoder.finish());
}

}  // namespace perch::png
