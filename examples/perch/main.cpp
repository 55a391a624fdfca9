// SPDX-License-Identifier: BSL-1.0
// perch: the command-line tool of the perch library (see `perch --help`).
// No exception, failed assert or std::terminate leaves it as an abort: each is a message on
// stderr and exit status 1 (out of memory: "out of memory").
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <string_view>

#include "perch/core/assert.hpp"
#include "support/args.hpp"
#include "tool.hpp"

namespace {

constexpr perch::support::command_info commands[] = {
    {"detect", "find where a drone can perch on a tree mask (JSON, --annotate picture)"},
    {"batch", "detect on every PNG of a directory, in parallel, with summary files; --shard, --merge"},
    {"skeleton", "the skeleton of a mask (and its radii) as PNGs"},
    {"graph", "the pruned skeleton graph of a mask as JSON"},
    {"synth", "write synthetic tree masks with their ground truth"},
    {"eval", "score detect against the ground truth of synthetic trees"},
    {"track", "follow the perch across the frames of a directory (one JSON line per frame)"},
};

/// What the exception in flight is, for a person.
std::string describe_current_exception() {
  const std::exception_ptr current = std::current_exception();
  if (!current) return "internal error (terminated without an exception)";
  try {
    std::rethrow_exception(current);
  } catch (const std::bad_alloc&) {
    return "out of memory";
  } catch (const std::exception& e) {
    return std::string("internal error: ") + e.what();
  } catch (...) {
    return "internal error: unknown exception";
  }
}

[[noreturn]] void exit_internal_error(const std::string& message) {
  std::fprintf(stderr, "perch: %s\n", message.c_str());
  std::fflush(stdout);
  std::_Exit(perch::tool::exit_internal);
}

/// std::terminate (an exception leaving a noexcept function or a thread): exit 1, not abort.
[[noreturn]] void on_terminate() { exit_internal_error(describe_current_exception()); }

/// A failed PERCH_ASSERT in the tool: a bug, reported as exit 1 rather than an abort.
[[noreturn]] void on_assert(const char* expression, const char* file, int line, const char* message) noexcept {
  exit_internal_error("internal error: " + std::string(message) + " (" + expression + " at " + file + ":" +
                      std::to_string(line) + ")");
}

int dispatch(int argc, char** argv) {
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
  if (command == "--version") {
    std::printf("perch %.*s\n", static_cast<int>(version.size()), version.data());
    return exit_ok;
  }
  if (command == "detect") return run_detect(argc, argv);
  if (command == "batch") return run_batch(argc, argv);
  if (command == "skeleton") return run_skeleton(argc, argv);
  if (command == "graph") return run_graph(argc, argv);
  if (command == "synth") return run_synth(argc, argv);
  if (command == "eval") return run_eval(argc, argv);
  if (command == "track") return run_track(argc, argv);
  std::fprintf(stderr, "perch: unknown command '%.*s'\n\n%s", static_cast<int>(command.size()),
               command.data(), usage.c_str());
  return exit_usage;
}

}  // namespace

int main(int argc, char** argv) {
  std::set_terminate(on_terminate);
  perch::set_assert_handler(on_assert);
  try {
    return dispatch(argc, argv);
  } catch (...) {
    exit_internal_error(describe_current_exception());
  }
}
