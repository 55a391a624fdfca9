// SPDX-License-Identifier: BSL-1.0
/// \file
/// Stage "bridges". Consumes a prepared mask (1 = tree) with its row runs and squared distance
/// map, and its pruned skeleton graph; produces the small gaps a segmenter left (two aligned
/// ends of a limb, or an end cut off the limb it grows from), each as a capsule drawn into
/// perch's own copy of the mask, which the mask's stages then analyse again. Builds on core and
/// the skeleton graph.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/bridge/gaps.hpp"
