// perch eval DIR: detect on synthetic trees, scored against their truth with the paper's four
// outcomes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <system_error>

#include "support/json_writer.hpp"
#include "support/parallel_for.hpp"
#include "truth.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

/// The PLI paper's four outcomes.
enum class outcome : std::uint8_t { correct, incorrect, missed, correct_none, error };
constexpr std::string_view outcome_keys[] = {"correct_location", "incorrect_location",
                                             "no_result_though_one_existed", "correctly_no_result",
                                             "error"};
constexpr std::string_view outcome_text[] = {"correct location", "incorrect location",
                                             "no result though one existed", "correctly no result",
                                             "error"};

struct eval_record {
  std::string name;
  std::string kind;
  outcome result = outcome::error;
  bool feasible = false;  ///< the truth holds a feasible stretch
  std::string detail;
};

bool diameter_ok(float d_mm, const platform_limits& l) { return d_mm >= l.diameter_min_mm && d_mm <= l.diameter_max_mm; }
bool slope_ok(float s_deg, const platform_limits& l) { return s_deg >= l.slope_min_deg && s_deg <= l.slope_max_deg; }

/// True when some non-twig limb has a stretch at least one drone width long, inside the image,
/// whose truth diameter and slope satisfy the platform's limits at every point (1 px steps).
bool truth_feasible(const truth_file& t, const platform_limits& l) {
  const float window_px = l.drone_width_mm / t.mm_per_px;
  for (const support::limb_truth& limb : t.limbs) {
    if (limb.kind == support::limb_kind::twig) continue;
    const float length = support::length_px(limb);
    float run = 0;
    for (float s = 0; s <= length; s += 1.0f) {
      const Eigen::Vector2f p = support::truth_point_at(limb, s);
      const float d = support::truth_diameter_at(limb, s);
      const bool inside = p.x() - 0.5f * d >= 0 && p.y() - 0.5f * d >= 0 &&
                          p.x() + 0.5f * d <= static_cast<float>(t.width - 1) &&
                          p.y() + 0.5f * d <= static_cast<float>(t.height - 1);
      const bool ok = inside && diameter_ok(d * t.mm_per_px, l) && slope_ok(support::truth_slope_deg_at(limb, s), l);
      run = ok ? run + 1.0f : 0.0f;
      if (run >= window_px) return true;
    }
  }
  return false;
}

std::string fmt(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

}  // namespace

int run_eval(int argc, const char* const* argv) {
  support::arg_parser args("perch eval",
                           "Runs detect on every NAME.png of DIR that has a NAME.truth.json (from perch synth)\n"
                           "and scores the best site with the PLI paper's four outcomes: correct location,\n"
                           "incorrect location, no result though one existed, correctly no result.");
  args.add_positional("DIR", "directory of masks and truth files");
  args.add_flag("known-scale", "use the truth's mm/px (fixed scale) instead of the scale options");
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_option("json", "OUT.json", "also write the scores as JSON");
  add_pipeline_options(args, depth_option::not_offered);
  args.set_epilog(
      "A site is correct when it lies on a truth limb (within half its diameter + 2 px) whose truth\n"
      "diameter and slope there are within the platform's limits. A truth 'has a perch' when a limb\n"
      "holds a stretch one drone width long, inside the image, within those limits throughout.\n"
      "Success rate = (correct location + correctly no result) / images.\n"
      "Exit status: 0; 2 for bad arguments or an unreadable mask or truth file (its row says\n"
      "which); 1 for an internal failure.\n"
      "Example: perch synth --seed 100 --count 30 --out /tmp/trees && perch eval /tmp/trees --known-scale");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "eval", exit)) return exit;
  run_config config;
  if (const std::string e = read_pipeline_options(args, depth_option::not_offered, config); !e.empty()) {
    report_error("eval", e);
    return exit_usage;
  }
  const auto jobs = args.get_int("jobs", 0, 0, 1024);
  if (!jobs) {
    report_error("eval", jobs.error);
    return exit_usage;
  }
  const bool known_scale = args.flag("known-scale");
  const std::filesystem::path dir(std::string(*args.positional("DIR")));
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    report_error("eval", dir.string() + " is not a directory");
    return exit_usage;
  }
  std::vector<std::filesystem::path> masks;
  std::filesystem::directory_iterator it(dir, ec);
  for (; !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    const std::filesystem::path& p = it->path();
    if (p.extension() != ".png") continue;
    std::filesystem::path truth = p;
    truth.replace_extension(".truth.json");
    std::error_code exists_ec;
    if (std::filesystem::exists(truth, exists_ec)) masks.push_back(p);
  }
  if (ec) {
    report_error("eval", "cannot list " + dir.string() + ": " + ec.message());
    return exit_usage;
  }
  std::sort(masks.begin(), masks.end());
  if (masks.empty()) {
    report_error("eval", "no NAME.png with NAME.truth.json in " + dir.string());
    return exit_usage;
  }
  const platform_limits limits = limits_of(config.platform);
  const unsigned workers = support::worker_count(masks.size(), static_cast<unsigned>(jobs.value));
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());

  const std::vector<eval_record> records =
      support::parallel_map(masks.size(), static_cast<unsigned>(jobs.value), [&](std::size_t i, unsigned worker) {
        eval_record rec;
        rec.name = masks[i].stem().string();
        truth_file truth;
        std::filesystem::path truth_path = masks[i];
        truth_path.replace_extension(".truth.json");
        if (std::string e = read_truth(truth_path, truth); !e.empty()) {
          rec.detail = std::move(e);
          return rec;
        }
        rec.kind = truth.kind;
        image<std::uint8_t> mask;
        if (std::string e = load_mask(masks[i], mask); !e.empty()) {
          rec.detail = std::move(e);
          return rec;
        }
        run_config c = config;
        c.timing = false;
        if (known_scale) {
          c.scale.kind = scale_kind::fixed;
          c.scale.mm_per_px = truth.mm_per_px;
        }
        analysis_request request;
        request.mask = &mask;
        request.detect_json = false;
        const analysis_output out = analyse(request, c, *spaces[worker]);
        if (out.exit_code != exit_ok) {
          rec.detail = out.error;
          return rec;
        }
        rec.feasible = truth_feasible(truth, limits);
        if (out.sites.empty()) {
          rec.result = rec.feasible ? outcome::missed : outcome::correct_none;
          return rec;
        }
        const window_measures& m = out.sites.front().window;
        const auto loc = support::locate(truth.limbs, Eigen::Vector2f(static_cast<float>(m.centre.x),
                                                                      static_cast<float>(m.centre.y)));
        const float d_mm = loc.diameter_px * truth.mm_per_px;
        const bool on_limb = loc.limb >= 0 && loc.distance_px <= 0.5f * loc.diameter_px + 2.0f;
        const bool ok = on_limb && diameter_ok(d_mm, limits) && slope_ok(loc.slope_deg, limits);
        rec.result = ok ? outcome::correct : outcome::incorrect;
        rec.detail = fmt("(%.0f, %.0f)", m.centre.x, m.centre.y) +
                     (loc.limb >= 0 ? fmt(" truth d %.0f mm, slope %.0f deg, %.1f px off", static_cast<double>(d_mm),
                                          static_cast<double>(loc.slope_deg), static_cast<double>(loc.distance_px))
                                    : std::string(" no limb"));
        return rec;
      });

  std::size_t width = 5;
  for (const eval_record& r : records) width = std::max(width, r.name.size());
  std::printf("%-*s  %-10s  %-8s  %-28s  %s\n", static_cast<int>(width), "image", "kind", "has perch", "outcome",
              "site");
  std::size_t counts[5] = {};
  for (const eval_record& r : records) {
    ++counts[static_cast<int>(r.result)];
    std::printf("%-*s  %-10s  %-8s  %-28s  %s\n", static_cast<int>(width), r.name.c_str(), r.kind.c_str(),
                r.result == outcome::error ? "?" : (r.feasible ? "yes" : "no"),
                std::string(outcome_text[static_cast<int>(r.result)]).c_str(), r.detail.c_str());
  }
  const std::size_t total = records.size();
  const double success = total == 0 ? 0.0
                                    : static_cast<double>(counts[0] + counts[3]) / static_cast<double>(total);
  std::printf("\n%-30s %6s %7s\n", "outcome", "images", "share");
  for (int k = 0; k < 5; ++k) {
    if (k == 4 && counts[4] == 0) continue;
    std::printf("%-30s %6zu %6.1f%%\n", std::string(outcome_text[k]).c_str(), counts[k],
                total == 0 ? 0.0 : 100.0 * static_cast<double>(counts[k]) / static_cast<double>(total));
  }
  std::printf("success rate: %.1f%% (%zu of %zu; platform %s, scale %s)\n", 100.0 * success,
              counts[0] + counts[3], total, std::string(platform_names[static_cast<std::size_t>(config.platform)]).c_str(),
              known_scale ? "known" : (config.scale.kind == scale_kind::fixed ? "fixed" : "trunk prior"));
  std::fflush(stdout);

  if (const auto path = args.value("json")) {
    support::json_writer json(support::json_style::pretty);
    json.begin_object();
    json.member("platform", platform_names[static_cast<std::size_t>(config.platform)]);
    json.member("images", total).member("success_rate", success);
    json.key("outcomes").begin_object();
    for (int k = 0; k < 5; ++k) json.member(outcome_keys[k], counts[k]);
    json.end_object();
    json.key("results").begin_array();
    for (const eval_record& r : records) {
      json.begin_object(support::json_layout::single_line);
      json.member("image", r.name).member("kind", r.kind).member("has_perch", r.feasible);
      json.member("outcome", outcome_keys[static_cast<int>(r.result)]).member("detail", r.detail);
      json.end_object();
    }
    json.end_array();
    json.end_object();
    if (const std::string e = write_text(std::string(*path), std::move(json).take()); !e.empty()) {
      report_error("eval", e);
      return exit_internal;
    }
  }
  return counts[4] > 0 ? exit_usage : exit_ok;
}

}  // namespace perch::tool
