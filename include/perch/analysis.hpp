// SPDX-License-Identifier: BSL-1.0
/// \file
/// Analysis: from a branch's centreline (points + radii) to windows one drone width long and
/// their measures (slope against the true horizontal, curvature, diameters, monotonicity,
/// distance to the branch origin), with the scale (fixed, trunk prior, depth) and the camera's
/// attitude; plus clearance queries around a window.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/analysis/attitude.hpp"
#include "perch/analysis/clearance.hpp"
#include "perch/analysis/measures.hpp"
#include "perch/analysis/scale.hpp"
#include "perch/analysis/windows.hpp"
