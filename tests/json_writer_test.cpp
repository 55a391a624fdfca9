// SPDX-License-Identifier: BSL-1.0
#include "support/json_writer.hpp"

#include <doctest/doctest.h>

#include <csignal>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

using perch::support::json_layout;
using perch::support::json_style;
using perch::support::json_writer;

namespace {

// A tiny validating JSON parser (RFC 8259), written for this test: it rejects anything that
// is not exactly one well-formed value, and builds a tree to compare against.
struct jvalue {
  enum class type { null, boolean, number, string, array, object } kind = type::null;
  bool flag = false;
  double number = 0.0;
  std::string text;  // strings: the decoded UTF-8
  std::vector<jvalue> items;
  std::vector<std::string> keys;  // object member names, parallel to `values`
  std::vector<jvalue> values;
};

class parser {
 public:
  explicit parser(std::string_view in) : in_(in) {}

  std::optional<jvalue> document() {
    jvalue v;
    skip_ws();
    if (!parse_value(v, 0)) return std::nullopt;
    skip_ws();
    if (pos_ != in_.size()) return std::nullopt;
    return v;
  }

 private:
  bool at_end() const { return pos_ >= in_.size(); }
  char peek() const { return at_end() ? '\0' : in_[pos_]; }
  void skip_ws() {
    while (!at_end() && (peek() == ' ' || peek() == '\n' || peek() == '\r' || peek() == '\t'))
      ++pos_;
  }
  bool literal(std::string_view word) {
    if (in_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }

  bool parse_value(jvalue& v, int depth) {
    if (depth > 64) return false;
    const char c = peek();
    if (c == '{') return parse_object(v, depth);
    if (c == '[') return parse_array(v, depth);
    if (c == '"') {
      v.kind = jvalue::type::string;
      return parse_string(v.text);
    }
    if (c == 't' && literal("true")) {
      v.kind = jvalue::type::boolean;
      v.flag = true;
      return true;
    }
    if (c == 'f' && literal("false")) {
      v.kind = jvalue::type::boolean;
      return true;
    }
    if (c == 'n' && literal("null")) return true;
    return parse_number(v);
  }

  bool parse_number(jvalue& v) {
    const std::size_t start = pos_;
    if (peek() == '-') ++pos_;
    if (peek() == '0') {
      ++pos_;
    } else if (peek() >= '1' && peek() <= '9') {
      while (peek() >= '0' && peek() <= '9') ++pos_;
    } else {
      return false;
    }
    if (peek() == '.') {
      ++pos_;
      if (!(peek() >= '0' && peek() <= '9')) return false;
      while (peek() >= '0' && peek() <= '9') ++pos_;
    }
    if (peek() == 'e' || peek() == 'E') {
      ++pos_;
      if (peek() == '+' || peek() == '-') ++pos_;
      if (!(peek() >= '0' && peek() <= '9')) return false;
      while (peek() >= '0' && peek() <= '9') ++pos_;
    }
    const std::string_view digits = in_.substr(start, pos_ - start);
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v.number);
    v.kind = jvalue::type::number;
    return ec == std::errc{} && end == digits.data() + digits.size();
  }

  static void append_utf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  bool parse_string(std::string& out) {
    ++pos_;  // opening quote
    while (true) {
      if (at_end()) return false;
      const auto c = static_cast<unsigned char>(in_[pos_++]);
      if (c == '"') return true;
      if (c < 0x20) return false;  // raw control characters are invalid
      if (c != '\\') {
        out += static_cast<char>(c);
        continue;
      }
      if (at_end()) return false;
      const char e = in_[pos_++];
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
          if (pos_ + 4 > in_.size()) return false;
          std::uint32_t cp = 0;
          const auto [end, ec] = std::from_chars(in_.data() + pos_, in_.data() + pos_ + 4, cp, 16);
          if (ec != std::errc{} || end != in_.data() + pos_ + 4) return false;
          pos_ += 4;
          append_utf8(out, cp);
          break;
        }
        default: return false;
      }
    }
  }

  bool parse_array(jvalue& v, int depth) {
    ++pos_;
    v.kind = jvalue::type::array;
    skip_ws();
    if (peek() == ']') {
      ++pos_;
      return true;
    }
    while (true) {
      skip_ws();
      jvalue item;
      if (!parse_value(item, depth + 1)) return false;
      v.items.push_back(std::move(item));
      skip_ws();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      if (peek() == ']') {
        ++pos_;
        return true;
      }
      return false;
    }
  }

  bool parse_object(jvalue& v, int depth) {
    ++pos_;
    v.kind = jvalue::type::object;
    skip_ws();
    if (peek() == '}') {
      ++pos_;
      return true;
    }
    while (true) {
      skip_ws();
      if (peek() != '"') return false;
      std::string name;
      if (!parse_string(name)) return false;
      skip_ws();
      if (peek() != ':') return false;
      ++pos_;
      skip_ws();
      jvalue item;
      if (!parse_value(item, depth + 1)) return false;
      v.keys.push_back(std::move(name));
      v.values.push_back(std::move(item));
      skip_ws();
      if (peek() == ',') {
        ++pos_;
        continue;
      }
      if (peek() == '}') {
        ++pos_;
        return true;
      }
      return false;
    }
  }

  std::string_view in_;
  std::size_t pos_ = 0;
};

std::optional<jvalue> parse(std::string_view text) { return parser(text).document(); }

const jvalue* member(const jvalue& v, std::string_view name) {
  for (std::size_t i = 0; i < v.keys.size(); ++i)
    if (v.keys[i] == name) return &v.values[i];
  return nullptr;
}

std::string string_value(std::string_view s) {
  json_writer w;
  w.value(s);
  return std::move(w).take();
}

}  // namespace

TEST_CASE("json test parser: rejects malformed documents (so the parse-back checks can fail)") {
  CHECK(parse("{\"a\": [1, 2.5e-3, true, null, \"x\"]}"));
  CHECK_FALSE(parse("{\"a\": 1,}"));
  CHECK_FALSE(parse("[1 2]"));
  CHECK_FALSE(parse("\"tab\there\""));
  CHECK_FALSE(parse("01"));
  CHECK_FALSE(parse("1."));
  CHECK_FALSE(parse("NaN"));
  CHECK_FALSE(parse("{} {}"));
  CHECK_FALSE(parse("{\"a\" 1}"));
  CHECK_FALSE(parse("\"\\x\""));
}

TEST_CASE("json_writer: compact output of every value kind") {
  json_writer w;
  w.begin_object();
  w.member("s", "hi").member("i", -42).member("u", std::uint64_t{18446744073709551615ull});
  w.member("d", 0.5).member("t", true).member("f", false).member_null("n");
  w.key("a").begin_array().value(1).value("x").null().end_array();
  w.key("e").begin_object().end_object();
  w.key("ea").begin_array().end_array();
  w.end_object();
  REQUIRE(w.complete());
  CHECK(w.str() ==
        R"({"s":"hi","i":-42,"u":18446744073709551615,"d":0.5,"t":true,"f":false,"n":null,)"
        R"("a":[1,"x",null],"e":{},"ea":[]})");
}

TEST_CASE("json_writer: pretty output with two-space indent and single-line containers") {
  json_writer w(json_style::pretty);
  w.begin_object();
  w.member("status", "ok");
  w.key("image").begin_object().member("width", 3).member("height", 2).end_object();
  w.key("empty").begin_array().end_array();
  w.key("polyline").begin_array();
  w.begin_array(json_layout::single_line).value(1).value(2).end_array();
  w.begin_array(json_layout::single_line).value(3).value(4.5).end_array();
  w.end_array();
  w.key("p").begin_object(json_layout::single_line).member("x", 1).key("q").begin_array().value(
      true).end_array().end_object();
  w.end_object();
  const std::string expected = R"({
  "status": "ok",
  "image": {
    "width": 3,
    "height": 2
  },
  "empty": [],
  "polyline": [
    [1, 2],
    [3, 4.5]
  ],
  "p": {"x": 1, "q": [true]}
}
)";
  CHECK(w.str() == expected);
  CHECK(parse(w.str()));
}

TEST_CASE("json_writer: string escaping") {
  CHECK(string_value("plain") == R"("plain")");
  CHECK(string_value("a\"b") == R"("a\"b")");
  CHECK(string_value("back\\slash") == R"("back\\slash")");
  CHECK(string_value("\n\r\t\b\f") == R"("\n\r\t\b\f")");
  CHECK(string_value(std::string_view("\0\x01\x1f", 3)) == R"("\u0000\u0001\u001f")");
  CHECK(string_value("\x7f/") == "\"\x7f/\"");  // DEL and '/' need no escape
  // Valid UTF-8 passes through: é (2 bytes), € (3 bytes), 𝄞 (4 bytes).
  CHECK(string_value("\xc3\xa9\xe2\x82\xac\xf0\x9d\x84\x9e") ==
        "\"\xc3\xa9\xe2\x82\xac\xf0\x9d\x84\x9e\"");
  // Invalid UTF-8 becomes U+FFFD, byte by byte: a lone continuation byte, a truncated
  // sequence, an overlong '/', a UTF-16 surrogate, a code point above U+10FFFF, 0xFF.
  CHECK(string_value("a\x80z") == R"("a\ufffdz")");
  CHECK(string_value("\xe2\x82") == R"("\ufffd\ufffd")");
  CHECK(string_value("\xc0\xaf") == R"("\ufffd\ufffd")");
  CHECK(string_value("\xed\xa0\x80") == R"("\ufffd\ufffd\ufffd")");
  CHECK(string_value("\xf4\x90\x80\x80") == R"("\ufffd\ufffd\ufffd\ufffd")");
  CHECK(string_value("\xff") == R"("\ufffd")");
  // Keys are escaped the same way.
  json_writer w;
  w.begin_object().member("k\"\n", 1).end_object();
  CHECK(w.str() == R"({"k\"\n":1})");
}

TEST_CASE("json_writer: every byte string parses back to itself (or with U+FFFD)") {
  std::mt19937 rng(20240611u);
  std::uniform_int_distribution<int> byte(0, 127);
  for (int round = 0; round < 500; ++round) {
    std::string s(static_cast<std::size_t>(round % 40), '\0');
    for (char& c : s) c = static_cast<char>(byte(rng));
    const std::string json = string_value(s);
    const auto parsed = parse(json);
    REQUIRE(parsed);
    CHECK(parsed->text == s);
  }
  // Arbitrary bytes (including invalid UTF-8) always give a valid document.
  std::uniform_int_distribution<int> any(0, 255);
  for (int round = 0; round < 500; ++round) {
    std::string s(static_cast<std::size_t>(round % 30), '\0');
    for (char& c : s) c = static_cast<char>(any(rng));
    CHECK(parse(string_value(s)));
  }
}

TEST_CASE("json_writer: numbers are short, round-trip exactly, non-finite is null") {
  const auto number_text = [](auto v) {
    json_writer w;
    w.value(v);
    return std::move(w).take();
  };
  CHECK(number_text(0.1) == "0.1");
  CHECK(number_text(0.1f) == "0.1");
  CHECK(number_text(100.0) == "100");
  CHECK(number_text(-0.0) == "-0");
  CHECK(number_text(1e21) == "1e+21");
  CHECK(number_text(std::numeric_limits<double>::quiet_NaN()) == "null");
  CHECK(number_text(std::numeric_limits<double>::infinity()) == "null");
  CHECK(number_text(-std::numeric_limits<float>::infinity()) == "null");
  CHECK(number_text(std::numeric_limits<std::int64_t>::min()) == "-9223372036854775808");
  CHECK(number_text(static_cast<unsigned char>(7)) == "7");

  std::mt19937_64 rng(7u);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  json_writer w;
  std::vector<double> values;
  w.begin_array();
  for (int i = 0; i < 2000; ++i) {
    const double v = std::ldexp(mantissa(rng), exponent(rng));
    values.push_back(v);
    w.value(v);
  }
  w.value(std::numeric_limits<double>::min()).value(std::numeric_limits<double>::max());
  w.value(std::numeric_limits<double>::denorm_min());
  values.push_back(std::numeric_limits<double>::min());
  values.push_back(std::numeric_limits<double>::max());
  values.push_back(std::numeric_limits<double>::denorm_min());
  w.end_array();
  const auto parsed = parse(w.str());
  REQUIRE(parsed);
  REQUIRE(parsed->items.size() == values.size());
  for (std::size_t i = 0; i < values.size(); ++i) CHECK(parsed->items[i].number == values[i]);

  // Floats round-trip as floats.
  std::uniform_real_distribution<float> f(-1000.0f, 1000.0f);
  for (int i = 0; i < 1000; ++i) {
    const float v = f(rng);
    const std::string text = number_text(v);
    float back = 0.0f;
    std::from_chars(text.data(), text.data() + text.size(), back);
    CHECK(back == v);
    CHECK(text.size() <= 16);
  }
}

TEST_CASE("json_writer: identical calls give byte-identical output") {
  const auto build = [] {
    json_writer w(json_style::pretty);
    w.begin_object();
    w.member("status", "no_perch").member_null("perch");
    w.key("candidates").begin_array();
    for (int i = 0; i < 5; ++i)
      w.begin_object().member("x", i * 1.25).member("y", 1.0 / (i + 3)).end_object();
    w.end_array();
    w.key("rejected").begin_object().member("slope", 3).member("diameter", 0).end_object();
    w.end_object();
    return std::move(w).take();
  };
  const std::string a = build();
  const std::string b = build();
  CHECK(a == b);
  const auto parsed = parse(a);
  REQUIRE(parsed);
  REQUIRE(member(*parsed, "status"));
  CHECK(member(*parsed, "status")->text == "no_perch");
  CHECK(member(*parsed, "perch")->kind == jvalue::type::null);
  CHECK(member(*parsed, "candidates")->items.size() == 5);
  CHECK(member(*parsed, "candidates")->items[2].values[1].number == 1.0 / 5);
}

TEST_CASE("json_writer: top-level scalars and completeness") {
  json_writer w;
  CHECK_FALSE(w.complete());
  w.begin_array();
  CHECK(w.depth() == 1);
  CHECK_FALSE(w.complete());
  w.end_array();
  CHECK(w.complete());
  json_writer p(json_style::pretty);
  p.value(3);
  CHECK(p.str() == "3\n");
  CHECK(p.complete());
}

namespace {
// Runs `f` in a child process and reports whether it aborted (a failed PERCH_ASSERT).
template <class F>
bool aborts(F f) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::signal(SIGABRT, SIG_DFL);  // not doctest's crash reporter
    f();
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT;
}
}  // namespace

TEST_CASE("json_writer: nesting mistakes fail PERCH_ASSERT") {
  CHECK_FALSE(aborts([] {
    json_writer w;
    w.begin_object().key("a").value(1).end_object();
  }));
  CHECK(aborts([] {
    json_writer w;
    w.begin_array().key("a");
  }));
  CHECK(aborts([] {
    json_writer w;
    w.begin_object().value(1);
  }));
  CHECK(aborts([] {
    json_writer w;
    w.begin_object().end_array();
  }));
  CHECK(aborts([] {
    json_writer w;
    w.begin_object().key("a").end_object();
  }));
  CHECK(aborts([] {
    json_writer w;
    w.value(1).value(2);
  }));
  CHECK(aborts([] {
    json_writer w;
    w.begin_array();
    static_cast<void>(std::move(w).take());
  }));
}
