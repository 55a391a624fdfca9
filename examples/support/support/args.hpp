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
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word` by `edit_distance`, if it is close enough to be a likely
/// typo (distance ≤ max(1, |word| / 3)); ties go to the earliest candidate.
[[nodiscard]] std::optional<std::string_view> closest_match(
    std::string_view word, std::span<const std::string_view> candidates);

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
[[nodiscard]] std::string format_commands(std::string_view program,
                                          std::span<const command_info> commands);

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
                         std::string default_text = {}, char short_name = 0);

  /// Declares a boolean flag `--name` (and `-short_name` if not 0).
  arg_parser& add_flag(std::string name, std::string help, char short_name = 0);

  /// Declares the next positional argument. Precondition: no optional positional before a
  /// required one, nothing after a `one_or_more` one.
  arg_parser& add_positional(std::string name, std::string help,
                             arg_presence presence = arg_presence::required);

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
  [[nodiscard]] std::string parse(std::span<const std::string_view> args);

  /// Parses `argv[first]` .. `argv[argc - 1]` (`first` = 2 skips "perch detect").
  [[nodiscard]] std::string parse(int argc, const char* const* argv, int first = 1);

  /// True if `--help` or `-h` was on the command line.
  [[nodiscard]] bool help_requested() const noexcept { return help_; }
  /// True if `--version` was on the command line (and `set_version` gave one).
  [[nodiscard]] bool version_requested() const noexcept { return version_asked_; }

  /// True if option or flag `name` (declared) was given.
  [[nodiscard]] bool has(std::string_view name) const;

  /// True if flag `name` (declared with `add_flag`) was given.
  [[nodiscard]] bool flag(std::string_view name) const;

  /// The raw text of option `name`, if given.
  [[nodiscard]] std::optional<std::string_view> value(std::string_view name) const;

  /// The positional declared as `name`, if given.
  [[nodiscard]] std::optional<std::string_view> positional(std::string_view name) const;

  /// All positionals given, in order.
  [[nodiscard]] std::span<const std::string> positionals() const noexcept { return positionals_; }

  /// Option `name` as text, or `fallback` if not given (never an error).
  [[nodiscard]] arg_value<std::string> get_string(std::string_view name,
                                                  std::string fallback = {}) const;

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
                                             double max) const;

  /// Option `name` as one of `choices`, or `fallback` if not given. Error: another word (the
  /// message lists the choices and suggests the closest).
  [[nodiscard]] arg_value<std::string> get_choice(std::string_view name, std::string fallback,
                                                  std::span<const std::string_view> choices) const;

  /// The help text, from the declarations: usage line, summary, arguments, options (in
  /// declaration order, then `-h, --help`), epilog. Ends with a newline.
  [[nodiscard]] std::string help() const;

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

  void declare(spec s);

  [[nodiscard]] std::size_t find(std::string_view name) const noexcept;
  [[nodiscard]] std::size_t find_short(char c) const noexcept;
  [[nodiscard]] std::size_t declared(std::string_view name) const;

  /// "-5", "-0.25", "-.5", "-1e3": a negative number, taken as a positional.
  [[nodiscard]] bool looks_numeric(std::string_view a) const noexcept;

  [[nodiscard]] std::string unknown_option(std::string_view shown) const;

  [[nodiscard]] static std::string format_number(double v);

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
