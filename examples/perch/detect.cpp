// SPDX-License-Identifier: BSL-1.0
// perch detect MASK.png: the best perch sites of one mask, as JSON (and a picture).
#include <cstdio>

#include "tool.hpp"

namespace perch::tool {
namespace {

/// The --image photo, of the mask's size. Returns an error message.
std::string load_photo(std::string_view path, const image<std::uint8_t>& mask,
                       std::optional<image<png::rgb8>>& photo) {
  auto png = png::read_png_file(std::string(path));
  if (!png) return png.error().message;
  photo = png::to_rgb8(*png);
  if (photo->width() == mask.width() && photo->height() == mask.height()) return {};
  return "--image " + std::string(path) + " is " + std::to_string(photo->width()) + "x" +
         std::to_string(photo->height()) + ", the mask " + std::to_string(mask.width()) + "x" +
         std::to_string(mask.height());
}

}  // namespace

int run_detect(int argc, const char* const* argv) {
  support::arg_parser args("perch detect",
                           "Finds where a drone can perch on the tree of a mask (any non-zero pixel is tree)\n"
                           "and prints the answer as JSON. MASK.png '-' reads the PNG from standard input.");
  args.add_positional("MASK.png", "tree mask, or - for standard input");
  args.add_option("image", "PHOTO.png", "photo behind the --annotate picture (same size as the mask)");
  add_mask_options(args);
  add_pipeline_options(args, depth_option::offered);
  args.add_option("json", "OUT.json", "write the JSON here instead of stdout");
  args.add_option("annotate", "OUT.png", "write a picture of the answer");
  args.set_epilog(
      "JSON: {\"version\", \"input\", [\"warnings\": [...]], \"status\": \"ok\"|\"no_perch\"|\"no_tree\", [\"reason\"],\n"
      "       \"image\": {\"width\", \"height\"}, \"mm_per_px\", \"platform\", \"perch\": {\"x\", \"y\", \"slope_deg\",\n"
      "       \"diameter_mm\", \"curvature_per_mm\", \"penalty\", \"branch\", \"component\", \"rank\",\n"
      "       \"heading_deg\", \"base_end\": [x, y], \"tip_end\": [x, y], with depth \"position_m\",\n"
      "       \"base_end_m\", \"tip_end_m\", \"axis_m\"} or null,\n"
      "       \"candidates\": [...] (rank 1 = the perch), \"rejected\": {constraint: count},\n"
      "       \"graph\": {\"nodes\", \"edges\", \"components\"}, \"timing_ms\": {stage: ms, ..., \"total\"},\n"
      "       \"cold\": the call grew its memory (a first call: its time includes page faults)}\n"
      "heading_deg: the branch's direction from its trunk-side end to its tip-side end, degrees\n"
      "counter-clockwise from the image's +x axis with y up, (-180, 180].\n"
      "Warnings (stderr and JSON) name input that is probably not a tree mask: a colour image, more than\n"
      "two grey levels, an inverted look; --threshold and --invert say what was meant.\n"
      "Exit status: 0 (also when no perch is found), 2 bad arguments, unreadable input or an output path\n"
      "that cannot be written (checked first: nothing is written), 1 internal failure (out of memory).\n"
      "Example: perch detect examples/data/synth-1.png --annotate perch.png");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "detect", exit)) return exit;
  run_config config;
  mask_reading reading;
  std::string problem = read_pipeline_options(args, depth_option::offered, config);
  if (problem.empty()) problem = read_mask_options(args, reading);
  if (problem.empty()) problem = check_output_options(args, {"json", "annotate"});
  if (!problem.empty()) {
    report_error("detect", problem);
    return exit_usage;
  }
  const std::string mask_path(*args.positional("MASK.png"));
  loaded_mask mask;
  if (const std::string e = load_mask(mask_path, reading, mask); !e.empty()) {
    report_error("detect", e);
    return exit_usage;
  }
  report_warnings("detect", mask_path, mask.warnings);
  std::optional<image<png::rgb8>> photo;
  if (const auto path = args.value("image"))
    if (const std::string e = load_photo(*path, mask.pixels, photo); !e.empty()) {
      report_error("detect", e);
      return exit_usage;
    }
  workspace ws;
  analysis_request request;
  request.mask = &mask.pixels;
  request.input = mask_path;
  request.warnings = mask.warnings;
  request.photo = photo ? &*photo : nullptr;
  request.annotation = args.has("annotate");
  analysis_output out = analyse(request, config, ws);
  if (out.exit_code != exit_ok) {
    report_error("detect", mask_path + ": " + out.error);
    return out.exit_code;
  }
  const std::string json_path(args.value("json").value_or(""));
  if (const std::string e = write_text(json_path, out.detect_json); !e.empty()) {
    report_error("detect", e);
    return exit_internal;
  }
  if (out.annotated) {
    const std::string path(*args.value("annotate"));
    const png::png_status written = png::write_png(path, image_view<const png::rgb8>(out.annotated->view()));
    if (!written) {
      report_error("detect", written.error().message);
      return exit_internal;
    }
  }
  return exit_ok;
}

}  // namespace perch::tool
