// SPDX-License-Identifier: BSL-1.0
/// \file
/// Stage "track": one stable perch target across the frames of an approach. `perch_tracker`
/// takes each frame's `find_perch` result and the camera's motion (`camera_motion`: given, or
/// estimated from the masks with `motion_estimator`) and keeps tracks with persistent ids,
/// smoothed positions and measures, and a target that changes only for a stated reason.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/track/motion.hpp"
#include "perch/track/motion_estimate.hpp"
#include "perch/track/tracker.hpp"
