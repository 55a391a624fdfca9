// SPDX-License-Identifier: BSL-1.0
// perch: the command-line tool of the perch library (see `perch --help`).
#include <cstdio>
#include <string_view>

#include "support/args.hpp"
#include "tool.hpp"

namespace {

constexpr perch::support::command_info commands[] = {
    {"detect", "find where a drone can perch on a tree mask (JSON, --annotate picture)"},
    {"batch", "detect on every PNG of a directory, in parallel, with a summary"},
    {"skeleton", "the skeleton of a mask (and its radii) as PNGs"},
    {"graph", "the pruned skeleton graph of a mask as JSON"},
    {"synth", "write synthetic tree masks with their ground truth"},
    {"eval", "score detect against the ground truth of synthetic trees"},
};

}  // namespace

int main(int argc, char** argv) {
  using namespace perch::tool;
  const std::string usage = perch::support::format_commands("perch", commands);
  if (argc < 2) {
    std::fputs(usage.c_str(), stderr);
    return exit_usage;
  }
  const std::string_view command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::fputs(usage.c_str(), stdout);
    return exit_ok;
  }
  if (command == "detect") return run_detect(argc, argv);
  if (command == "batch") return run_batch(argc, argv);
  if (command == "skeleton") return run_skeleton(argc, argv);
  if (command == "graph") return run_graph(argc, argv);
  if (command == "synth") return run_synth(argc, argv);
  if (command == "eval") return run_eval(argc, argv);
  std::fprintf(stderr, "perch: unknown command '%.*s'\n\n%s", static_cast<int>(command.size()),
               command.data(), usage.c_str());
  return exit_usage;
}
