// SPDX-License-Identifier: BSL-1.0
/// \file
/// `json_writer`: a small streaming JSON writer (RFC 8259) into a `std::string`, for the perch
/// tool's outputs. Host code, not part of the library.
///
/// Guarantees:
///   - Deterministic: the same calls give byte-identical output (no locale, no clock, no
///     pointer values). Floating-point numbers use the shortest representation that reads
///     back to the same value (`std::to_chars` without precision), so output is short and
///     round-trips exactly; NaN and ±infinity are written as `null`.
///   - Strings are escaped: `"` and `\` with a backslash, control characters U+0000–U+001F as
///     `\b \f \n \r \t` or `\u00XX`. Valid UTF-8 passes through unchanged; each byte of an
///     invalid UTF-8 sequence becomes `\ufffd`, so the output is always valid UTF-8.
///   - Nesting is checked with `PERCH_ASSERT` (a key outside an object, a value where a key is
///     due, a mismatched end, a second top-level value) — programmer errors, never data.
///   - Nothing throws (beyond `std::bad_alloc` from `std::string`).
///
/// Styles: `json_style::compact` writes no whitespace at all; `json_style::pretty` indents by
/// two spaces, writes `"key": value`, keeps empty containers as `{}` / `[]`, and ends the
/// document with a newline once the top-level value is complete. A container opened with
/// `json_layout::single_line` (e.g. a point `[x, y]`) stays on one line in pretty mode,
/// with `, ` and `: ` separators, and so do all containers inside it.
///
/// Usage:
/// \code
///   perch::support::json_writer json(perch::support::json_style::pretty);
///   json.begin_object();
///   json.member("status", "ok");
///   json.key("image").begin_object().member("width", 640).member("height", 480).end_object();
///   json.key("xy").begin_array(perch::support::json_layout::single_line)
///       .value(1.5).value(2).end_array();
///   json.end_object();
///   std::string text = std::move(json).take();
/// \endcode
#pragma once

#include <charconv>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include "perch/core/assert.hpp"

namespace perch::support {

/// Whitespace of a whole document.
enum class json_style : std::uint8_t {
  compact,  ///< no whitespace at all
  pretty,   ///< two-space indentation, one member / element per line
};

/// Layout of one container in `json_style::pretty` (ignored in compact style).
enum class json_layout : std::uint8_t {
  multi_line,   ///< one member / element per line
  single_line,  ///< the whole container on one line, e.g. `[1, 2]`
};

/// Appends `text` to `out` as a quoted, escaped JSON string (see the file comment for the
/// escaping rules). Complexity: O(text.size()).
void append_json_string(std::string& out, std::string_view text);

/// Appends `value` as a JSON number: the shortest decimal form that reads back to the same
/// `double` (`std::to_chars`), or `null` for NaN and ±infinity. `-0.0` is written `-0`.
void append_json_number(std::string& out, double value);

/// Appends `value` as a JSON number: the shortest decimal form that reads back to the same
/// `float` (so `0.1f` is written `0.1`, not `0.10000000149011612`), or `null` if not finite.
void append_json_number(std::string& out, float value);

/// Appends an integer in decimal.
template <std::integral I>
  requires(!std::same_as<I, bool>)
void append_json_number(std::string& out, I value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  PERCH_ASSERT(ec == std::errc{}, "append_json_number: buffer too small");
  out.append(buffer, end);
}

/// A streaming JSON writer into an owned `std::string`. Every call returns `*this`, so calls
/// chain. See the file comment for the guarantees.
class json_writer {
 public:
  /// An empty document in `style`.
  explicit json_writer(json_style style = json_style::compact) : style_(style) {}

  /// Opens an object (as a value: at the top level, in an array, or after `key`).
  json_writer& begin_object(json_layout layout = json_layout::multi_line) {
    return open('{', kind::object, layout);
  }
  /// Closes the innermost object. Precondition: it is an object and no key is pending.
  json_writer& end_object() { return close('}', kind::object); }
  /// Opens an array (as a value).
  json_writer& begin_array(json_layout layout = json_layout::multi_line) {
    return open('[', kind::array, layout);
  }
  /// Closes the innermost array. Precondition: it is an array.
  json_writer& end_array() { return close(']', kind::array); }

  /// Writes a member name. Precondition: inside an object, no key pending. Keys are escaped
  /// like strings; duplicates are not detected.
  json_writer& key(std::string_view name);

  /// Writes a string value.
  json_writer& value(std::string_view text);
  /// Writes a string value (a C string; without this overload it would become a bool).
  json_writer& value(const char* text) {
    PERCH_ASSERT(text != nullptr, "json_writer::value: null C string (use null())");
    return value(std::string_view(text));
  }
  /// Writes a string value.
  json_writer& value(const std::string& text) { return value(std::string_view(text)); }
  /// Writes `true` or `false`.
  json_writer& value(bool flag);
  /// Writes `null`.
  json_writer& value(std::nullptr_t) { return null(); }
  /// Writes `null`.
  json_writer& null();
  /// Writes an integer.
  template <std::integral I>
    requires(!std::same_as<I, bool>)
  json_writer& value(I number) {
    before_value();
    append_json_number(out_, number);
    return after_value();
  }
  /// Writes a `double` (shortest round-trip form; `null` if not finite).
  json_writer& value(double number);
  /// Writes a `float` (shortest round-trip form as a float; `null` if not finite).
  json_writer& value(float number);

  /// `key(name)` then `value(v)`.
  template <class T>
  json_writer& member(std::string_view name, const T& v) {
    key(name);
    return value(v);
  }
  /// `key(name)` then `null()`.
  json_writer& member_null(std::string_view name) {
    key(name);
    return null();
  }

  /// True once exactly one top-level value has been written and every container is closed.
  [[nodiscard]] bool complete() const noexcept { return done_ && stack_.empty(); }
  /// Current nesting depth (0 at the top level).
  [[nodiscard]] std::size_t depth() const noexcept { return stack_.size(); }
  /// The text so far.
  [[nodiscard]] const std::string& str() const noexcept { return out_; }
  /// Moves the text out. Precondition: `complete()`.
  [[nodiscard]] std::string take() && {
    PERCH_ASSERT(complete(), "json_writer::take: document not complete");
    return std::move(out_);
  }

 private:
  enum class kind : std::uint8_t { object, array };
  struct frame {
    kind type;
    bool single_line;
    bool key_pending;
    std::size_t count;
  };

  void newline_and_indent(bool single_line, bool after_comma);
  void before_value();
  json_writer& after_value();
  json_writer& open(char bracket, kind type, json_layout layout);
  json_writer& close(char bracket, kind type);

  json_style style_;
  bool done_ = false;
  std::string out_;
  std::vector<frame> stack_;
};

}  // namespace perch::support
