// SPDX-License-Identifier: BSL-1.0
/// \file
/// Stage "skeleton graph". Consumes a one-pixel-thin skeleton (any `BinaryView`, non-zero =
/// skeleton) and its squared distance map (`image_view<const std::uint32_t>`, radius = √dist2
/// px); produces the `skeleton_graph` of every connected component: pixel kinds, junction
/// clusters as nodes, branches as edges with ordered polylines and radii, branch types, the
/// trunk node of each component, eq. 1 weights, pruning, and distances to the trunk.
/// Also offers the generic `adjacency_list` it is built on.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include "perch/core.hpp"
#include "perch/graph/adjacency_list.hpp"
#include "perch/graph/pixel_kinds.hpp"
#include "perch/graph/prune.hpp"
#include "perch/graph/junctions.hpp"
#include "perch/graph/limbs.hpp"
#include "perch/graph/limb_surroundings.hpp"
#include "perch/graph/skeleton_graph.hpp"
#include "perch/graph/trunk_distances.hpp"
