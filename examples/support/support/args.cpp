// SPDX-License-Identifier: BSL-1.0
// args.hpp's command-line parser, compiled once into perch_support.
#include "support/args.hpp"

namespace perch::support {

std::size_t edit_distance(std::string_view a, std::string_view b) {
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

std::optional<std::string_view> closest_match(std::string_view word,
                                              std::span<const std::string_view> candidates) {
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

std::string format_commands(std::string_view program, std::span<const command_info> commands) {
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

arg_parser& arg_parser::add_option(std::string name, std::string value_name, std::string help,
                                   std::string default_text, char short_name) {
  declare(spec{std::move(name), std::move(value_name), std::move(help),
               std::move(default_text), short_name, true});
  return *this;
}

arg_parser& arg_parser::add_flag(std::string name, std::string help, char short_name) {
  declare(spec{std::move(name), {}, std::move(help), {}, short_name, false});
  return *this;
}

arg_parser& arg_parser::add_positional(std::string name, std::string help, arg_presence presence) {
  PERCH_ASSERT(positional_specs_.empty() || presence == arg_presence::optional ||
                   positional_specs_.back().presence == arg_presence::required,
               "arg_parser: a required positional after an optional one");
  PERCH_ASSERT(positional_specs_.empty() || positional_specs_.back().presence != arg_presence::one_or_more,
               "arg_parser: a positional after a repeated one");
  positional_specs_.push_back(positional_spec{std::move(name), std::move(help), presence});
  return *this;
}

std::string arg_parser::parse(std::span<const std::string_view> args) {
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

std::string arg_parser::parse(int argc, const char* const* argv, int first) {
  std::vector<std::string_view> args;
  for (int i = std::max(first, 0); i < argc; ++i)
    if (argv[i] != nullptr) args.emplace_back(argv[i]);
  return parse(std::span<const std::string_view>(args));
}

bool arg_parser::has(std::string_view name) const {
  const std::size_t i = declared(name);
  return specs_[i].takes_value ? values_.size() > i && values_[i].has_value()
                               : flags_.size() > i && flags_[i];
}

bool arg_parser::flag(std::string_view name) const {
  const std::size_t i = declared(name);
  PERCH_ASSERT(!specs_[i].takes_value, "arg_parser::flag: not a flag");
  return flags_.size() > i && flags_[i];
}

std::optional<std::string_view> arg_parser::value(std::string_view name) const {
  const std::size_t i = declared(name);
  PERCH_ASSERT(specs_[i].takes_value, "arg_parser::value: a flag has no value");
  if (values_.size() <= i || !values_[i]) return std::nullopt;
  return std::string_view(*values_[i]);
}

std::optional<std::string_view> arg_parser::positional(std::string_view name) const {
  for (std::size_t i = 0; i < positional_specs_.size(); ++i) {
    if (positional_specs_[i].name != name) continue;
    if (i < positionals_.size()) return std::string_view(positionals_[i]);
    return std::nullopt;
  }
  PERCH_ASSERT(false, "arg_parser::positional: undeclared positional");
  return std::nullopt;
}

arg_value<std::string> arg_parser::get_string(std::string_view name, std::string fallback) const {
  const auto text = value(name);
  return {text ? std::string(*text) : std::move(fallback), {}};
}

arg_value<double> arg_parser::get_double(std::string_view name, double fallback, double min,
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

arg_value<std::string> arg_parser::get_choice(std::string_view name, std::string fallback,
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

std::string arg_parser::help() const {
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

void arg_parser::declare(spec s) {
  PERCH_ASSERT(!s.name.empty() && s.name != "help", "arg_parser: empty or reserved name");
  PERCH_ASSERT(find(s.name) == npos, "arg_parser: option declared twice");
  PERCH_ASSERT(s.short_name != 'h' && (s.short_name == 0 || find_short(s.short_name) == npos),
               "arg_parser: short name reserved or declared twice");
  specs_.push_back(std::move(s));
}

std::size_t arg_parser::find(std::string_view name) const noexcept {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].name == name) return i;
  return npos;
}

std::size_t arg_parser::find_short(char c) const noexcept {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].short_name != 0 && specs_[i].short_name == c) return i;
  return npos;
}

std::size_t arg_parser::declared(std::string_view name) const {
  const std::size_t i = find(name);
  PERCH_ASSERT(i != npos, "arg_parser: asking for an undeclared option");
  return i;
}

bool arg_parser::looks_numeric(std::string_view a) const noexcept {
  if (a.size() < 2 || a[0] != '-') return false;
  if (find_short(a[1]) != npos) return false;
  return (a[1] >= '0' && a[1] <= '9') || (a[1] == '.' && a.size() > 2);
}

std::string arg_parser::unknown_option(std::string_view shown) const {
  std::string message = "unknown option '" + std::string(shown) + "'";
  if (shown.starts_with("--")) {
    std::vector<std::string_view> names;
    for (const spec& s : specs_) names.emplace_back(s.name);
    if (const auto near = closest_match(shown.substr(2), names))
      message += " (did you mean '--" + std::string(*near) + "'?)";
  }
  return message;
}

std::string arg_parser::format_number(double v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  if (ec != std::errc{}) return "?";
  return std::string(buffer, end);
}

}  // namespace perch::support
