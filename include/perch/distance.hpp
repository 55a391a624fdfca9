// SPDX-License-Identifier: BSL-1.0
/// \file
/// Distance stage. Consumes a binary mask (any `BinaryView`, non-zero = tree); produces the
/// exact Euclidean distance from every tree pixel to the nearest background pixel centre:
/// squared integers (`distance_transform_sq`, what the skeleton stage reads), optionally with
/// the nearest background pixel, or real distances for anisotropic pixels
/// (`distance_transform`). Meijster, Roerdink & Hesselink 2000, linear time.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/core.hpp"
#include "perch/distance/distance_transform.hpp"
