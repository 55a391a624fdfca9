// SPDX-License-Identifier: BSL-1.0
/// \file
/// `image_view<T>`: a cheap non-owning 2-D view (pointer, width, height, row stride in elements)
/// and the concepts the algorithms check in their signatures. Coordinates are (x, y) = (column,
/// row), origin top-left, y down, everywhere in perch.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>

#include "perch/core/assert.hpp"
#include "perch/core/result.hpp"

namespace perch {

/// Largest image perch accepts: 2^30 pixels (e.g. 32768 × 32768), so every pixel index fits in
/// a signed 32-bit integer with room for neighbour offsets.
inline constexpr std::int64_t max_image_pixels = std::int64_t{1} << 30;

/// A non-owning view of `height` rows of `width` pixels of type `T`, rows `stride` elements
/// apart. `T` may be const. Copying a view is cheap and never copies pixels.
/// Works in place over a camera buffer with row padding, an Eigen row-major map
/// (`outerStride()`), an OpenCV `Mat` (`step1()`), or a firmware frame.
template <class T>
class image_view {
 public:
  using value_type = std::remove_cv_t<T>;
  using element_type = T;

  constexpr image_view() noexcept = default;
  /// A view of `width` × `height` pixels at `data`, rows `stride` elements apart (default: dense).
  /// Use `validate(view)` (or any perch algorithm, which does) to check the numbers.
  constexpr image_view(T* data, int width, int height, std::ptrdiff_t stride) noexcept
      : data_(data), width_(width), height_(height), stride_(stride) {}
  constexpr image_view(T* data, int width, int height) noexcept
      : image_view(data, width, height, width) {}

  /// A mutable view converts to a const one.
  template <class U>
    requires(std::is_same_v<const U, T> && !std::is_same_v<U, T>)
  constexpr image_view(const image_view<U>& other) noexcept  // NOLINT: implicit by design
      : data_(other.data()), width_(other.width()), height_(other.height()),
        stride_(other.stride()) {}

  [[nodiscard]] constexpr T* data() const noexcept { return data_; }
  [[nodiscard]] constexpr int width() const noexcept { return width_; }
  [[nodiscard]] constexpr int height() const noexcept { return height_; }
  [[nodiscard]] constexpr std::ptrdiff_t stride() const noexcept { return stride_; }
  [[nodiscard]] constexpr bool empty() const noexcept { return width_ <= 0 || height_ <= 0; }
  /// width × height.
  [[nodiscard]] constexpr std::size_t size() const noexcept {
    return empty() ? 0 : static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  }
  [[nodiscard]] constexpr bool contains(int x, int y) const noexcept {
    return x >= 0 && y >= 0 && x < width_ && y < height_;
  }

  /// Pixel at column `x`, row `y` (checked by `PERCH_ASSERT`).
  [[nodiscard]] constexpr T& operator()(int x, int y) const noexcept {
    PERCH_ASSERT(contains(x, y), "image_view: pixel out of range");
    return data_[static_cast<std::ptrdiff_t>(y) * stride_ + x];
  }
  /// Row `y` as a span of `width` pixels.
  [[nodiscard]] constexpr std::span<T> row(int y) const noexcept {
    PERCH_ASSERT(y >= 0 && y < height_, "image_view: row out of range");
    return {data_ + static_cast<std::ptrdiff_t>(y) * stride_, static_cast<std::size_t>(width_)};
  }
  /// The rectangle [x, x+w) × [y, y+h), clipped to the view.
  [[nodiscard]] constexpr image_view sub_view(int x, int y, int w, int h) const noexcept {
    const int x0 = x < 0 ? 0 : (x > width_ ? width_ : x);
    const int y0 = y < 0 ? 0 : (y > height_ ? height_ : y);
    const int x1 = w <= 0 ? x0 : (x + w > width_ ? width_ : (x + w < x0 ? x0 : x + w));
    const int y1 = h <= 0 ? y0 : (y + h > height_ ? height_ : (y + h < y0 ? y0 : y + h));
    T* origin = (x1 > x0 && y1 > y0) ? data_ + static_cast<std::ptrdiff_t>(y0) * stride_ + x0
                                     : nullptr;
    return image_view(origin, x1 - x0, y1 - y0, stride_);
  }

 private:
  T* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  std::ptrdiff_t stride_ = 0;
};

template <class T>
image_view(T*, int, int, std::ptrdiff_t) -> image_view<T>;
template <class T>
image_view(T*, int, int) -> image_view<T>;

/// Anything read like an image: width(), height(), v(x, y), row(y).
template <class V>
concept ImageView = requires(const V& v, int i) {
  typename V::value_type;
  { v.width() } -> std::convertible_to<int>;
  { v.height() } -> std::convertible_to<int>;
  { v.stride() } -> std::convertible_to<std::ptrdiff_t>;
  { v.data() };
  v(i, i);
  v.row(i);
};

/// An `ImageView` whose pixels can be assigned.
template <class V>
concept MutableImageView = ImageView<V> && requires(const V& v, int i, typename V::value_type p) {
  v(i, i) = p;
};

/// An `ImageView` whose pixels test as bool (non-zero = foreground / tree).
template <class V>
concept BinaryView = ImageView<V> && requires(const V& v, int i) {
  { static_cast<bool>(v(i, i)) };
};

/// Checks that a view's numbers describe real memory: non-negative dimensions, stride ≥ width,
/// non-null data when non-empty, no overflow, at most `max_image_pixels`. An empty view is
/// valid here; algorithms that need pixels report `errc::empty_image` themselves.
template <ImageView V>
[[nodiscard]] constexpr status validate(const V& view) noexcept {
  const std::int64_t w = view.width();
  const std::int64_t h = view.height();
  if (w < 0 || h < 0) return fail(errc::bad_dimensions);
  if (w == 0 || h == 0) return {};
  if (view.data() == nullptr) return fail(errc::null_data);
  if (static_cast<std::int64_t>(view.stride()) < w) return fail(errc::stride_too_small);
  // Row offsets are ptrdiff_t: stride × height must fit the target's (32 bits on 32-bit ARM).
  constexpr std::int64_t limit = std::numeric_limits<std::ptrdiff_t>::max() / 2;
  if (static_cast<std::int64_t>(view.stride()) > limit / h) return fail(errc::size_overflow);
  if (w * h > max_image_pixels) return fail(errc::image_too_large);
  return {};
}

/// Like `validate`, and also rejects an empty view.
template <ImageView V>
[[nodiscard]] constexpr status validate_non_empty(const V& view) noexcept {
  PERCH_TRY(validate(view));
  if (view.width() == 0 || view.height() == 0) return fail(errc::empty_image);
  return {};
}

/// Checks that two views have the same width and height.
template <ImageView A, ImageView B>
[[nodiscard]] constexpr status same_size(const A& a, const B& b) noexcept {
  if (a.width() != b.width() || a.height() != b.height()) return fail(errc::size_mismatch);
  return {};
}

/// Sets every pixel of `view` to `value`.
template <MutableImageView V>
constexpr void fill(const V& view, typename V::value_type value) noexcept {
  for (int y = 0; y < view.height(); ++y)
    for (auto& p : view.row(y)) p = value;
}

/// Copies `src` into `dst` pixel by pixel (sizes must match: checked by `PERCH_ASSERT`).
template <ImageView S, MutableImageView D>
constexpr void copy(const S& src, const D& dst) noexcept {
  PERCH_ASSERT(src.width() == dst.width() && src.height() == dst.height(),
               "copy: views differ in size");
  for (int y = 0; y < src.height(); ++y) {
    const auto s = src.row(y);
    const auto d = dst.row(y);
    for (std::size_t x = 0; x < s.size(); ++x)
      d[x] = static_cast<typename D::value_type>(s[x]);
  }
}

}  // namespace perch
