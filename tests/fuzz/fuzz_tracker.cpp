// SPDX-License-Identifier: BSL-1.0
// Fuzz target: perch_tracker on arbitrary sequences of frames (tests/track/tracker_fuzz.hpp):
// garbage sites and near misses, hostile motions, frame sizes, missing frames and resets. Any
// input must keep the tracker's invariants; never a crash, UB, an assert or an endless loop.
#include <cstddef>
#include <cstdint>

#include "../track/tracker_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  perch::test::run_tracker_fuzz(data, size, [](const char*) { __builtin_trap(); });
  return 0;
}
