// SPDX-License-Identifier: BSL-1.0
/// \file
/// `perch batch`'s summary files, one row per input, for scripts: `summary.json` and
/// `summary.csv` in the output directory, written by a batch (or one shard of it) and read
/// back by `perch batch --merge` to join the shards.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace perch::tool {

/// The chosen perch of one input, as the summary gives it.
struct summary_perch {
  float x = 0, y = 0;
  float slope_deg = 0, diameter_mm = 0, penalty = 0;
};

/// One input: its file name, "ok" | "no_perch" | "no_tree" | "error", why (empty when ok),
/// its warnings, the chosen perch and find_perch's time.
struct summary_row {
  std::string file;
  std::string status;
  std::string reason;
  std::vector<std::string> warnings;
  std::optional<summary_perch> perch;
  float time_ms = 0;
};

/// Which slice of the sorted folder a batch processed: input i (from 0) belongs to shard
/// `i % count + 1`.
struct shard_spec {
  int index = 1;  ///< 1..count
  int count = 1;
  [[nodiscard]] bool holds(std::size_t i) const noexcept {
    return static_cast<int>(i % static_cast<std::size_t>(count)) + 1 == index;
  }
};

struct batch_summary {
  std::string input;                ///< the folder
  std::optional<shard_spec> shard;  ///< none: the whole folder (or a merge)
  int merged_shards = 0;            ///< shards joined by --merge (0: not a merge)
  std::size_t files_in_input = 0;   ///< PNGs in the whole folder, every shard's
  int exit_code = 0;                ///< the batch's exit status
  std::vector<summary_row> rows;    ///< sorted by file name
};

/// `{"version", "input", "shard": {"index", "count"}|null, ["merged_shards"], "files_in_input",
///   "exit_code", "counts": {status: n}, "rows": [{"file", "status", "reason", "warnings",
///   "x", "y", "slope_deg", "diameter_mm", "penalty" (null without a perch), "time_ms"}]}`
[[nodiscard]] std::string summary_json(const batch_summary& s);
/// `file,status,reason,warnings,x,y,slope_deg,diameter_mm,penalty,time_ms`, one line per row
/// (RFC 4180 quoting; warnings joined by "; "; empty fields without a perch).
[[nodiscard]] std::string summary_csv(const batch_summary& s);
/// Reads `dir`/summary.json. Returns an error message (empty on success).
[[nodiscard]] std::string read_summary(const std::filesystem::path& dir, batch_summary& out);

/// Joins shards' summaries: every shard 1..N of the same N exactly once, rows re-sorted by
/// file name, the worst exit status (1 over 2 over 0). Returns an error message.
[[nodiscard]] std::string merge_summaries(std::vector<batch_summary> shards, batch_summary& merged);

}  // namespace perch::tool
