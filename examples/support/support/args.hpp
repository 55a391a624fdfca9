// SPDX-License-Identifier: BSL-1.0
/// \file
/// `arg_parser`: a small command-line parser for one subcommand of the perch tool. Host code,
/// not part of the library. No exceptions: every problem comes back as a message string.
///
/// Accepted syntax:
///   - options with a value: `--top 5`, `--top=5`, and with a short name `-j 4`, `-j4`; the
///     value may start with '-' (`--roll-deg -5`) but not with "--";
///   - boolean flags: `--known-scale` (`--known-scale=...` is an error); repeating one is fine;
///   - positionals, in declaration order; `--` ends the options (all later arguments are
///     positional); a lone `-` is positional;
///   - `--help` / `-h` anywhere before `--` asks for help: `parse` then succeeds whatever else
///     is on the line, and `help_requested()` is true; likewise `--version` when `set_version`
///     gave one (`version_requested()`);
///   - the last positional may be `arg_presence::one_or_more`: it takes every remaining one.
/// Errors name what is wrong: `unknown option '--tpo' (did you mean '--top'?)`,
/// `option '--top' needs a value (K)`, `option '--top' given more than once`,
/// `missing argument MASK.png`, `unexpected argument 'x.png'`, and from the typed getters
/// `--top: expected an integer, got 'abc'`, `--top: 0 is out of range [1, 100]`.
///
/// Usage:
/// \code
///   perch::support::arg_parser args("perch detect", "Finds where to perch on a tree mask.");
///   args.add_positional("MASK.png", "tree mask; any non-zero pixel is tree");
///   args.add_option("top", "K", "number of candidates to report", "5");
///   args.add_flag("known-scale", "use the scale from the truth file");
///   if (std::string e = args.parse(argc, argv, 2); !e.empty()) { report(e); return 2; }
///   if (args.help_requested()) { std::fputs(args.help().c_str(), stdout); return 0; }
///   const auto top = args.get_int("top", 5, 1, 100);
///   if (!top) { report(top.error); return 2; }
/// \endcode
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "perch/core/assert.hpp"

namespace perch::support {

/// A typed value read from the command line, or why it could not be read (`error` non-empty;
/// `value` then holds the fallback).
template <class T>
struct arg_value {
  T value{};
  std::string error;
  [[nodiscard]] explicit operator bool() const noexcept { return error.empty(); }
};

/// Whether a positional argument must be given (`one_or_more`: the last one, repeated).
enum class arg_presence : std::uint8_t { required, optional, one_or_more };

/// Edit distance between `a` and `b`: insertions, deletions, substitutions and swaps of two
/// adjacent characters each cost 1 (optimal string alignment), so "tpo" is 1 from "top".
/// Complexity: O(|a|·|b|) time, O(|b|) memory.
[[nodiscard]] inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = b.size() + 1;
  std::vector<std::size_t> before(n), previous(n), current(n);
  for (std::size_t j = 0; j < n; ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j < n; ++j) {
      const std::size_t substitute = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitute});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        current[j] = std::min(current[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, current);
  }
  return previous[n - 1];
}

/// The candidate closest to `word` by `edit_distance`, if it is close enough to be a likely
/// typo (distance ≤ max(1, |word| / 3)); ties go to the earliest candidate.
[[nodiscard]] inline std::optional<std::string_view> closest_match(
    std::string_view word, std::span<const std::string_view> candidates) {
  std::optional<std::string_view> best;
  std::size_t best_distance = std::max<std::size_t>(1, word.size() / 3) + 1;
  for (const std::string_view c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

/// A subcommand for `format_commands`.
struct command_info {
  std::string_view name;
  std::string_view summary;
};

/// The top-level help of a tool with subcommands:
///
///     usage: perch <command> [options]
///
///     commands:
///       detect    find the best perch site in a tree mask
///       ...
///
///     Run 'perch <command> --help' for a command's options.
[[nodiscard]] inline std::string format_commands(std::string_view program,
                                                 std::span<const command_info> commands) {
  std::size_t column = 0;
  for (const command_info& c : commands) column = std::max(column, c.name.size());
  std::string out = "usage: ";
  out.append(program);
  out += " <command> [options]\n\ncommands:\n";
  for (const command_info& c : commands) {
    out += "  ";
    out.append(c.name);
    out.append(column - c.name.size() + 2, ' ');
    out.append(c.summary);
    out += '\n';
  }
  out += "\nRun '";
  out.append(program);
  out += " <command> --help' for a command's options.\n";
  return out;
}

/// A parser for one (sub)command: declare options, flags and positionals, `parse`, then read
/// typed values. See the file comment for the syntax and the messages.
class arg_parser {
 public:
  /// `usage_name` is what the usage line starts with, e.g. "perch detect"; `summary` is one
  /// or more sentences printed under it.
  arg_parser(std::string usage_name, std::string summary)
      : usage_name_(std::move(usage_name)), summary_(std::move(summary)) {}

  /// Declares `--name VALUE_NAME` (and `-short_name` if not 0). `default_text`, if not empty,
  /// is shown in the help as "(default: ...)". Precondition: the name is new.
  arg_parser& add_option(std::string name, std::string value_name, std::string help,
                         std::string default_text = {}, char short_name = 0) {
    declare(spec{std::move(name), std::move(value_name), std::move(help),
                 std::move(default_text), short_name, true});
    return *this;
  }

  /// Declares a boolean flag `--name` (and `-short_name` if not 0).
  arg_parser& add_flag(std::string name, std::string help, char short_name = 0) {
    declare(spec{std::move(name), {}, std::move(help), {}, short_name, false});
    return *this;
  }

  /// Declares the next positional argument. Precondition: no optional positional before a
  /// required one, nothing after a `one_or_more` one.
  arg_parser& add_positional(std::string name, std::string help,
                             arg_presence presence = arg_presence::required) {
    PERCH_ASSERT(positional_specs_.empty() || presence == arg_presence::optional ||
                     positional_specs_.back().presence == arg_presence::required,
                 "arg_parser: a required positional after an optional one");
    PERCH_ASSERT(positional_specs_.empty() || positional_specs_.back().presence != arg_presence::one_or_more,
                 "arg_parser: a positional after a repeated one");
    positional_specs_.push_back(positional_spec{std::move(name), std::move(help), presence});
    return *this;
  }

  /// Accepts `--version` (listed in the help): `version()` is what the caller prints.
  arg_parser& set_version(std::string text) {
    version_ = std::move(text);
    return *this;
  }
  [[nodiscard]] const std::string& version() const noexcept { return version_; }

  /// Text printed at the end of the help (examples, notes).
  arg_parser& set_epilog(std::string text) {
    epilog_ = std::move(text);
    return *this;
  }

  /// Parses `args` (without the program and subcommand names). Returns an empty string on
  /// success, else the first problem found. Resets anything parsed before.
  [[nodiscard]] std::string parse(std::span<const std::string_view> args) {
    values_.assign(specs_.size(), std::nullopt);
    flags_.assign(specs_.size(), false);
    positionals_.clear();
    help_ = false;
    version_asked_ = false;
    for (const std::string_view a : args) {
      if (a == "--") break;
      if (a == "--help" || a == "-h") help_ = true;
      if (a == "--version" && !version_.empty()) version_asked_ = true;
    }
    if (help_ || version_asked_) return {};
    bool options_done = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string_view a = args[i];
      if (options_done || a == "-" || a.size() < 2 || a[0] != '-' || looks_numeric(a)) {
        positionals_.emplace_back(a);
        continue;
      }
      if (a == "--") {
        options_done = true;
        continue;
      }
      std::string_view name;
      std::optional<std::string_view> inline_value;
      std::size_t index = 0;
      if (a[1] == '-') {
        name = a.substr(2);
        if (const std::size_t eq = name.find('='); eq != std::string_view::npos) {
          inline_value = name.substr(eq + 1);
          name = name.substr(0, eq);
        }
        index = find(name);
        if (index == npos) return unknown_option(a.substr(0, 2 + name.size()));
      } else {
        index = find_short(a[1]);
        if (index == npos) return unknown_option(a.substr(0, 2));
        if (a.size() > 2) {
          if (!specs_[index].takes_value) return "option '" + std::string(a.substr(0, 2)) +
                                                 "' takes no value";
          inline_value = a.substr(a[2] == '=' ? 3 : 2);
        }
      }
      const spec& s = specs_[index];
      const std::string shown = "--" + s.name;
      if (!s.takes_value) {
        if (inline_value) return "option '" + shown + "' takes no value";
        flags_[index] = true;
        continue;
      }
      if (values_[index]) return "option '" + shown + "' given more than once";
      if (!inline_value) {
        if (i + 1 >= args.size() || args[i + 1].starts_with("--"))
          return "option '" + shown + "' needs a value (" + s.value_name + ")";
        inline_value = args[++i];
      }
      values_[index] = std::string(*inline_value);
    }
    std::size_t required = 0;
    for (const positional_spec& p : positional_specs_)
      if (p.presence != arg_presence::optional) ++required;
    if (positionals_.size() < required)
      return "missing argument " + positional_specs_[positionals_.size()].name;
    const bool repeated_last =
        !positional_specs_.empty() && positional_specs_.back().presence == arg_presence::one_or_more;
    if (positionals_.size() > positional_specs_.size() && !repeated_last)
      return "unexpected argument '" + positionals_[positional_specs_.size()] + "'";
    return {};
  }

  /// Parses `argv[first]` .. `argv[argc - 1]` (`first` = 2 skips "perch detect").
  [[nodiscard]] std::string parse(int argc, const char* const* argv, int first = 1) {
    std::vector<std::string_view> args;
    for (int i = std::max(first, 0); i < argc; ++i)
      if (argv[i] != nullptr) args.emplace_back(argv[i]);
    return parse(std::span<const std::string_view>(args));
  }

  /// True if `--help` or `-h` was on the command line.
  [[nodiscard]] bool help_requested() const noexcept { return help_; }
  /// True if `--version` was on the command line (and `set_version` gave one).
  [[nodiscard]] bool version_requested() const noexcept { return version_asked_; }

  /// True if option or flag `name` (declared) was given.
  [[nodiscard]] bool has(std::string_view name) const {
    const std::size_t i = declared(name);
    return specs_[i].takes_value ? values_.size() > i && values_[i].has_value()
                                 : flags_.size() > i && flags_[i];
  }

  /// True if flag `name` (declared with `add_flag`) was given.
  [[nodiscard]] bool flag(std::string_view name) const {
    const std::size_t i = declared(name);
    PERCH_ASSERT(!specs_[i].takes_value, "arg_parser::flag: not a flag");
    return flags_.size() > i && flags_[i];
  }

  /// The raw text of option `name`, if given.
  [[nodiscard]] std::optional<std::string_view> value(std::string_view name) const {
    const std::size_t i = declared(name);
    PERCH_ASSERT(specs_[i].takes_value, "arg_parser::value: a flag has no value");
    if (values_.size() <= i || !values_[i]) return std::nullopt;
    return std::string_view(*values_[i]);
  }

  /// The positional declared as `name`, if given.
  [[nodiscard]] std::optional<std::string_view> positional(std::string_view name) const {
    for (std::size_t i = 0; i < positional_specs_.size(); ++i) {
      if (positional_specs_[i].name != name) continue;
      if (i < positionals_.size()) return std::string_view(positionals_[i]);
      return std::nullopt;
    }
    PERCH_ASSERT(false, "arg_parser::positional: undeclared positional");
    return std::nullopt;
  }

  /// All positionals given, in order.
  [[nodiscard]] std::span<const std::string> positionals() const noexcept { return positionals_; }

  /// Option `name` as text, or `fallback` if not given (never an error).
  [[nodiscard]] arg_value<std::string> get_string(std::string_view name,
                                                  std::string fallback = {}) const {
    const auto text = value(name);
    return {text ? std::string(*text) : std::move(fallback), {}};
  }

  /// Option `name` as an integer of type `T` in [min, max], or `fallback` if not given (the
  /// fallback is not range-checked). Errors: not an integer (the whole text must be one,
  /// decimal, optional sign), outside the range of `T`, outside [min, max].
  template <std::integral T>
  [[nodiscard]] arg_value<T> get_integer(std::string_view name, T fallback, T min, T max) const {
    const auto text = value(name);
    if (!text) return {fallback, {}};
    std::string_view digits = *text;
    if (digits.starts_with('+')) digits.remove_prefix(1);
    T parsed{};
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), parsed);
    const std::string shown = "--" + std::string(name);
    if (digits.empty() || ec == std::errc::invalid_argument ||
        end != digits.data() + digits.size())
      return {fallback, shown + ": expected an integer, got '" + std::string(*text) + "'"};
    if (ec == std::errc::result_out_of_range || parsed < min || parsed > max)
      return {fallback, shown + ": " + std::string(*text) + " is out of range [" +
                            std::to_string(min) + ", " + std::to_string(max) + "]"};
    return {parsed, {}};
  }

  /// `get_integer<int>`.
  [[nodiscard]] arg_value<int> get_int(std::string_view name, int fallback, int min,
                                       int max) const {
    return get_integer<int>(name, fallback, min, max);
  }

  /// Option `name` as a finite number in [min, max], or `fallback` if not given. Accepts
  /// decimal and scientific notation (`0.25`, `-3`, `1e-3`). Errors: not a number, not finite,
  /// outside [min, max].
  [[nodiscard]] arg_value<double> get_double(std::string_view name, double fallback, double min,
                                             double max) const {
    const auto text = value(name);
    if (!text) return {fallback, {}};
    std::string_view digits = *text;
    if (digits.starts_with('+')) digits.remove_prefix(1);
    double parsed = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), parsed,
                                           std::chars_format::general);
    const std::string shown = "--" + std::string(name);
    if (digits.empty() || ec != std::errc{} || end != digits.data() + digits.size() ||
        !std::isfinite(parsed))
      return {fallback, shown + ": expected a number, got '" + std::string(*text) + "'"};
    if (parsed < min || parsed > max)
      return {fallback, shown + ": " + std::string(*text) + " is out of range [" +
                            format_number(min) + ", " + format_number(max) + "]"};
    return {parsed, {}};
  }

  /// Option `name` as one of `choices`, or `fallback` if not given. Error: another word (the
  /// message lists the choices and suggests the closest).
  [[nodiscard]] arg_value<std::string> get_choice(std::string_view name, std::string fallback,
                                                  std::span<const std::string_view> choices) const {
    const auto text = value(name);
    if (!text) return {std::move(fallback), {}};
    for (const std::string_view c : choices)
      if (c == *text) return {std::string(c), {}};
    std::string message = "--" + std::string(name) + ": unknown value '" + std::string(*text) +
                          "' (choose from";
    for (std::size_t i = 0; i < choices.size(); ++i) {
      message += i == 0 ? " " : ", ";
      message.append(choices[i]);
    }
    message += ")";
    if (const auto near = closest_match(*text, choices))
      message += "; did you mean '" + std::string(*near) + "'?";
    return {std::move(fallback), std::move(message)};
  }

  /// The help text, from the declarations: usage line, summary, arguments, options (in
  /// declaration order, then `-h, --help`), epilog. Ends with a newline.
  [[nodiscard]] std::string help() const {
    std::string out = "usage: " + usage_name_;
    if (!specs_.empty()) out += " [options]";
    for (const positional_spec& p : positional_specs_)
      out += p.presence == arg_presence::required      ? " " + p.name
             : p.presence == arg_presence::one_or_more ? " " + p.name + "..."
                                                       : " [" + p.name + "]";
    out += "\n";
    if (!summary_.empty()) out += "\n" + summary_ + "\n";
    std::vector<std::pair<std::string, std::string>> rows;
    if (!positional_specs_.empty()) {
      for (const positional_spec& p : positional_specs_) rows.emplace_back(p.name, p.help);
    }
    const std::size_t positional_rows = rows.size();
    for (const spec& s : specs_) {
      std::string left = s.short_name != 0 ? std::string("-") + s.short_name + ", " : "";
      left += "--" + s.name;
      if (s.takes_value) left += " " + s.value_name;
      std::string right = s.help;
      if (!s.default_text.empty()) right += " (default: " + s.default_text + ")";
      rows.emplace_back(std::move(left), std::move(right));
    }
    rows.emplace_back("-h, --help", "show this help and exit");
    if (!version_.empty()) rows.emplace_back("--version", "print the version and exit");
    std::size_t column = 0;
    for (const auto& row : rows) column = std::max(column, row.first.size());
    column = std::min<std::size_t>(column, 26) + 4;
    const auto write_row = [&](const std::pair<std::string, std::string>& row) {
      std::string line = "  " + row.first;
      if (line.size() + 2 > column) {
        out += line + "\n";
        line.clear();
      }
      line.append(column - line.size(), ' ');
      std::size_t start = 0;
      while (true) {
        const std::size_t end = row.second.find('\n', start);
        out += line + row.second.substr(start, end - start) + "\n";
        if (end == std::string::npos) break;
        start = end + 1;
        line.assign(column, ' ');
      }
    };
    if (positional_rows > 0) {
      out += "\narguments:\n";
      for (std::size_t i = 0; i < positional_rows; ++i) write_row(rows[i]);
    }
    out += "\noptions:\n";
    for (std::size_t i = positional_rows; i < rows.size(); ++i) write_row(rows[i]);
    if (!epilog_.empty()) out += "\n" + epilog_ + (epilog_.ends_with('\n') ? "" : "\n");
    return out;
  }

 private:
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  struct spec {
    std::string name;
    std::string value_name;
    std::string help;
    std::string default_text;
    char short_name;
    bool takes_value;
  };
  struct positional_spec {
    std::string name;
    std::string help;
    arg_presence presence;
  };

  void declare(spec s) {
    PERCH_ASSERT(!s.name.empty() && s.name != "help", "arg_parser: empty or reserved name");
    PERCH_ASSERT(find(s.name) == npos, "arg_parser: option declared twice");
    PERCH_ASSERT(s.short_name != 'h' && (s.short_name == 0 || find_short(s.short_name) == npos),
                 "arg_parser: short name reserved or declared twice");
    specs_.push_back(std::move(s));
  }

  [[nodiscard]] std::size_t find(std::string_view name) const noexcept {
    for (std::size_t i = 0; i < specs_.size(); ++i)
      if (specs_[i].name == name) return i;
    return npos;
  }
  [[nodiscard]] std::size_t find_short(char c) const noexcept {
    for (std::size_t i = 0; i < specs_.size(); ++i)
      if (specs_[i].short_name != 0 && specs_[i].short_name == c) return i;
    return npos;
  }
  [[nodiscard]] std::size_t declared(std::string_view name) const {
    const std::size_t i = find(name);
    PERCH_ASSERT(i != npos, "arg_parser: asking for an undeclared option");
    return i;
  }

  /// "-5", "-0.25", "-.5", "-1e3": a negative number, taken as a positional.
  [[nodiscard]] bool looks_numeric(std::string_view a) const noexcept {
    if (a.size() < 2 || a[0] != '-') return false;
    if (find_short(a[1]) != npos) return false;
    return (a[1] >= '0' && a[1] <= '9') || (a[1] == '.' && a.size() > 2);
  }

  [[nodiscard]] std::string unknown_option(std::string_view shown) const {
    std::string message = "unknown option '" + std::string(shown) + "'";
    if (shown.starts_with("--")) {
      std::vector<std::string_view> names;
      for (const spec& s : specs_) names.emplace_back(s.name);
      if (const auto near = closest_match(shown.substr(2), names))
        message += " (did you mean '--" + std::string(*near) + "'?)";
    }
    return message;
  }

  [[nodiscard]] static std::string format_number(double v) {
    char buffer[64];
    const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
    if (ec != std::errc{}) return "?";
    return std::string(buffer, end);
  }

  std::string usage_name_;
  std::string summary_;
  std::string epilog_;
  std::vector<spec> specs_;
  std::vector<positional_spec> positional_specs_;
  std::vector<std::optional<std::string>> values_;
  std::vector<bool> flags_;
  std::vector<std::string> positionals_;
  bool help_ = false;
  std::string version_;
  bool version_asked_ = false;
};

}  // namespace perch::support
