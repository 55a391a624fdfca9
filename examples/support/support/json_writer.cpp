// SPDX-License-Identifier: BSL-1.0
// json_writer.hpp's JSON writer, compiled once into perch_support.
#include "support/json_writer.hpp"

namespace perch::support {

void append_json_string(std::string& out, std::string_view text) {
  static constexpr char hex[] = "0123456789abcdef";
  out += '"';
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  std::size_t i = 0;
  while (i < text.size()) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\b': out += "\\b"; break;
        case '\f': out += "\\f"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        default:
          if (c < 0x20) {
            out += "\\u00";
            out += hex[c >> 4];
            out += hex[c & 0xF];
          } else {
            out += static_cast<char>(c);
          }
      }
      ++i;
      continue;
    }
    // A multi-byte UTF-8 sequence: check lead byte, continuation bytes, overlongs, surrogates
    // and the U+10FFFF limit (RFC 3629, section 4).
    std::size_t length = 0;
    std::uint32_t code = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      length = 2;
      code = c & 0x1Fu;
    } else if (c >= 0xE0 && c <= 0xEF) {
      length = 3;
      code = c & 0x0Fu;
    } else if (c >= 0xF0 && c <= 0xF4) {
      length = 4;
      code = c & 0x07u;
    }
    bool valid = length != 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) {
      const unsigned char cont = byte(i + k);
      if ((cont & 0xC0u) != 0x80u) valid = false;
      code = (code << 6) | (cont & 0x3Fu);
    }
    if (valid) {
      if (length == 3 && (code < 0x800 || (code >= 0xD800 && code <= 0xDFFF))) valid = false;
      if (length == 4 && (code < 0x10000 || code > 0x10FFFF)) valid = false;
    }
    if (valid) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      out += "\\ufffd";
      ++i;
    }
  }
  out += '"';
}

void append_json_number(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  PERCH_ASSERT(ec == std::errc{}, "append_json_number: buffer too small");
  out.append(buffer, end);
}

void append_json_number(std::string& out, float value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  PERCH_ASSERT(ec == std::errc{}, "append_json_number: buffer too small");
  out.append(buffer, end);
}

json_writer& json_writer::key(std::string_view name) {
  PERCH_ASSERT(!stack_.empty() && stack_.back().type == kind::object,
               "json_writer::key: not inside an object");
  PERCH_ASSERT(!stack_.back().key_pending, "json_writer::key: a key is already pending");
  frame& f = stack_.back();
  if (f.count > 0) out_ += ',';
  newline_and_indent(f.single_line, f.count > 0);
  append_json_string(out_, name);
  out_ += ':';
  if (style_ == json_style::pretty) out_ += ' ';
  f.key_pending = true;
  return *this;
}

json_writer& json_writer::value(std::string_view text) {
  before_value();
  append_json_string(out_, text);
  return after_value();
}

json_writer& json_writer::value(bool flag) {
  before_value();
  out_ += flag ? "true" : "false";
  return after_value();
}

json_writer& json_writer::null() {
  before_value();
  out_ += "null";
  return after_value();
}

json_writer& json_writer::value(double number) {
  before_value();
  append_json_number(out_, number);
  return after_value();
}

json_writer& json_writer::value(float number) {
  before_value();
  append_json_number(out_, number);
  return after_value();
}

void json_writer::newline_and_indent(bool single_line, bool after_comma) {
  if (style_ != json_style::pretty) return;
  if (single_line) {
    if (after_comma) out_ += ' ';
    return;
  }
  out_ += '\n';
  out_.append(2 * stack_.size(), ' ');
}

void json_writer::before_value() {
  PERCH_ASSERT(!done_, "json_writer: a second top-level value");
  if (stack_.empty()) return;
  frame& f = stack_.back();
  if (f.type == kind::object) {
    PERCH_ASSERT(f.key_pending, "json_writer: a value inside an object needs a key first");
    return;  // key() wrote the separator and indentation
  }
  if (f.count > 0) out_ += ',';
  newline_and_indent(f.single_line, f.count > 0);
}

json_writer& json_writer::after_value() {
  if (stack_.empty()) {
    done_ = true;
    if (style_ == json_style::pretty) out_ += '\n';
    return *this;
  }
  frame& f = stack_.back();
  f.key_pending = false;
  ++f.count;
  return *this;
}

json_writer& json_writer::open(char bracket, kind type, json_layout layout) {
  before_value();
  const bool single =
      layout == json_layout::single_line || (!stack_.empty() && stack_.back().single_line);
  out_ += bracket;
  stack_.push_back(frame{type, single, false, 0});
  return *this;
}

json_writer& json_writer::close(char bracket, kind type) {
  PERCH_ASSERT(!stack_.empty() && stack_.back().type == type,
               "json_writer: end does not match the innermost container");
  PERCH_ASSERT(!stack_.back().key_pending, "json_writer: a key without a value");
  const frame f = stack_.back();
  stack_.pop_back();
  if (f.count > 0 && !f.single_line && style_ == json_style::pretty) {
    out_ += '\n';
    out_.append(2 * stack_.size(), ' ');
  }
  out_ += bracket;
  return after_value();
}

}  // namespace perch::support
