// SPDX-License-Identifier: BSL-1.0
// perch skeleton / perch graph: one stage's output, for people who want just that.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "report.hpp"
#include "support/json_writer.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

/// The factor `--radius-out` multiplies radii by (16-bit PNG: value = round(16 · r)).
constexpr float radius_scale = 16.0f;

constexpr std::array<std::string_view, 3> method_names = {"medial-axis", "zhang-suen", "guo-hall"};

template <class F>
decltype(auto) visit_method(std::string_view name, F&& f) {
  if (name == "zhang-suen") return f(zhang_suen{});
  if (name == "guo-hall") return f(guo_hall{});
  return f(medial_axis{});
}

struct skeleton_images {
  image<std::uint8_t> skeleton;
  image<std::uint16_t> radius;
  std::size_t pixels = 0;
};

template <class Method>
result<skeleton_images> skeletonise(const image<std::uint8_t>& mask, const Method& method, workspace& ws) {
  skeleton_images out{image<std::uint8_t>(mask.width(), mask.height(), 0),
                      image<std::uint16_t>(mask.width(), mask.height(), 0), 0};
  auto prepared = prepare_mask(mask.view(), ws);
  if (!prepared) return unexpected{prepared.error()};
  if (prepared->tree_pixels == 0) return out;
  const image_view<const std::uint8_t> local(prepared->pixels);
  const auto n = static_cast<std::size_t>(local.width()) * static_cast<std::size_t>(local.height());
  auto dist_memory = ws.allocate<std::uint32_t>(n);
  if (!dist_memory) return unexpected{dist_memory.error()};
  const image_view<std::uint32_t> dist(dist_memory->data(), local.width(), local.height());
  PERCH_TRY(distance_transform_sq(local, dist, ws));
  auto skeleton_memory = ws.allocate_zeroed<std::uint8_t>(n);
  if (!skeleton_memory) return unexpected{skeleton_memory.error()};
  const image_view<std::uint8_t> skeleton(skeleton_memory->data(), local.width(), local.height());
  PERCH_TRY(method(local, image_view<const std::uint32_t>(dist), skeleton, ws));
  for (int y = 0; y < local.height(); ++y)
    for (int x = 0; x < local.width(); ++x) {
      if (skeleton(x, y) == 0) continue;
      const int ix = x + prepared->offset.x;
      const int iy = y + prepared->offset.y;
      if (ix < 0 || iy < 0 || ix >= mask.width() || iy >= mask.height()) continue;
      out.skeleton(ix, iy) = 255;
      const float r = std::sqrt(static_cast<float>(dist(x, y)));
      out.radius(ix, iy) = static_cast<std::uint16_t>(std::min(65535.0f, std::round(radius_scale * r)));
      ++out.pixels;
    }
  return out;
}

}  // namespace

int run_skeleton(int argc, const char* const* argv) {
  support::arg_parser args("perch skeleton",
                           "Writes the skeleton of a tree mask as an 8-bit PNG (255 = skeleton) of the\n"
                           "mask's size, and optionally the radius at every skeleton pixel.");
  args.add_positional("MASK.png", "tree mask (any non-zero pixel is tree), or - for standard input");
  args.add_option("out", "SKEL.png", "skeleton picture to write");
  add_mask_options(args);
  args.add_option("method", "NAME", "medial-axis, zhang-suen or guo-hall", "medial-axis");
  args.add_option("radius-out", "RADIUS.png",
                  "16-bit PNG: round(16 x r) at skeleton pixels, r = Euclidean distance in px\n"
                  "from the pixel to the nearest background pixel; 0 elsewhere");
  args.set_epilog("Prints {\"version\", \"input\", [\"warnings\"], \"method\", \"width\", \"height\", \"skeleton_pixels\",\n"
                  "\"radius_scale\"} on stdout.\n"
                  "Example: perch skeleton examples/data/synth-1.png --out skel.png --radius-out radius.png");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "skeleton", exit)) return exit;
  const auto method = args.get_choice("method", "medial-axis", method_names);
  if (!method) {
    report_error("skeleton", method.error);
    return exit_usage;
  }
  if (!args.has("out")) {
    report_error("skeleton", "missing option --out SKEL.png");
    return exit_usage;
  }
  mask_reading reading;
  std::string problem = read_mask_options(args, reading);
  if (problem.empty()) problem = check_output_options(args, {"out", "radius-out"});
  if (!problem.empty()) {
    report_error("skeleton", problem);
    return exit_usage;
  }
  const std::string mask_path(*args.positional("MASK.png"));
  loaded_mask loaded;
  if (const std::string e = load_mask(mask_path, reading, loaded); !e.empty()) {
    report_error("skeleton", e);
    return exit_usage;
  }
  report_warnings("skeleton", mask_path, loaded.warnings);
  const image<std::uint8_t>& mask = loaded.pixels;
  workspace ws;
  auto made = visit_method(method.value, [&](const auto& m) { return skeletonise(mask, m, ws); });
  if (!made) {
    report_error("skeleton", mask_path + ": " + describe(made.error()));
    return exit_code_for(made.error());
  }
  const png::png_status written =
      png::write_png(std::string(*args.value("out")), image_view<const std::uint8_t>(made->skeleton.view()));
  if (!written) {
    report_error("skeleton", written.error().message);
    return exit_internal;
  }
  if (const auto path = args.value("radius-out")) {
    const png::png_status r = png::write_png(std::string(*path), image_view<const std::uint16_t>(made->radius.view()));
    if (!r) {
      report_error("skeleton", r.error().message);
      return exit_internal;
    }
  }
  support::json_writer json(support::json_style::pretty);
  json.begin_object();
  write_source(json, {.input = mask_path, .warnings = loaded.warnings});
  json.member("method", method.value).member("width", mask.width()).member("height", mask.height());
  json.member("skeleton_pixels", made->pixels).member("radius_scale", radius_scale);
  json.end_object();
  if (const std::string e = write_text({}, std::move(json).take()); !e.empty()) {
    report_error("skeleton", e);
    return exit_internal;
  }
  return exit_ok;
}

int run_graph(int argc, const char* const* argv) {
  support::arg_parser args("perch graph",
                           "Writes the skeleton graph find_perch analyses (after pruning) as JSON.\n"
                           "Pruning weighs branches by the platform's diameters and the scale, so the\n"
                           "platform and scale options apply.");
  args.add_positional("MASK.png", "tree mask (any non-zero pixel is tree), or - for standard input");
  args.add_option("json", "GRAPH.json", "write the JSON here instead of stdout");
  add_mask_options(args);
  add_pipeline_options(args, depth_option::offered);
  args.set_epilog(
      "JSON: {\"version\", \"input\", [\"warnings\"], \"components\": N, \"mm_per_px\", \"nodes\": [{\"id\", \"x\", \"y\", \"kind\": \"junction\"|\"end\"|\n"
      "       \"isolated\"|\"loop\", \"component\", \"trunk\"}], \"edges\": [{\"id\", \"from\", \"to\", \"length_px\",\n"
      "       \"mean_diameter_px\", \"type\", \"polyline\": [[x, y], ...]}]}\n"
      "Example: perch graph examples/data/synth-1.png --json graph.json");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "graph", exit)) return exit;
  run_config config;
  mask_reading reading;
  std::string problem = read_pipeline_options(args, depth_option::offered, config);
  if (problem.empty()) problem = read_mask_options(args, reading);
  if (problem.empty()) problem = check_output_options(args, {"json"});
  if (!problem.empty()) {
    report_error("graph", problem);
    return exit_usage;
  }
  const std::string mask_path(*args.positional("MASK.png"));
  loaded_mask mask;
  if (const std::string e = load_mask(mask_path, reading, mask); !e.empty()) {
    report_error("graph", e);
    return exit_usage;
  }
  report_warnings("graph", mask_path, mask.warnings);
  workspace ws;
  analysis_request request;
  request.mask = &mask.pixels;
  request.input = mask_path;
  request.warnings = mask.warnings;
  request.detect_json = false;
  request.graph_json = true;
  const analysis_output out = analyse(request, config, ws);
  if (out.exit_code != exit_ok) {
    report_error("graph", mask_path + ": " + out.error);
    return out.exit_code;
  }
  if (const std::string e = write_text(std::string(args.value("json").value_or("")), out.graph_json); !e.empty()) {
    report_error("graph", e);
    return exit_internal;
  }
  return exit_ok;
}

}  // namespace perch::tool
