// SPDX-License-Identifier: BSL-1.0
/// \file
/// A tiny PNG reader and writer for perch's host code (the tool, the examples, the tests).
/// It lives in `examples/`, never in `include/perch/`: the library itself does no I/O.
///
/// Reads every standard PNG image type (ISO/IEC 15948:2003, "PNG (Portable Network Graphics)
/// Specification, Second Edition", W3C Recommendation 2003): gray 1/2/4/8/16-bit, gray+alpha
/// 8/16, RGB 8/16, RGBA 8/16, palette 1/2/4/8, with or without Adam7 interlace, all five
/// filter types. Writes 8-bit gray, 8-bit RGB and 16-bit gray. zlib does inflate/deflate; the
/// chunks, CRCs, filters and interlace are perch's own code.
///
/// Like the library, nothing here throws (beyond `std::bad_alloc` from the standard
/// containers): every failure comes back as a `png_error` whose message says what is wrong
/// and where. Nothing crashes on hostile input: sizes are checked before anything is allocated
/// (at most `max_png_pixels`), every chunk's CRC is checked, and the decompressed data must
/// have exactly the size the header promises.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "perch/core/assert.hpp"
#include "perch/core/image.hpp"
#include "perch/core/image_view.hpp"

namespace perch::png {

/// Largest image the reader and the writer accept: 2^28 pixels (e.g. 16384 × 16384).
/// Checked against the header before any pixel memory is allocated.
inline constexpr std::int64_t max_png_pixels = std::int64_t{1} << 28;

/// Why a PNG could not be read or written: a message a person can act on (never empty).
struct png_error {
  std::string message;
};

/// A value or a `png_error`; members named like `std::expected`. `value()` on an error is a
/// programmer error (`PERCH_ASSERT`), never an exception.
template <class T>
class [[nodiscard]] png_result {
 public:
  png_result(T v) : value_(std::move(v)) {}          // NOLINT: implicit by design
  png_result(png_error e) : error_(std::move(e)) {}  // NOLINT: implicit by design

  [[nodiscard]] bool has_value() const noexcept { return value_.has_value(); }
  explicit operator bool() const noexcept { return has_value(); }
  [[nodiscard]] T& value() & noexcept {
    PERCH_ASSERT(has_value(), "png_result::value() called on an error");
    return *value_;
  }
  [[nodiscard]] const T& value() const& noexcept {
    PERCH_ASSERT(has_value(), "png_result::value() called on an error");
    return *value_;
  }
  [[nodiscard]] T&& value() && noexcept {
    PERCH_ASSERT(has_value(), "png_result::value() called on an error");
    return std::move(*value_);
  }
  T& operator*() & noexcept { return value(); }
  const T& operator*() const& noexcept { return value(); }
  T* operator->() noexcept { return &value(); }
  const T* operator->() const noexcept { return &value(); }
  /// The error; only meaningful when `!has_value()`.
  [[nodiscard]] const png_error& error() const noexcept {
    PERCH_ASSERT(!has_value(), "png_result::error() called on a value");
    return error_;
  }

 private:
  std::optional<T> value_{};
  png_error error_{};
};

/// Success or a `png_error`: what the file writers return.
class [[nodiscard]] png_status {
 public:
  png_status() = default;
  png_status(png_error e) : ok_(false), error_(std::move(e)) {}  // NOLINT: implicit by design

  [[nodiscard]] bool has_value() const noexcept { return ok_; }
  explicit operator bool() const noexcept { return ok_; }
  /// The error; only meaningful when `!has_value()`.
  [[nodiscard]] const png_error& error() const noexcept {
    PERCH_ASSERT(!ok_, "png_status::error() called on a success");
    return error_;
  }

 private:
  bool ok_ = true;
  png_error error_{};
};

/// The colour type byte of a PNG header (PNG spec §11.2.2, Table 11.1).
enum class colour_type : std::uint8_t {
  gray = 0,
  rgb = 2,
  palette = 3,
  gray_alpha = 4,
  rgba = 6,
};

/// The interlace method of a PNG header (PNG spec §8).
enum class interlace : std::uint8_t {
  none = 0,
  adam7 = 1,
};

/// An 8-bit RGB pixel (for `to_rgb8` and the RGB writer).
struct rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  friend constexpr bool operator==(const rgb8&, const rgb8&) noexcept = default;
};

/// A decoded PNG: `height` rows of `width` pixels of `channels` interleaved samples, each of
/// `bit_depth` bits, rows dense, origin top-left.
///   - channels: 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA. Palette images are expanded to RGB (3);
///     their tRNS transparency is ignored.
///   - bit_depth: 8 or 16. Gray of 1, 2 or 4 bits is scaled exactly to 8 bits (×255, ×85,
///     ×17), so a 1-bit 1 reads as 255.
///   - samples live in `samples8` (bit_depth 8) or `samples16` (bit_depth 16, host order);
///     the other vector is empty. Index: (y × width + x) × channels + c.
/// `source_colour_type`, `source_bit_depth` and `source_interlace` describe the file.
struct decoded_png {
  int width = 0;
  int height = 0;
  int channels = 0;
  int bit_depth = 0;
  colour_type source_colour_type = colour_type::gray;
  int source_bit_depth = 0;
  interlace source_interlace = interlace::none;
  std::vector<std::uint8_t> samples8;
  std::vector<std::uint16_t> samples16;

  /// Sample `c` of pixel (x, y), in the image's bit depth (checked by `PERCH_ASSERT`).
  [[nodiscard]] std::uint16_t sample(int x, int y, int c) const noexcept {
    PERCH_ASSERT(x >= 0 && y >= 0 && x < width && y < height && c >= 0 && c < channels,
                 "decoded_png::sample: out of range");
    const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                           static_cast<std::size_t>(x)) *
                              static_cast<std::size_t>(channels) +
                          static_cast<std::size_t>(c);
    return bit_depth == 16 ? samples16[i] : samples8[i];
  }
};

/// Reader limits.
struct read_options {
  /// Images with more pixels are rejected before allocation (clamped to `max_png_pixels`).
  std::int64_t max_pixels = max_png_pixels;
};

/// Decodes a PNG held in memory.
/// Errors (each message says what and where): not a PNG signature; truncated file; a chunk
/// whose CRC does not match; chunks out of order (IHDR not first, PLTE after IDAT, IDAT not
/// consecutive, missing IDAT/IEND/PLTE, duplicates); an unknown critical chunk; a header with
/// zero or too many pixels or an invalid bit depth / colour type / method; a corrupt zlib
/// stream; decompressed data too short or too long; a filter type byte above 4; a palette
/// index outside the palette.
/// Complexity: O(file size + pixels). Memory: the output plus one copy of the filtered data.
[[nodiscard]] png_result<decoded_png> read_png(std::span<const std::uint8_t> bytes,
                                               const read_options& options = {});

/// Reads and decodes the PNG file at `path` (errors of `read_png`, plus a path that does not
/// exist, is a directory or another non-regular file, or cannot be opened or read, named in
/// the message; nothing is read from such a path).
[[nodiscard]] png_result<decoded_png> read_png_file(const std::filesystem::path& path,
                                                    const read_options& options = {});

/// 8-bit gray of a decoded image: gray as is, RGB as ITU-R BT.601 luma
/// (299 R + 587 G + 114 B + 500) / 1000, alpha ignored, palettes already expanded, 16-bit
/// samples scaled to 8 bits with rounding (v × 255 / 65535).
[[nodiscard]] image<std::uint8_t> to_gray8(const decoded_png& png);

/// A 0/1 tree mask: 1 where any colour (or gray) sample is non-zero, alpha ignored.
/// "Any non-zero pixel is tree."
[[nodiscard]] image<std::uint8_t> to_mask(const decoded_png& png);

/// 16-bit gray, e.g. a depth image in millimetres: 16-bit gray as is, 8-bit samples promoted
/// unchanged (not rescaled), RGB as BT.601 luma in the image's own bit depth, alpha ignored.
[[nodiscard]] image<std::uint16_t> to_gray16(const decoded_png& png);

/// 8-bit RGB: gray replicated into r = g = b, alpha ignored, 16-bit scaled to 8 bits.
[[nodiscard]] image<rgb8> to_rgb8(const decoded_png& png);

/// How the writer chooses each row's filter (PNG spec §9, §12.8).
enum class filter_choice : std::uint8_t {
  none,         ///< filter type 0 on every row
  minimum_sum,  ///< per row, the type with the least sum of |signed filtered bytes|; ties pick the
                ///< lowest type
};

/// Writer options. Output is deterministic for given pixels, options and zlib version.
struct write_options {
  filter_choice filter = filter_choice::minimum_sum;
  int compression_level = 6;  ///< zlib level 0..9 (clamped)
};

/// Encodes an 8-bit gray image. Errors: an invalid or empty view, more than
/// `max_png_pixels` pixels, a zlib failure. Works on any stride ≥ width.
[[nodiscard]] png_result<std::vector<std::uint8_t>> encode_png(image_view<const std::uint8_t> gray,
                                                               const write_options& options = {});
/// Encodes an 8-bit RGB image (same errors).
[[nodiscard]] png_result<std::vector<std::uint8_t>> encode_png(image_view<const rgb8> rgb,
                                                               const write_options& options = {});
/// Encodes a 16-bit gray image, e.g. radii or depth in millimetres (same errors).
[[nodiscard]] png_result<std::vector<std::uint8_t>> encode_png(image_view<const std::uint16_t> gray,
                                                               const write_options& options = {});

/// Encodes and writes an 8-bit gray PNG to `path` (errors of `encode_png`, plus a file that
/// cannot be written, named in the message).
[[nodiscard]] png_status write_png(const std::filesystem::path& path,
                                   image_view<const std::uint8_t> gray,
                                   const write_options& options = {});
/// Encodes and writes an 8-bit RGB PNG to `path`.
[[nodiscard]] png_status write_png(const std::filesystem::path& path, image_view<const rgb8> rgb,
                                   const write_options& options = {});
/// Encodes and writes a 16-bit gray PNG to `path`.
[[nodiscard]] png_status write_png(const std::filesystem::path& path,
                                   image_view<const std::uint16_t> gray,
                                   const write_options& options = {});

/// Options of an animated PNG.
struct animation_options {
  write_options png{};
  std::uint32_t plays = 0;  ///< times the animation plays; 0: forever
  /// Stores each frame after the first as only the rectangle where it differs from the frame
  /// before (dispose none, blend source): the same pictures, a smaller file.
  bool crop_to_changes = true;
};

/// Builds an animated PNG (APNG 1.0, https://wiki.mozilla.org/APNG_Specification) of 8-bit RGB
/// frames, one `add` per frame; `finish` gives the file. Frame 0 is also the default image
/// (its data is the IDAT), so a viewer or reader without APNG support (like `read_png`) sees
/// the first frame. Each frame is compressed as it is added; the encoder keeps the compressed
/// frames and one uncompressed frame (the last, to find what changed).
class apng_encoder {
 public:
  explicit apng_encoder(const animation_options& options = {}) : options_(options) {}

  /// Adds a frame shown for `delay_ms` milliseconds (0: as fast as the viewer goes). Errors: an
  /// invalid or empty view, more than `max_png_pixels` pixels, a size other than the first
  /// frame's, a zlib failure; the frame is not added then.
  [[nodiscard]] png_status add(image_view<const rgb8> frame, std::uint16_t delay_ms);
  /// Frames added.
  [[nodiscard]] std::size_t frames() const noexcept { return frames_.size(); }
  /// The file: signature, IHDR, acTL, per frame an fcTL and its data (IDAT for frame 0, fdAT
  /// for the others; fcTL and fdAT numbered 0, 1, 2, ... in file order), IEND. Error: no frame.
  [[nodiscard]] png_result<std::vector<std::uint8_t>> finish() const;

 private:
  struct stored_frame {
    std::uint32_t x = 0, y = 0, width = 0, height = 0;  ///< the region stored
    std::uint16_t delay_ms = 0;
    std::vector<std::uint8_t> compressed;  ///< its zlib stream
  };
  animation_options options_;
  std::vector<stored_frame> frames_;
  std::vector<rgb8> previous_;  ///< the last frame added, rows dense
  int width_ = 0, height_ = 0;
};

/// Writes `encoder.finish()` to `path` (its errors, plus a file that cannot be written).
[[nodiscard]] png_status write_apng(const std::filesystem::path& path, const apng_encoder& encoder);

/// CRC-32 of `bytes` as PNG chunks use it (PNG spec §5.5 and Annex D: polynomial
/// 0xEDB88320 reflected, initial and final XOR 0xFFFFFFFF). Exposed for tests and tools.
[[nodiscard]] std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept;

/// Continues a CRC-32: `crc32_update(crc32_update(0, a), b) == crc32(a ++ b)`.
[[nodiscard]] std::uint32_t crc32_update(std::uint32_t crc,
                                         std::span<const std::uint8_t> bytes) noexcept;

}  // namespace perch::png
