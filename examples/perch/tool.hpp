// SPDX-License-Identifier: BSL-1.0
/// \file
/// What the perch tool's subcommands share: exit codes, the pipeline options every analysing
/// subcommand takes (platform, scale, roll, top-k, downscale), loading masks, and `analyse`,
/// which runs `find_perch` once and turns its result into JSON and pictures while the
/// workspace still holds it. Host code: std::string, std::vector, files; no exceptions thrown.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "png/png.hpp"
#include "support/args.hpp"

namespace perch::tool {

/// The tool's version: the CMake project's version, passed as PERCH_VERSION (one place).
inline constexpr std::string_view version = PERCH_VERSION;

/// The mask path that means standard input.
inline constexpr std::string_view stdin_name = "-";

/// Exit codes of every subcommand.
inline constexpr int exit_ok = 0;        ///< success, including "no perch found"
inline constexpr int exit_internal = 1;  ///< internal failure (out of memory, cannot write)
inline constexpr int exit_usage = 2;     ///< bad arguments or unreadable input

/// The five platforms, by their command-line names.
enum class platform_id : std::uint8_t { tendon_claw, tensile_tether, metamorphic, ornithopter, treecreeper };
inline constexpr std::array<std::string_view, 5> platform_names = {
    "tendon-claw", "tensile-tether", "metamorphic", "ornithopter", "treecreeper"};

/// The limits a platform's constraints declare (for `eval`'s truth and `--annotate`'s clearance
/// envelope). A rule the platform does not have keeps the value that never fails.
struct platform_limits {
  float diameter_min_mm = 0;
  float diameter_max_mm = 1e9f;
  float slope_min_deg = 0;
  float slope_max_deg = 90;
  float drone_width_mm = 0;
  float claw_width_mm = 0;
  float mass_kg = 0;
  bool has_min_slope = false;     ///< `min_slope` (the synthetic truth has no such rule)
  float bend_max_deg = 180;       ///< `max_bend`
  float border_px = 0;            ///< `image_border`
  float resolution_px = 0;        ///< `resolved_diameter`: uncertainty of a diameter, px
  float max_stress_mpa = 1e30f;   ///< `bending_stress`: modulus of rupture / safety / load
  bool has_clearance = false;     ///< `clearance`
  float clearance_mm = 0;         ///< its margin: the free gap around the limb's surface
  float clearance_uncertainty_px = 0;  ///< and the pixels added to it (`clearance::uncertainty_px`)
};
[[nodiscard]] platform_limits limits_of(platform_id id);

/// The drone's geometry on platform `id`.
[[nodiscard]] platform_geometry geometry_of(platform_id id);

/// How the tool gets the scale.
enum class scale_kind : std::uint8_t { trunk_prior, fixed, depth };

struct scale_config {
  scale_kind kind = scale_kind::trunk_prior;
  float mm_per_px = 0;          ///< --mm-per-px
  float trunk_mm = 180.0f;      ///< --trunk-mm
  std::optional<float> uncertainty;  ///< --scale-uncertainty (relative); else the policy's own
  std::optional<image<std::uint16_t>> depth_mm;  ///< --depth (millimetres, 0 invalid)
  std::optional<std::filesystem::path> depth_dir;  ///< --depth-dir (track: DIR/NAME per frame)
  pinhole intrinsics{};         ///< --fx --fy --cx --cy
};

/// Reads a depth PNG (16-bit millimetres, 0 invalid; 8-bit widened) into `out`. Returns an
/// error message ("cannot read depth PATH: ..."), or an empty string.
[[nodiscard]] std::string load_depth(const std::filesystem::path& path, image<std::uint16_t>& out);

/// The options of one analysis (detect, batch, graph, eval).
struct run_config {
  platform_id platform = platform_id::tendon_claw;
  scale_config scale{};
  float roll_deg = 0;
  std::size_t top_k = 5;
  float downscale = 1.0f;
  std::int32_t max_hole_px = 4;  ///< --max-hole-px
  float max_gap_px = bridge_options{}.max_gap_px;  ///< --max-gap-px (0: no bridging)
  bool timing = true;  ///< false (--no-timing): timing_ms all 0, output byte-deterministic
};

/// Which pipeline options `add_pipeline_options` declares: --depth FILE (`offered`), --depth-dir
/// DIR (`per_frame`: a depth image per mask, of the same file name), or neither.
enum class depth_option : std::uint8_t { offered, per_frame, not_offered };

/// Declares --platform, --mm-per-px, --trunk-mm, [--depth or --depth-dir, --fx --fy --cx --cy],
/// --roll-deg, --top, --downscale, --max-hole-px, --max-gap-px, --no-timing.
void add_pipeline_options(support::arg_parser& args, depth_option depth);

/// Reads the options declared by `add_pipeline_options` (and loads --depth; checks that
/// --depth-dir is a directory). Returns an error message (empty on success).
[[nodiscard]] std::string read_pipeline_options(const support::arg_parser& args, depth_option depth,
                                                run_config& config);

/// The `perch_options` of `config` (downscale, holes, gaps, roll, top-k; no clock).
[[nodiscard]] perch_options perch_options_of(const run_config& config);

/// `find_perch` on `mask` with `config`'s platform and scale and `options` (usually
/// `perch_options_of(config)`). The one place the tool names the platform and scale types
/// (platforms.cpp).
[[nodiscard]] result<perch_result> find_with(image_view<const std::uint8_t> mask, const run_config& config,
                                             const perch_options& options, workspace& ws);

/// `find_perch` on a frame with its depth when it has one (`depth`: `config` with the frame's
/// depth image as its scale), else with `config`'s scale. Depth with no valid sample on the
/// tree is dropped for `config`'s scale, and `depth_dropped` says so: a frame is analysed with
/// what it has (perch track --depth-dir, perch eval --sequences --depth).
[[nodiscard]] result<perch_result> find_in_frame(const image<std::uint8_t>& mask, const run_config& config,
                                                 const run_config* depth, workspace& ws, bool& depth_dropped);

/// The value below which a fraction `q` ∈ [0, 1] of `values` lie (nearest rank); 0 when empty.
[[nodiscard]] float percentile(std::vector<float> values, double q);

/// How a PNG becomes a tree mask: by default any non-zero colour sample is tree; `threshold`:
/// tree where the 8-bit gray level is above it; `invert`: the other pixels are tree.
struct mask_reading {
  std::optional<std::uint8_t> threshold;
  bool invert = false;
};

/// Declares --threshold and --invert; reads them (an error message, empty on success).
void add_mask_options(support::arg_parser& args);
[[nodiscard]] std::string read_mask_options(const support::arg_parser& args, mask_reading& reading);

/// A tree mask (0/1) and why it is probably not one: a colour image, more than two grey levels
/// (both unless a threshold was given), or an inverted look (tree on more than half of it or on
/// along all four borders, on more than half of each).
struct loaded_mask {
  image<std::uint8_t> pixels;
  std::vector<std::string> warnings;
};

/// Reads the PNG at `path` (`stdin_name`: standard input) as `reading` says. Returns an error
/// message (empty on success): a path that is not a readable regular file, a corrupt PNG.
[[nodiscard]] std::string load_mask(const std::filesystem::path& path, const mask_reading& reading,
                                    loaded_mask& out);

/// Prints "perch <command>: warning: <path>: <warning>" to stderr for each warning.
void report_warnings(std::string_view command, const std::filesystem::path& path,
                     std::span<const std::string> warnings);

/// Why `path` cannot take an output file (an existing directory, a missing or unwritable
/// parent directory), or an empty string. Checked before any analysis, so a bad output path
/// is exit 2 with nothing written.
[[nodiscard]] std::string check_output_path(const std::filesystem::path& path);
/// Creates `dir` if missing and checks that it can take `file` (`check_output_path`). Returns an
/// error message ("cannot create DIR", ...), or an empty string.
[[nodiscard]] std::string make_output_dir(const std::filesystem::path& dir, std::string_view file);
/// `check_output_path` for each of `options` given on the command line: the first problem,
/// "--option: ...", or an empty string.
[[nodiscard]] std::string check_output_options(const support::arg_parser& args,
                                               std::initializer_list<std::string_view> options);

/// What `analyse` should produce.
struct analysis_request {
  const image<std::uint8_t>* mask = nullptr;
  std::string_view input;                 ///< the mask's path, for the JSON
  std::span<const std::string> warnings;  ///< the mask's warnings, for the JSON
  const image<png::rgb8>* photo = nullptr;  ///< background for the picture (mask when null)
  bool detect_json = true;
  bool annotation = false;
  bool graph_json = false;
};

/// What `analyse` produced.
struct analysis_output {
  int exit_code = exit_ok;  ///< exit_ok, or exit_usage / exit_internal with `error`
  std::string error;
  perch_outcome outcome = perch_outcome::no_tree;
  std::string reason;             ///< why no perch (empty when found)
  std::vector<perch_site> sites;  ///< copies, input-image pixels
  float mm_per_px = 0;
  float total_ms = 0;
  std::string detect_json;
  std::string graph_json;
  std::optional<image<png::rgb8>> annotated;
};

/// Runs `find_perch` on `request.mask` with `config`, and writes what `request` asks for.
/// Library errors become `exit_usage` (bad input or options) or `exit_internal` (memory).
[[nodiscard]] analysis_output analyse(const analysis_request& request, const run_config& config,
                                      workspace& ws);

/// "message (detail)" of a library error.
[[nodiscard]] std::string describe(const error& e);
/// exit_internal for resource errors, exit_usage for everything else (bad input).
[[nodiscard]] int exit_code_for(const error& e);

/// Writes `text` to `path` (or stdout when `path` is empty). Returns an error message.
[[nodiscard]] std::string write_text(const std::filesystem::path& path, std::string_view text);

/// Prints "perch <command>: <message>" to stderr.
void report_error(std::string_view command, std::string_view message);

/// Parses `args` for `command`; prints help or the version (returns exit_ok in `exit`) or
/// the error.
/// Returns true when the caller should go on.
[[nodiscard]] bool parse_or_exit(support::arg_parser& args, int argc, const char* const* argv,
                                 std::string_view command, int& exit);

// The subcommands: argv[0] = "perch", argv[1] = the command.
int run_detect(int argc, const char* const* argv);
int run_batch(int argc, const char* const* argv);
int run_skeleton(int argc, const char* const* argv);
int run_graph(int argc, const char* const* argv);
int run_synth(int argc, const char* const* argv);
int run_eval(int argc, const char* const* argv);
/// `perch eval --sequences N`: the tracker on synthetic approach sequences (track_eval.cpp).
int run_track_eval(int argc, const char* const* argv);
int run_track(int argc, const char* const* argv);
/// `perch synth --sequence I`: an approach sequence's frames, truth and motion (track.cpp).
int run_synth_sequence(int argc, const char* const* argv);

}  // namespace perch::tool
