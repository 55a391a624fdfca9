// SPDX-License-Identifier: BSL-1.0
/// \file
/// Skeleton stage. Consumes a binary mask (non-zero = tree) and its squared distance map (from
/// the distance stage); produces a skeleton image (1 = skeleton pixel), one pixel thin and
/// topology-preserving by default, with the distance map giving the radius at every skeleton
/// pixel. Methods behind the `Skeletoniser` concept: `medial_axis` (default; distance-ordered
/// homotopic thinning), `zhang_suen` (1984) and `guo_hall` (1989).
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/skeleton/medial_axis.hpp"
#include "perch/skeleton/skeleton_workspace.hpp"
#include "perch/skeleton/skeletoniser.hpp"
#include "perch/skeleton/thinning.hpp"
