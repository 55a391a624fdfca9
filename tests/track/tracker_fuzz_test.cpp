// SPDX-License-Identifier: BSL-1.0
// The tracker's fuzz driver (tracker_fuzz.hpp) on fixed pseudo-random inputs, so the sanitizer
// builds (the asan preset) run it on every test run: garbage sites and near misses, hostile
// motions, frame sizes, missing frames and resets must keep every invariant, and never crash
// or reach undefined behaviour. tests/fuzz/fuzz_tracker.cpp runs the same driver under
// libFuzzer.
#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "tracker_fuzz.hpp"

TEST_CASE("the tracker keeps its invariants on hostile input") {
  std::mt19937 rng(27u);
  std::vector<std::string> failures;
  auto report = [&](const char* what) { failures.emplace_back(what); };
  for (int input = 0; input < 3000; ++input) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(rng() % 2048u));
    for (std::uint8_t& b : bytes) b = static_cast<std::uint8_t>(rng() & 0xffu);
    perch::test::run_tracker_fuzz(bytes.data(), bytes.size(), report);
    if (!failures.empty()) {
      INFO("input " << input << ": " << failures.front());
      CHECK(failures.empty());
      break;
    }
  }
  CHECK(failures.empty());
}

TEST_CASE("the fuzz driver's checks catch a broken invariant") {
  // A tracker whose result claims a target that is not among its tracks must be reported: the
  // checks above are not vacuous.
  perch::perch_tracker tracker;
  perch::perch_track stray;
  stray.id = 7;
  stray.state = perch::track_state::confirmed;
  perch::tracking_result r;
  r.target = &stray;
  int reported = 0;
  perch::test::check_result(tracker, r, [&](const char*) { ++reported; });
  CHECK(reported > 0);
  stray.doubtful = true;
  stray.feasible = false;
  stray.marginal = true;
  stray.infeasible_streak = tracker.options().doubtful_frames;
  reported = 0;
  perch::perch_track kept[1] = {stray};
  r.tracks = kept;
  r.target = &kept[0];
  perch::test::check_result(tracker, r, [&](const char*) { ++reported; });
  CHECK(reported == 1);  // kept through its noise for doubtful_frames: too long
}
