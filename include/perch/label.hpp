// SPDX-License-Identifier: BSL-1.0
/// \file
/// Labelling stage. Consumes a binary mask (any `BinaryView`: non-zero = foreground) and a
/// workspace; produces an int32 label image numbered 1..n in raster order of each component's
/// first pixel (0 = background) with optional per-component area and bounding box
/// (`label_components`), and the component and hole counts that prove a skeleton kept the
/// mask's topology (`count_topology`). Builds on core only.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/label/components.hpp"
#include "perch/label/connectivity.hpp"
#include "perch/label/holes.hpp"
#include "perch/label/topology.hpp"
