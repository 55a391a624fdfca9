// SPDX-License-Identifier: BSL-1.0
/// \file
/// Core vocabulary. Consumes nothing; produces what every stage uses: `image_view` and its
/// concepts, `result`/`status`/`errc`, the `workspace`, `bounded_vector`, and Eigen points.
/// (The owning `image<T>` for host code is in `perch/core/image.hpp`, included on demand.)
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/core/assert.hpp"
#include "perch/core/bounded_vector.hpp"
#include "perch/core/disc_index.hpp"
#include "perch/core/eigen_view.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/mask.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/workspace.hpp"
