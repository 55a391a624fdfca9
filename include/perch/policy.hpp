// SPDX-License-Identifier: BSL-1.0
/// \file
/// Policies: the `Constraint` and `Scorer` concepts, the paper's constraints (viability) and
/// penalty (eq. 3), and composites. Consumes `window_measures` (and a `window_context` for
/// clearance); produces a verdict (by how much a window misses) and a penalty per window.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/policy/composites.hpp"
#include "perch/policy/concepts.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/rank.hpp"
#include "perch/policy/scorers.hpp"
