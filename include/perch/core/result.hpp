// SPDX-License-Identifier: BSL-1.0
/// \file
/// Error codes, `error`, and `result<T>`: how every perch function reports a data outcome it
/// cannot turn into a value. Members are named like `std::expected` (C++23) so code moves over
/// unchanged. Nothing here throws or allocates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>

#include "perch/core/assert.hpp"

namespace perch {

/// Why a call could not produce its value. Each code has an actionable message (`to_string`).
enum class errc : std::uint8_t {
  null_data,               ///< a view has a null pointer but a non-zero size
  bad_dimensions,          ///< a width or height is negative
  empty_image,             ///< a width or height is zero
  size_overflow,           ///< width × height or stride × height overflows
  stride_too_small,        ///< a row stride is smaller than the width
  image_too_large,         ///< more pixels than perch's documented limit
  size_mismatch,           ///< two views that must match in size do not
  invalid_parameter,       ///< a parameter is NaN, infinite, negative or zero where it may not be
  range_inverted,          ///< a range has min > max
  weights_not_normalised,  ///< scorer weights λ are negative or do not sum to 1
  workspace_too_small,     ///< a borrowed workspace buffer cannot hold what the call needs
  capacity_exceeded,       ///< more items than a fixed capacity allows
  out_of_memory,           ///< the workspace's upstream memory resource returned nothing
  no_valid_depth,          ///< a depth view has no valid (non-zero) sample where one is needed
};

/// A message a person can act on, for every code.
[[nodiscard]] constexpr std::string_view to_string(errc code) noexcept {
  switch (code) {
    case errc::null_data:
      return "image view has a null data pointer but a non-zero size: pass the pixel buffer";
    case errc::bad_dimensions:
      return "image width or height is negative: check the dimensions passed to the view";
    case errc::empty_image:
      return "image has zero width or height: there is nothing to analyse";
    case errc::size_overflow:
      return "image dimensions overflow (width x height or stride x height): check them";
    case errc::stride_too_small:
      return "row stride is smaller than the width: the stride counts elements per row, >= width";
    case errc::image_too_large:
      return "image has more pixels than perch supports (2^30): downscale it first";
    case errc::size_mismatch:
      return "two views that must have the same size differ: resize or crop one to match";
    case errc::invalid_parameter:
      return "a parameter is NaN, infinite, negative or zero where a positive value is needed";
    case errc::range_inverted:
      return "a range has its minimum above its maximum: swap or correct the bounds";
    case errc::weights_not_normalised:
      return "scorer weights must be >= 0 and sum to 1 (within 1e-4): rescale them";
    case errc::workspace_too_small:
      return "the workspace buffer is too small: give it at least error::needed bytes";
    case errc::capacity_exceeded:
      return "more items than the fixed capacity allows: raise the capacity in the options";
    case errc::out_of_memory:
      return "the workspace's memory resource could not provide memory";
    case errc::no_valid_depth:
      return "the depth view has no valid (non-zero) sample where one is needed";
  }
  return "unknown perch error";
}

/// An error: the code, an optional static detail naming the culprit (e.g. the parameter), and
/// for `workspace_too_small` / `capacity_exceeded` the amount that would have been needed.
struct error {
  errc code = errc::invalid_parameter;
  std::string_view detail{};  ///< static text naming what failed, e.g. "options.stride_mm"
  std::size_t needed = 0;     ///< bytes or items needed, where the code says so

  [[nodiscard]] constexpr std::string_view message() const noexcept { return to_string(code); }
  friend constexpr bool operator==(const error& a, const error& b) noexcept {
    return a.code == b.code && a.detail == b.detail && a.needed == b.needed;
  }
};

/// Tag to construct an error result explicitly, like `std::unexpected`.
struct unexpected {
  perch::error value;
  constexpr explicit unexpected(perch::error e) noexcept : value(e) {}
  constexpr explicit unexpected(errc code, std::string_view detail = {},
                                std::size_t needed = 0) noexcept
      : value{code, detail, needed} {}
};

/// A value or an error. `[[nodiscard]]`; `value()` on an error is a programmer error
/// (`PERCH_ASSERT`), never an exception.
template <class T>
class [[nodiscard]] result {
 public:
  using value_type = T;
  using error_type = perch::error;

  constexpr result(const T& v) : value_(v) {}                  // NOLINT: implicit by design
  constexpr result(T&& v) : value_(std::move(v)) {}            // NOLINT: implicit by design
  constexpr result(unexpected u) noexcept : error_(u.value) {}  // NOLINT: implicit by design

  [[nodiscard]] constexpr bool has_value() const noexcept { return value_.has_value(); }
  constexpr explicit operator bool() const noexcept { return has_value(); }

  [[nodiscard]] constexpr T& value() & noexcept {
    PERCH_ASSERT(has_value(), "result::value() called on an error");
    return *value_;
  }
  [[nodiscard]] constexpr const T& value() const& noexcept {
    PERCH_ASSERT(has_value(), "result::value() called on an error");
    return *value_;
  }
  [[nodiscard]] constexpr T&& value() && noexcept {
    PERCH_ASSERT(has_value(), "result::value() called on an error");
    return std::move(*value_);
  }
  constexpr T& operator*() & noexcept { return value(); }
  constexpr const T& operator*() const& noexcept { return value(); }
  constexpr T* operator->() noexcept { return &value(); }
  constexpr const T* operator->() const noexcept { return &value(); }

  template <class U>
  [[nodiscard]] constexpr T value_or(U&& fallback) const& {
    return has_value() ? *value_ : static_cast<T>(std::forward<U>(fallback));
  }

  /// The error; only meaningful when `!has_value()`.
  [[nodiscard]] constexpr const perch::error& error() const noexcept {
    PERCH_ASSERT(!has_value(), "result::error() called on a value");
    return error_;
  }

 private:
  std::optional<T> value_{};
  perch::error error_{};
};

/// `result<void>`: success or an error.
template <>
class [[nodiscard]] result<void> {
 public:
  using value_type = void;
  using error_type = perch::error;

  constexpr result() noexcept = default;
  constexpr result(unexpected u) noexcept : ok_(false), error_(u.value) {}  // NOLINT: implicit

  [[nodiscard]] constexpr bool has_value() const noexcept { return ok_; }
  constexpr explicit operator bool() const noexcept { return ok_; }
  constexpr void value() const noexcept {
    PERCH_ASSERT(ok_, "result<void>::value() called on an error");
  }
  [[nodiscard]] constexpr const perch::error& error() const noexcept {
    PERCH_ASSERT(!ok_, "result::error() called on a success");
    return error_;
  }

 private:
  bool ok_ = true;
  perch::error error_{};
};

/// Success or an error: what a function with outputs in caller buffers returns.
using status = result<void>;

/// Shorthand for an error result of any type.
[[nodiscard]] constexpr unexpected fail(errc code, std::string_view detail = {},
                                        std::size_t needed = 0) noexcept {
  return unexpected{code, detail, needed};
}

/// Success when every one of `results` holds a value, else the first one's error: the one way
/// to pass on the errors of results already in hand (several workspace arrays taken at once,
/// or one), with `PERCH_TRY(all_ok(a, b, c))`. Reads them in place.
template <class... R>
[[nodiscard]] constexpr status all_ok(const R&... results) noexcept {
  status out{};
  ((out.has_value() && !results.has_value() ? void(out = unexpected{results.error()}) : void()),
   ...);
  return out;
}

}  // namespace perch

/// Returns the error of `expr` (a result) from the enclosing function if it holds one.
#define PERCH_TRY(expr)                                                    \
  do {                                                                     \
    if (auto perch_try_result_ = (expr); !perch_try_result_.has_value())   \
      return ::perch::unexpected{perch_try_result_.error()};               \
  } while (false)
