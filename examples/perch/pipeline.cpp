// SPDX-License-Identifier: BSL-1.0
// The shared part of the perch tool: options, loading, and `analyse` (find_perch + outputs).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <unistd.h>

#include "annotate.hpp"
#include "report.hpp"
#include "tool.hpp"

namespace perch::tool {

void add_pipeline_options(support::arg_parser& args, depth_option depth) {
  args.add_option("platform", "NAME",
                  "tendon-claw, tensile-tether, metamorphic, ornithopter or treecreeper",
                  "tendon-claw");
  args.add_option("mm-per-px", "X", "known scale: millimetres per input pixel");
  args.add_option("trunk-mm", "D", "trunk prior: the widest point of the tree is D mm wide", "180");
  args.add_option("scale-uncertainty", "U",
                  "the scale is known to +-U (relative, [0, 0.5)): every rule in mm holds at both\n"
                  "ends of the range; default 0 with --mm-per-px or depth, 0.1 with the trunk prior");
  if (depth == depth_option::offered)
    args.add_option("depth", "DEPTH.png", "16-bit depth in mm registered to the mask (0 = invalid); needs --fx --fy --cx --cy");
  if (depth == depth_option::per_frame)
    args.add_option("depth-dir", "DEPTH_DIR",
                    "each frame's depth, DEPTH_DIR/NAME of the mask: 16-bit PNG in mm registered to\n"
                    "the mask (0 = invalid); needs --fx --fy --cx --cy");
  if (depth != depth_option::not_offered) {
    args.add_option("fx", "F", "focal length x, px");
    args.add_option("fy", "F", "focal length y, px");
    args.add_option("cx", "C", "principal point x, px");
    args.add_option("cy", "C", "principal point y, px");
  }
  args.add_option("roll-deg", "R", "camera roll: angle from the image x axis to the horizon, + clockwise", "0");
  args.add_option("top", "K", "number of ranked candidates", "5");
  args.add_option("downscale", "F", "analyse the mask reduced by F in (0, 1]", "1");
  args.add_option("max-hole-px", "N", "fill holes of at most N pixels first (0 keeps every hole)", "4");
  char gap_default[16];
  std::snprintf(gap_default, sizeof gap_default, "%g", static_cast<double>(bridge_options{}.max_gap_px));
  args.add_option("max-gap-px", "PX",
                  "bridge gaps of at most PX pixels (and a diameter) between aligned ends of a limb\n"
                  "or an end and the limb it was cut from, first (0 bridges none)", gap_default);
  args.add_flag("no-timing", "report every timing as 0 (byte-identical output across runs)");
}

namespace {

/// The option that gives depth: "depth" or "depth-dir".
std::string depth_option_name(depth_option depth) { return depth == depth_option::per_frame ? "depth-dir" : "depth"; }

/// The options after the scale: --roll-deg, --top, --downscale, --max-hole-px, --max-gap-px,
/// --no-timing.
std::string read_common_options(const support::arg_parser& args, run_config& config) {
  const auto roll = args.get_double("roll-deg", 0.0, -360.0, 360.0);
  if (!roll) return roll.error;
  config.roll_deg = static_cast<float>(roll.value);
  const auto top = args.get_int("top", 5, 1, 1000);
  if (!top) return top.error;
  config.top_k = static_cast<std::size_t>(top.value);
  const auto down = args.get_double("downscale", 1.0, 1e-3, 1.0);
  if (!down) return down.error;
  config.downscale = static_cast<float>(down.value);
  const auto holes = args.get_int("max-hole-px", 4, 0, 1 << 30);
  if (!holes) return holes.error;
  config.max_hole_px = static_cast<std::int32_t>(holes.value);
  const auto gap = args.get_double("max-gap-px", static_cast<double>(bridge_options{}.max_gap_px), 0.0, 1e4);
  if (!gap) return gap.error;
  config.max_gap_px = static_cast<float>(gap.value);
  config.timing = !args.flag("no-timing");
  return {};
}

/// --depth or --depth-dir (`depth` says which) and the intrinsics: all or none, fx and fy
/// positive; loads --depth, checks that --depth-dir is a directory.
std::string read_depth_options(const support::arg_parser& args, depth_option depth, run_config& config) {
  const std::string depth_name = depth_option_name(depth);
  const bool given_depth = args.has(depth_name);
  const char* names[] = {"fx", "fy", "cx", "cy"};
  float values[4] = {};
  int given = 0;
  for (int i = 0; i < 4; ++i) {
    const auto v = args.get_double(names[i], 0.0, -1e7, 1e7);
    if (!v) return v.error;
    values[i] = static_cast<float>(v.value);
    given += args.has(names[i]) ? 1 : 0;
  }
  if (given_depth && given != 4) return "--" + depth_name + " needs --fx, --fy, --cx and --cy";
  if (!given_depth && given != 0) return "--fx, --fy, --cx, --cy need --" + depth_name;
  if (given_depth) {
    if (!(values[0] > 0 && values[1] > 0)) return "--fx and --fy must be positive";
    config.scale.intrinsics = pinhole{values[0], values[1], values[2], values[3]};
    const std::filesystem::path path(std::string(*args.value(depth_name)));
    if (depth == depth_option::per_frame) {
      std::error_code ec;
      if (!std::filesystem::is_directory(path, ec)) return "--depth-dir " + path.string() + " is not a directory";
      config.scale.depth_dir = path;
    } else {
      config.scale.depth_mm.emplace();
      if (std::string e = load_depth(path, *config.scale.depth_mm); !e.empty()) return e;
      config.scale.kind = scale_kind::depth;
    }
  }
  return {};
}

}  // namespace

std::string read_pipeline_options(const support::arg_parser& args, depth_option depth,
                                  run_config& config) {
  const auto platform = args.get_choice("platform", "tendon-claw", platform_names);
  if (!platform) return platform.error;
  for (std::size_t i = 0; i < platform_names.size(); ++i)
    if (platform_names[i] == platform.value) config.platform = static_cast<platform_id>(i);

  const std::string depth_name = depth_option_name(depth);
  const bool has_depth = depth != depth_option::not_offered && args.has(depth_name);
  const int scales = (args.has("mm-per-px") ? 1 : 0) + (args.has("trunk-mm") ? 1 : 0) + (has_depth ? 1 : 0);
  if (scales > 1) return "give one of --mm-per-px, --trunk-mm, --" + depth_name;
  const auto mm = args.get_double("mm-per-px", 0.0, 1e-6, 1e6);
  if (!mm) return mm.error;
  const auto trunk = args.get_double("trunk-mm", 180.0, 1e-3, 1e6);
  if (!trunk) return trunk.error;
  config.scale.trunk_mm = static_cast<float>(trunk.value);
  const auto uncertainty = args.get_double("scale-uncertainty", 0.0, 0.0, 0.49);
  if (!uncertainty) return uncertainty.error;
  if (args.has("scale-uncertainty")) config.scale.uncertainty = static_cast<float>(uncertainty.value);
  if (args.has("mm-per-px")) {
    config.scale.kind = scale_kind::fixed;
    config.scale.mm_per_px = static_cast<float>(mm.value);
  }
  if (depth != depth_option::not_offered)
    if (std::string e = read_depth_options(args, depth, config); !e.empty()) return e;
  return read_common_options(args, config);
}

std::string load_depth(const std::filesystem::path& path, image<std::uint16_t>& out) {
  auto png = png::read_png_file(path);
  if (!png) return "cannot read depth " + path.string() + ": " + png.error().message;
  out = png::to_gray16(*png);
  return {};
}

float percentile(std::vector<float> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::min(values.size() - 1, i == 0 ? 0 : i - 1)];
}

perch_options perch_options_of(const run_config& config) {
  perch_options options;
  options.downscale = config.downscale;
  options.max_hole_px = config.max_hole_px;
  options.bridging.enabled = config.max_gap_px > 0;
  options.bridging.max_gap_px = config.max_gap_px;
  options.camera = attitude{config.roll_deg};
  options.ranking.top_k = config.top_k;
  return options;
}

std::string check_output_path(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return path.string() + " is a directory, not a file to write";
  const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : ".";
  if (!std::filesystem::is_directory(parent, ec))
    return "cannot write " + path.string() + ": " + parent.string() + " is not a directory";
  if (::access(parent.c_str(), W_OK) != 0)
    return "cannot write " + path.string() + ": " + parent.string() + " is not writable";
  return {};
}

std::string make_output_dir(const std::filesystem::path& dir, std::string_view file) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) return "cannot create " + dir.string();
  return check_output_path(dir / file);
}

std::string check_output_options(const support::arg_parser& args, std::initializer_list<std::string_view> options) {
  for (const std::string_view option : options)
    if (const auto path = args.value(option))
      if (std::string e = check_output_path(std::string(*path)); !e.empty()) return "--" + std::string(option) + ": " + e;
  return {};
}

std::string describe(const error& e) {
  std::string out(e.message());
  if (!e.detail.empty()) out += " (" + std::string(e.detail) + ")";
  if (e.needed != 0) out += ", needs " + std::to_string(e.needed);
  return out;
}

int exit_code_for(const error& e) {
  return e.code == errc::out_of_memory || e.code == errc::workspace_too_small ? exit_internal : exit_usage;
}

namespace {

std::int64_t steady_now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

analysis_output analyse(const analysis_request& request, const run_config& config, workspace& ws) {
  analysis_output out;
  perch_options options = perch_options_of(config);
  options.clock = config.timing ? &steady_now_ns : nullptr;
  auto found = find_with(request.mask->view(), config, options, ws);
  if (!found) {
    out.exit_code = exit_code_for(found.error());
    out.error = describe(found.error());
    return out;
  }
  perch_result& r = *found;
  r.cold = r.cold && config.timing;  // --no-timing: output that does not depend on the run
  out.outcome = r.outcome;
  out.sites.assign(r.sites.begin(), r.sites.end());
  out.mm_per_px = r.mm_per_px;
  out.total_ms = r.timing.total_ms;
  const platform_geometry geometry = geometry_of(config.platform);
  out.reason = no_perch_reason(r, geometry);
  const document_source source{.input = request.input, .warnings = request.warnings};
  if (request.detect_json) out.detect_json = detect_json(r, source, geometry);
  if (request.graph_json) out.graph_json = graph_json(r, source);
  if (request.annotation) {
    const platform_limits limits = limits_of(config.platform);
    const clearance_envelope envelope{.margin_mm = limits.has_clearance ? limits.clearance_mm : -1.0f,
                                      .uncertainty_px = limits.clearance_uncertainty_px};
    out.annotated = annotate(r, geometry, envelope, *request.mask, request.photo);
  }
  return out;
}

std::string write_text(const std::filesystem::path& path, std::string_view text) {
  if (path.empty()) {
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
      return "cannot write to stdout";
    return {};
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return "cannot open " + path.string() + " for writing";
  file.write(text.data(), static_cast<std::streamsize>(text.size()));
  file.close();
  if (!file) return "cannot write " + path.string();
  return {};
}

void report_error(std::string_view command, std::string_view message) {
  std::fprintf(stderr, "perch %.*s: %.*s\n", static_cast<int>(command.size()), command.data(),
               static_cast<int>(message.size()), message.data());
}

bool parse_or_exit(support::arg_parser& args, int argc, const char* const* argv,
                   std::string_view command, int& exit) {
  args.set_version("perch " + std::string(version));
  const std::string problem = args.parse(argc, argv, 2);
  if (!problem.empty()) {
    report_error(command, problem);
    std::fprintf(stderr, "Run 'perch %.*s --help' for its options.\n", static_cast<int>(command.size()),
                 command.data());
    exit = exit_usage;
    return false;
  }
  if (args.help_requested()) {
    const std::string help = args.help();
    std::fputs(help.c_str(), stdout);
    exit = exit_ok;
    return false;
  }
  if (args.version_requested()) {
    std::printf("%s\n", args.version().c_str());
    exit = exit_ok;
    return false;
  }
  return true;
}

}  // namespace perch::tool
