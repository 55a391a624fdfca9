// SPDX-License-Identifier: BSL-1.0
#include "support/args.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

using perch::support::arg_parser;

namespace {

arg_parser detect_parser() {
  arg_parser p("perch detect", "Finds where to perch on a tree mask.");
  p.add_positional("MASK.png", "tree mask; any non-zero pixel is tree");
  p.add_option("top", "K", "number of candidates to report", "5");
  p.add_option("mm-per-px", "X", "image scale");
  p.add_option("roll-deg", "R", "camera roll");
  p.add_option("jobs", "N", "worker threads", "all cores", 'j');
  p.add_option("platform", "NAME", "tendon-claw, tensile-tether, ...", "tendon-claw");
  p.add_flag("known-scale", "use the scale from the truth file");
  return p;
}

std::string parse(arg_parser& p, std::vector<std::string_view> args) {
  return p.parse(std::span<const std::string_view>(args));
}

}  // namespace

TEST_CASE("arg_parser: values in both spellings, flags, positionals") {
  auto p = detect_parser();
  REQUIRE(parse(p, {"mask.png", "--top", "7", "--mm-per-px=0.25", "--known-scale", "-j", "3",
                    "--roll-deg", "-5"}) == "");
  CHECK_FALSE(p.help_requested());
  CHECK(p.positional("MASK.png") == "mask.png");
  CHECK(p.positionals().size() == 1);
  CHECK(p.value("top") == "7");
  CHECK(p.has("top"));
  CHECK_FALSE(p.has("platform"));
  CHECK(p.flag("known-scale"));
  CHECK(p.has("known-scale"));
  const auto top = p.get_int("top", 5, 1, 100);
  REQUIRE(top);
  CHECK(top.value == 7);
  const auto scale = p.get_double("mm-per-px", 1.0, 1e-6, 1e6);
  REQUIRE(scale);
  CHECK(scale.value == 0.25);
  CHECK(p.get_double("roll-deg", 0.0, -180.0, 180.0).value == -5.0);
  CHECK(p.get_integer<unsigned>("jobs", 0u, 0u, 1024u).value == 3u);
  // Absent options give the fallback, unchecked.
  const auto platform = p.get_string("platform", "tendon-claw");
  CHECK(platform.value == "tendon-claw");
  CHECK(p.get_int("top", 5, 1, 100).value == 7);

  // Short option glued to its value, and "--" ending the options.
  auto q = detect_parser();
  REQUIRE(parse(q, {"-j8", "--", "--weird-name.png"}) == "");
  CHECK(q.get_integer<unsigned>("jobs", 0u, 0u, 64u).value == 8u);
  CHECK(q.positional("MASK.png") == "--weird-name.png");
  CHECK_FALSE(q.flag("known-scale"));
}

TEST_CASE("arg_parser: error messages name the problem") {
  auto p = detect_parser();
  CHECK(parse(p, {"m.png", "--tpo", "3"}) == "unknown option '--tpo' (did you mean '--top'?)");
  CHECK(parse(p, {"m.png", "--frobnicate"}) == "unknown option '--frobnicate'");
  CHECK(parse(p, {"m.png", "-x"}) == "unknown option '-x'");
  CHECK(parse(p, {"m.png", "--top"}) == "option '--top' needs a value (K)");
  CHECK(parse(p, {"m.png", "--top", "--known-scale"}) == "option '--top' needs a value (K)");
  CHECK(parse(p, {"m.png", "--top", "1", "--top=2"}) == "option '--top' given more than once");
  CHECK(parse(p, {"m.png", "--known-scale=yes"}) == "option '--known-scale' takes no value");
  CHECK(parse(p, {}) == "missing argument MASK.png");
  CHECK(parse(p, {"a.png", "b.png"}) == "unexpected argument 'b.png'");
  // A failed parse followed by a good one starts afresh.
  CHECK(parse(p, {"a.png"}) == "");
  CHECK_FALSE(p.has("top"));
}

TEST_CASE("arg_parser: typed getters check syntax and range") {
  auto p = detect_parser();
  REQUIRE(parse(p, {"m.png", "--top", "abc", "--mm-per-px", "nan", "--roll-deg", "400", "-j",
                    "99999999999999999999", "--platform", "ornithoptr"}) == "");
  const auto top = p.get_int("top", 5, 1, 100);
  CHECK_FALSE(top);
  CHECK(top.value == 5);
  CHECK(top.error == "--top: expected an integer, got 'abc'");
  CHECK(p.get_double("mm-per-px", 1.0, 0.0, 10.0).error ==
        "--mm-per-px: expected a number, got 'nan'");
  CHECK(p.get_double("roll-deg", 0.0, -180.0, 180.0).error ==
        "--roll-deg: 400 is out of range [-180, 180]");
  CHECK(p.get_integer<unsigned>("jobs", 0u, 0u, 64u).error ==
        "--jobs: 99999999999999999999 is out of range [0, 64]");
  const std::array<std::string_view, 5> platforms{"tendon-claw", "tensile-tether", "metamorphic",
                                                  "ornithopter", "treecreeper"};
  const auto platform = p.get_choice("platform", "tendon-claw", platforms);
  CHECK_FALSE(platform);
  CHECK(platform.error ==
        "--platform: unknown value 'ornithoptr' (choose from tendon-claw, tensile-tether, "
        "metamorphic, ornithopter, treecreeper); did you mean 'ornithopter'?");

  auto q = detect_parser();
  REQUIRE(parse(q, {"m.png", "--top", "12x", "--mm-per-px", "1e-3", "--platform", "metamorphic",
                    "--roll-deg", "+2.5"}) == "");
  CHECK(q.get_int("top", 5, 1, 100).error == "--top: expected an integer, got '12x'");
  CHECK(q.get_double("mm-per-px", 1.0, 0.0, 10.0).value == 0.001);
  CHECK(q.get_choice("platform", "tendon-claw", platforms).value == "metamorphic");
  CHECK(q.get_double("roll-deg", 0.0, -180.0, 180.0).value == 2.5);
  REQUIRE(parse(q, {"m.png", "--top", "0"}) == "");
  CHECK(q.get_int("top", 5, 1, 100).error == "--top: 0 is out of range [1, 100]");
  REQUIRE(parse(q, {"m.png", "--top="}) == "");
  CHECK(q.get_int("top", 5, 1, 100).error == "--top: expected an integer, got ''");
}

TEST_CASE("arg_parser: --help wins over everything and the text lists every option") {
  auto p = detect_parser();
  p.set_epilog("Example: perch detect mask.png --top 3");
  CHECK(parse(p, {"--bogus", "--help"}) == "");
  CHECK(p.help_requested());
  CHECK(parse(p, {"-h"}) == "");
  CHECK(p.help_requested());
  CHECK(parse(p, {"m.png", "--", "--help"}) == "unexpected argument '--help'");
  CHECK_FALSE(p.help_requested());

  const std::string help = p.help();
  const std::string expected =
      "usage: perch detect [options] MASK.png\n"
      "\n"
      "Finds where to perch on a tree mask.\n"
      "\n"
      "arguments:\n"
      "  MASK.png         tree mask; any non-zero pixel is tree\n"
      "\n"
      "options:\n"
      "  --top K          number of candidates to report (default: 5)\n"
      "  --mm-per-px X    image scale\n"
      "  --roll-deg R     camera roll\n"
      "  -j, --jobs N     worker threads (default: all cores)\n"
      "  --platform NAME  tendon-claw, tensile-tether, ... (default: tendon-claw)\n"
      "  --known-scale    use the scale from the truth file\n"
      "  -h, --help       show this help and exit\n"
      "\n"
      "Example: perch detect mask.png --top 3\n";
  CHECK(help == expected);

  arg_parser long_names("perch x", "");
  long_names.add_option("a-really-very-long-option-name", "VALUE", "first line\nsecond line");
  long_names.add_positional("OUT", "output", perch::support::arg_presence::optional);
  const std::string h = long_names.help();
  CHECK(h.find("usage: perch x [options] [OUT]\n") == 0);
  CHECK(h.find("  --a-really-very-long-option-name VALUE\n"
               "                              first line\n"
               "                              second line\n") != std::string::npos);
  CHECK(parse(long_names, {}) == "");
  CHECK_FALSE(long_names.positional("OUT").has_value());
}

TEST_CASE("arg_parser: argc/argv entry point and helpers") {
  auto p = detect_parser();
  const char* argv[] = {"perch", "detect", "m.png", "--top", "3"};
  CHECK(p.parse(5, argv, 2) == "");
  CHECK(p.get_int("top", 5, 1, 9).value == 3);
  CHECK(p.positional("MASK.png") == "m.png");

  CHECK(perch::support::edit_distance("kitten", "sitting") == 3);
  CHECK(perch::support::edit_distance("", "abc") == 3);
  CHECK(perch::support::edit_distance("same", "same") == 0);
  CHECK(perch::support::edit_distance("tpo", "top") == 1);
  CHECK(perch::support::edit_distance("ca", "abc") == 3);
  const std::array<std::string_view, 3> commands{"detect", "batch", "skeleton"};
  CHECK(perch::support::closest_match("detetc", commands) == "detect");
  CHECK(perch::support::closest_match("bach", commands) == "batch");
  CHECK_FALSE(perch::support::closest_match("xyz", commands).has_value());

  const std::array<perch::support::command_info, 2> info{
      {{"detect", "find the best perch site"}, {"batch", "run detect on every PNG in DIR"}}};
  CHECK(perch::support::format_commands("perch", info) ==
        "usage: perch <command> [options]\n\ncommands:\n"
        "  detect  find the best perch site\n"
        "  batch   run detect on every PNG in DIR\n"
        "\nRun 'perch <command> --help' for a command's options.\n");
}

TEST_CASE("arg_parser: --version only when set, anywhere before --, listed in the help") {
  auto p = detect_parser();
  CHECK(parse(p, {"--version"}) != "");  // not declared: an unknown option
  p.set_version("perch 1.2.3");
  REQUIRE(parse(p, {"--top", "x", "--version"}) == "");  // like --help: the rest is not checked
  CHECK(p.version_requested());
  CHECK(p.version() == "perch 1.2.3");
  CHECK(p.help().find("--version") != std::string::npos);
  REQUIRE(parse(p, {"mask.png", "--", "--version"}) != "");  // after "--": a positional, one too many
  CHECK_FALSE(p.version_requested());
}

TEST_CASE("arg_parser: a one_or_more positional takes every remaining argument") {
  arg_parser p("perch batch", "Merges shards.");
  p.add_positional("SHARD_DIR", "a shard's output", perch::support::arg_presence::one_or_more);
  CHECK(parse(p, {}) == "missing argument SHARD_DIR");
  REQUIRE(parse(p, {"a", "b", "c"}) == "");
  CHECK(p.positionals().size() == 3);
  CHECK(p.positional("SHARD_DIR") == "a");
  CHECK(p.help().find("SHARD_DIR...") != std::string::npos);
}
