// SPDX-License-Identifier: BSL-1.0
/// \file
/// A small JSON reader (RFC 8259) for the perch tool's own files (truth JSON of `perch synth`)
/// and its tests. Host code; no exceptions: a parse failure returns `std::nullopt` and a
/// message. Numbers are read as `double`; nesting is limited to 64 levels.
#pragma once

#include <charconv>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace perch::tool {

struct json_member;

/// A parsed JSON value.
struct json_value {
  enum class type : unsigned char { null, boolean, number, string, array, object };
  type kind = type::null;
  bool boolean = false;
  double number = 0;
  std::string text;
  std::vector<json_value> items;                              ///< array elements
  std::vector<json_member> members;  ///< object members, in order

  /// The member named `key` of an object, or null.
  [[nodiscard]] const json_value* find(std::string_view key) const;
  [[nodiscard]] bool is_number() const { return kind == type::number; }
  [[nodiscard]] bool is_array() const { return kind == type::array; }
  [[nodiscard]] bool is_object() const { return kind == type::object; }
  [[nodiscard]] bool is_string() const { return kind == type::string; }
};

/// One member of an object.
struct json_member {
  std::string key;
  json_value value;
};

inline const json_value* json_value::find(std::string_view key) const {
  if (kind != type::object) return nullptr;
  for (const json_member& m : members)
    if (m.key == key) return &m.value;
  return nullptr;
}

namespace detail {

class json_parser {
 public:
  explicit json_parser(std::string_view text) : s_(text) {}

  std::optional<json_value> document(std::string& error) {
    json_value v;
    if (!value(v, 0)) {
      error = error_ + " at byte " + std::to_string(i_);
      return std::nullopt;
    }
    skip();
    if (i_ != s_.size()) {
      error = "trailing characters at byte " + std::to_string(i_);
      return std::nullopt;
    }
    return v;
  }

 private:
  void skip() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t')) ++i_;
  }
  bool fail(const char* what) {
    error_ = what;
    return false;
  }
  bool literal(std::string_view word) {
    if (s_.substr(i_, word.size()) != word) return fail("invalid literal");
    i_ += word.size();
    return true;
  }
  bool string(std::string& out) {
    ++i_;  // opening quote
    while (i_ < s_.size()) {
      const char c = s_[i_++];
      if (c == '"') return true;
      if (static_cast<unsigned char>(c) < 0x20) return fail("control character in string");
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) break;
      const char e = s_[i_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          if (i_ + 4 > s_.size()) return fail("short \\u escape");
          unsigned code = 0;
          const auto [end, ec] = std::from_chars(s_.data() + i_, s_.data() + i_ + 4, code, 16);
          if (ec != std::errc{} || end != s_.data() + i_ + 4) return fail("bad \\u escape");
          i_ += 4;
          if (code < 0x80) {
            out += static_cast<char>(code);
          } else if (code < 0x800) {
            out += static_cast<char>(0xC0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3F));
          } else {  // surrogates are kept as they are (the tool never writes them)
            out += static_cast<char>(0xE0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (code & 0x3F));
          }
          break;
        }
        default:
          return fail("bad escape");
      }
    }
    return fail("unterminated string");
  }
  bool value(json_value& v, int depth) {
    if (depth > 64) return fail("nesting too deep");
    skip();
    if (i_ >= s_.size()) return fail("unexpected end");
    const char c = s_[i_];
    if (c == 'n') return literal("null");
    if (c == 't') {
      v.kind = json_value::type::boolean;
      v.boolean = true;
      return literal("true");
    }
    if (c == 'f') {
      v.kind = json_value::type::boolean;
      return literal("false");
    }
    if (c == '"') {
      v.kind = json_value::type::string;
      return string(v.text);
    }
    if (c == '[') {
      v.kind = json_value::type::array;
      ++i_;
      skip();
      if (i_ < s_.size() && s_[i_] == ']') {
        ++i_;
        return true;
      }
      while (true) {
        v.items.emplace_back();
        if (!value(v.items.back(), depth + 1)) return false;
        skip();
        if (i_ >= s_.size()) return fail("unterminated array");
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (s_[i_] == ']') {
          ++i_;
          return true;
        }
        return fail("expected , or ]");
      }
    }
    if (c == '{') {
      v.kind = json_value::type::object;
      ++i_;
      skip();
      if (i_ < s_.size() && s_[i_] == '}') {
        ++i_;
        return true;
      }
      while (true) {
        skip();
        if (i_ >= s_.size() || s_[i_] != '"') return fail("expected a member name");
        std::string key;
        if (!string(key)) return false;
        skip();
        if (i_ >= s_.size() || s_[i_] != ':') return fail("expected :");
        ++i_;
        v.members.push_back(json_member{std::move(key), json_value{}});
        if (!value(v.members.back().value, depth + 1)) return false;
        skip();
        if (i_ >= s_.size()) return fail("unterminated object");
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (s_[i_] == '}') {
          ++i_;
          return true;
        }
        return fail("expected , or }");
      }
    }
    if (c == '-' || (c >= '0' && c <= '9')) {
      v.kind = json_value::type::number;
      const auto [end, ec] = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v.number);
      if (ec != std::errc{}) return fail("bad number");
      i_ = static_cast<std::size_t>(end - s_.data());
      return true;
    }
    return fail("unexpected character");
  }

  std::string_view s_;
  std::size_t i_ = 0;
  std::string error_;
};

}  // namespace detail

/// Parses `text`; on failure returns nullopt and sets `error`.
[[nodiscard]] inline std::optional<json_value> parse_json(std::string_view text, std::string& error) {
  return detail::json_parser(text).document(error);
}

}  // namespace perch::tool
