// SPDX-License-Identifier: BSL-1.0
// perch batch DIR --out DIR: detect on every PNG of a directory, in parallel.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <system_error>

#include "support/parallel_for.hpp"
#include "support/progress.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

struct batch_record {
  std::string name;
  std::string status;  ///< ok, no_perch, error
  std::string message;
  int exit_code = exit_ok;
  float total_ms = 0;
  std::optional<perch_site> best;
};

/// The PNG files directly in `dir`, sorted by name (so the order never depends on the file
/// system). Returns an error message.
std::string list_pngs(const std::filesystem::path& dir, std::vector<std::filesystem::path>& files) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return dir.string() + " is not a directory";
  std::filesystem::directory_iterator it(dir, ec);
  if (ec) return "cannot list " + dir.string() + ": " + ec.message();
  for (; it != std::filesystem::directory_iterator(); it.increment(ec)) {
    if (ec) return "cannot list " + dir.string() + ": " + ec.message();
    const std::filesystem::path& p = it->path();
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
    std::error_code file_ec;
    if (ext == ".png" && it->is_regular_file(file_ec)) files.push_back(p);
  }
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return a.filename().string() < b.filename().string(); });
  return {};
}

float percentile(std::vector<float> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size()))) ;
  return values[std::min(values.size() - 1, i == 0 ? 0 : i - 1)];
}

}  // namespace

int run_batch(int argc, const char* const* argv) {
  support::arg_parser args("perch batch",
                           "Runs detect on every PNG mask in DIR (not recursive), over --jobs threads,\n"
                           "writing OUT/NAME.json (and OUT/NAME.annotated.png with --annotate) per image\n"
                           "and a summary table on stdout. A bad file is reported and skipped.");
  args.add_positional("DIR", "directory of tree masks (*.png)");
  args.add_option("out", "DIR", "output directory (created if missing)");
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_flag("annotate", "also write an annotated picture per image");
  args.add_flag("quiet", "no progress bar");
  add_pipeline_options(args, depth_option::not_offered);
  args.set_epilog("Exit status: 0 (bad images are skipped), 2 bad arguments, 1 internal failure.\n"
                  "Example: perch batch examples/data --out build/demo --annotate --jobs 2");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "batch", exit)) return exit;
  run_config config;
  if (const std::string e = read_pipeline_options(args, depth_option::not_offered, config); !e.empty()) {
    report_error("batch", e);
    return exit_usage;
  }
  if (!args.has("out")) {
    report_error("batch", "missing option --out DIR");
    return exit_usage;
  }
  const auto jobs = args.get_int("jobs", 0, 0, 1024);
  if (!jobs) {
    report_error("batch", jobs.error);
    return exit_usage;
  }
  const std::filesystem::path in_dir(std::string(*args.positional("DIR")));
  const std::filesystem::path out_dir(std::string(*args.value("out")));
  std::vector<std::filesystem::path> files;
  if (const std::string e = list_pngs(in_dir, files); !e.empty()) {
    report_error("batch", e);
    return exit_usage;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec || !std::filesystem::is_directory(out_dir, ec)) {
    report_error("batch", "cannot create " + out_dir.string());
    return exit_usage;
  }
  const bool annotate = args.flag("annotate");

  const unsigned workers = support::worker_count(files.size(), static_cast<unsigned>(jobs.value));
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());
  support::progress_options progress_options;
  if (args.flag("quiet")) progress_options.display = support::progress_display::off;
  support::progress_bar progress(files.size(), progress_options);

  const std::vector<batch_record> records =
      support::parallel_map(files.size(), static_cast<unsigned>(jobs.value), [&](std::size_t i, unsigned worker) {
        batch_record rec;
        const std::filesystem::path& file = files[i];
        rec.name = file.filename().string();
        const std::string stem = file.stem().string();
        image<std::uint8_t> mask;
        if (std::string e = load_mask(file, mask); !e.empty()) {
          rec.status = "error";
          rec.message = std::move(e);
          rec.exit_code = exit_usage;
          progress.tick();
          return rec;
        }
        analysis_request request;
        request.mask = &mask;
        request.annotation = annotate;
        analysis_output out = analyse(request, config, *spaces[worker]);
        if (out.exit_code != exit_ok) {
          rec.status = "error";
          rec.message = out.error;
          rec.exit_code = out.exit_code;
          progress.tick();
          return rec;
        }
        rec.status = out.outcome == perch_outcome::found ? "ok" : "no_perch";
        rec.total_ms = out.total_ms;
        if (!out.sites.empty()) rec.best = out.sites.front();
        if (std::string e = write_text(out_dir / (stem + ".json"), out.detect_json); !e.empty()) {
          rec.status = "error";
          rec.message = std::move(e);
          rec.exit_code = exit_internal;
        } else if (out.annotated) {
          const png::png_status written = png::write_png(out_dir / (stem + ".annotated.png"),
                                                         image_view<const png::rgb8>(out.annotated->view()));
          if (!written) {
            rec.status = "error";
            rec.message = written.error().message;
            rec.exit_code = exit_internal;
          }
        }
        progress.tick();
        return rec;
      });
  progress.finish();

  int result = exit_ok;
  for (const batch_record& r : records) {
    if (r.status != "error") continue;
    report_error("batch", "skipped " + r.name + ": " + r.message);
    if (r.exit_code == exit_internal) result = exit_internal;
  }

  // The summary: one row per image, counts per status, median and p95 time.
  std::size_t width = 5;
  for (const batch_record& r : records) width = std::max(width, r.name.size());
  std::printf("%-*s  %-8s  %6s %6s  %9s  %8s  %9s\n", static_cast<int>(width), "image", "status", "x", "y",
              "slope_deg", "diam_mm", "time_ms");
  std::vector<float> times;
  std::size_t ok = 0, no_perch = 0, errors = 0;
  for (const batch_record& r : records) {
    if (r.status == "ok") ++ok;
    if (r.status == "no_perch") ++no_perch;
    if (r.status == "error") {
      ++errors;
      std::printf("%-*s  %-8s\n", static_cast<int>(width), r.name.c_str(), r.status.c_str());
      continue;
    }
    times.push_back(r.total_ms);
    if (r.best)
      std::printf("%-*s  %-8s  %6d %6d  %9.1f  %8.1f  %9.2f\n", static_cast<int>(width), r.name.c_str(),
                  r.status.c_str(), r.best->window.centre.x, r.best->window.centre.y,
                  static_cast<double>(r.best->window.slope_deg),
                  static_cast<double>(r.best->window.claw_diameter_mm), static_cast<double>(r.total_ms));
    else
      std::printf("%-*s  %-8s  %6s %6s  %9s  %8s  %9.2f\n", static_cast<int>(width), r.name.c_str(),
                  r.status.c_str(), "-", "-", "-", "-", static_cast<double>(r.total_ms));
  }
  std::printf("\nstatus      images\nok          %6zu\nno_perch    %6zu\nerror       %6zu\ntotal       %6zu\n", ok,
              no_perch, errors, records.size());
  std::printf("find_perch time: median %.2f ms, p95 %.2f ms (%zu analysed image%s, %u job%s)\n",
              static_cast<double>(percentile(times, 0.5)), static_cast<double>(percentile(times, 0.95)),
              times.size(), times.size() == 1 ? "" : "s", workers, workers == 1 ? "" : "s");
  std::printf("output: %s\n", out_dir.string().c_str());
  std::fflush(stdout);
  return result;
}

}  // namespace perch::tool
