// SPDX-License-Identifier: BSL-1.0
/// \file
/// The perch tool's JSON documents: `perch detect` (issue 6's shape, which other tools rely
/// on) and `perch graph`. Byte-deterministic: the same result gives the same bytes (numbers in
/// shortest round-trip form, members in a fixed order, no clock unless timings were asked for).
#pragma once

#include <string>

#include "perch/pli.hpp"

namespace perch::tool {

/// The `perch detect` document:
/// `{"status": "ok"|"no_perch", ["reason"], "image": {"width", "height"}, "mm_per_px", "scale",
///   "platform", "perch": site|null, "candidates": [site...], "rejected": {constraint: count},
///   "near_misses": [...], "windows": {"measured", "viable"}, "graph": {"nodes", "edges",
///   "components", "holes_filled"}, "timing_ms": {stage: ms, ..., "total"}}`
/// with site = `{"x", "y", "slope_deg", "diameter_mm", "curvature_per_mm", "slope_max_deg",
/// "bend_deg", "penalty", "branch", "component", "rank"[, "position_m"]}` (x, y in input pixels;
/// diameter = claw region mean; curvature = the window's largest; slope_max_deg = the steepest
/// local tangent, bend_deg = the largest turn over a drone width) and near miss =
/// `{"constraint", "miss", "unit", "x", "y"}`: every constraint of the platform by its name
/// (`border` px, `resolution` px, `bend` deg, `clearance` mm, `supported`, ...), `miss` in its
/// unit. Pretty-printed, ends with a newline.
[[nodiscard]] std::string detect_json(const perch_result& r);

/// The `perch graph` document (after pruning): `{"components", "mm_per_px", "nodes": [{"id",
/// "x", "y", "kind", "component", "trunk"}], "edges": [{"id", "from", "to", "length_px",
/// "mean_diameter_px", "type", "polyline": [[x, y], ...]}]}`; positions in input pixels,
/// lengths in analysed pixels (input pixels unless --downscale).
[[nodiscard]] std::string graph_json(const perch_result& r);

}  // namespace perch::tool
