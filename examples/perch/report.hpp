// SPDX-License-Identifier: BSL-1.0
/// \file
/// The perch tool's JSON documents: `perch detect` (issue 6's shape, which other tools rely
/// on) and `perch graph`. Byte-deterministic: the same result gives the same bytes (numbers in
/// shortest round-trip form, members in a fixed order, no clock unless timings were asked for).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "perch/pli.hpp"
#include "support/json_writer.hpp"

namespace perch::tool {

/// What every document says about where it came from: `"version"` (the tool's), `"input"`
/// (the mask's path, "-" for standard input) and, when there are any, `"warnings"` (why the
/// input is probably not a tree mask).
struct document_source {
  std::string_view input;
  std::span<const std::string> warnings;
};

/// The `"status"` of an outcome: "ok", "no_perch" or "no_tree".
[[nodiscard]] std::string_view status_name(perch_outcome outcome) noexcept;

/// Why `r` has no perch, for a person: no tree pixel; no window measured (no limb left after
/// pruning, or none with a stretch clear of junctions one drone width long, with the longest
/// limb's length); or every measured window failed a constraint. Empty when found.
[[nodiscard]] std::string no_perch_reason(const perch_result& r, const platform_geometry& geometry);

/// The `perch detect` document:
/// `{"version", "input", ["warnings": [...]], "status": "ok"|"no_perch"|"no_tree", ["reason"],
///   "image": {"width", "height"}, "mm_per_px", "scale",
///   "platform", "perch": site|null, "candidates": [site...], "rejected": {constraint: count},
///   "near_misses": [...], "windows": {"measured", "viable"}, "graph": {"nodes", "edges",
///   "components", "holes_filled"}, "timing_ms": {stage: ms, ..., "total"}}`
/// with site = `{"x", "y", "slope_deg", "diameter_mm", "curvature_per_mm", "slope_max_deg",
/// "bend_deg", "penalty", "branch", "component", "rank"[, "position_m"]}` (rank 1 = the chosen
/// perch; x, y in input pixels;
/// diameter = claw region mean; curvature = the window's largest; slope_max_deg = the steepest
/// local tangent, bend_deg = the largest turn over a drone width) and near miss =
/// `{"constraint", "miss", "unit", "x", "y"}`: every constraint of the platform by its name
/// (`border` px, `resolution` px, `bend` deg, `clearance` mm, `supported`, ...), `miss` in its
/// unit. Pretty-printed, ends with a newline.
[[nodiscard]] std::string detect_json(const perch_result& r, const document_source& source,
                                      const platform_geometry& geometry);

/// The `perch graph` document (after pruning): `{"version", "input", ["warnings"], "components", "mm_per_px", "nodes": [{"id",
/// "x", "y", "kind", "component", "trunk"}], "edges": [{"id", "from", "to", "length_px",
/// "mean_diameter_px", "type", "polyline": [[x, y], ...]}]}`; positions in input pixels,
/// lengths in analysed pixels (input pixels unless --downscale).
[[nodiscard]] std::string graph_json(const perch_result& r, const document_source& source);

/// Writes `"version"`, `"input"` and (when any) `"warnings"` into the open object of `json`.
void write_source(support::json_writer& json, const document_source& source);

/// Writes `"KEY": [x, y, z]`, each rounded to 1e-4 relative steps, into the open object of `json`.
void write_point3(support::json_writer& json, std::string_view key, const point3f& v);

}  // namespace perch::tool
