// SPDX-License-Identifier: BSL-1.0
/// \file
/// Platforms: the `Platform` concept and the five drones of the PLI paper, each a type composed
/// of constraint and scorer policies. Consumes policies; produces what `find_perch` is given.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/platform/metamorphic.hpp"
#include "perch/platform/ornithopter.hpp"
#include "perch/platform/platform.hpp"
#include "perch/platform/tendon_claw.hpp"
#include "perch/platform/tensile_tether.hpp"
#include "perch/platform/treecreeper.hpp"
