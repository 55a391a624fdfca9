// SPDX-License-Identifier: BSL-1.0
/// \file
/// Ground truth of a synthetic tree as JSON (written by `perch synth`, read by `perch eval`):
/// `{"generator", "kind", "seed", "width", "height", "mm_per_px", "limbs": [{"kind":
/// "trunk"|"limb"|"twig"|"fragment", "level", "parent", "base_heading_rad", "curvature_per_px",
/// "tree", "exact_arc", "centreline": [[x, y], ...], "diameter_px": [...]}]}` — px, y down, base
/// to tip. `perch eval` judges the windows of a tree read back with `support::perch_truth`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "support/synthetic_tree.hpp"

namespace perch::tool {

struct truth_file {
  std::string kind;  ///< what the generator made, e.g. "clean", "noisy", "no-perch", "shape"
  std::uint32_t seed = 0;
  int width = 0;
  int height = 0;
  float mm_per_px = 1;
  std::vector<support::limb_truth> limbs;
};

/// The truth as JSON text (deterministic; coordinates rounded to 0.01 px).
[[nodiscard]] std::string truth_json(const truth_file& truth);

/// Reads a truth file (arc lengths recomputed). Returns an error message (empty on success).
[[nodiscard]] std::string read_truth(const std::filesystem::path& path, truth_file& truth);

}  // namespace perch::tool
