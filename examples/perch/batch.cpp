// SPDX-License-Identifier: BSL-1.0
// perch batch DIR --out DIR: detect on every PNG of a directory (or one shard of it), in
// parallel, with summary files; perch batch --merge SHARD_DIR... --out DIR joins shards.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <new>
#include <system_error>

#include "report.hpp"
#include "summary.hpp"
#include "support/parallel_for.hpp"
#include "support/progress.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

/// One input's row and how it failed, if it did.
struct batch_record {
  summary_row row;
  int exit_code = exit_ok;  ///< exit_usage: unreadable; exit_internal: could not write, memory
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
    if (ext == ".png") files.push_back(p);  // a directory or device named *.png is an unreadable input
  }
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return a.filename().string() < b.filename().string(); });
  return {};
}

/// "K/N" with 1 <= K <= N. Returns an error message.
std::string parse_shard(std::string_view text, shard_spec& shard) {
  const std::size_t slash = text.find('/');
  const auto number = [](std::string_view s, int& v) {
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && ec == std::errc{} && end == s.data() + s.size();
  };
  if (slash == std::string_view::npos || !number(text.substr(0, slash), shard.index) ||
      !number(text.substr(slash + 1), shard.count) || shard.count < 1 || shard.index < 1 || shard.index > shard.count)
    return "--shard: expected K/N with 1 <= K <= N, got '" + std::string(text) + "'";
  return {};
}

summary_row failed(std::string file, std::string reason) {
  summary_row row;
  row.file = std::move(file);
  row.status = "error";
  row.reason = std::move(reason);
  return row;
}

/// Detect on one file, its JSON (and picture) written to `out_dir`.
batch_record process(const std::filesystem::path& file, const std::filesystem::path& out_dir, const run_config& config,
                     const mask_reading& reading, bool annotate, workspace& ws) {
  batch_record rec;
  const std::string name = file.filename().string();
  const std::string stem = file.stem().string();
  loaded_mask mask;
  if (std::string e = load_mask(file, reading, mask); !e.empty()) return {failed(name, std::move(e)), exit_usage};
  analysis_request request;
  request.mask = &mask.pixels;
  const std::string input = file.string();
  request.input = input;
  request.warnings = mask.warnings;
  request.annotation = annotate;
  analysis_output out = analyse(request, config, ws);
  if (out.exit_code != exit_ok) return {failed(name, out.error), out.exit_code};
  rec.row.file = name;
  rec.row.status = status_name(out.outcome);
  rec.row.reason = out.reason;
  rec.row.warnings = std::move(mask.warnings);
  rec.row.time_ms = out.total_ms;
  if (!out.sites.empty()) {
    const window_measures& m = out.sites.front().window;
    rec.row.perch = summary_perch{static_cast<float>(m.centre.x), static_cast<float>(m.centre.y), m.slope_deg,
                                  m.claw_diameter_mm, out.sites.front().penalty};
  }
  if (std::string e = write_text(out_dir / (stem + ".json"), out.detect_json); !e.empty())
    return {failed(name, std::move(e)), exit_internal};
  if (out.annotated) {
    const png::png_status written =
        png::write_png(out_dir / (stem + ".annotated.png"), image_view<const png::rgb8>(out.annotated->view()));
    if (!written) return {failed(name, written.error().message), exit_internal};
  }
  return rec;
}

/// `process`, with an exception (out of memory) turned into this input's failure.
batch_record process_guarded(const std::filesystem::path& file, const std::filesystem::path& out_dir,
                             const run_config& config, const mask_reading& reading, bool annotate, workspace& ws) {
  try {
    return process(file, out_dir, config, reading, annotate, ws);
  } catch (const std::bad_alloc&) {
    return {failed(file.filename().string(), "out of memory"), exit_internal};
  } catch (const std::exception& e) {
    return {failed(file.filename().string(), std::string("internal error: ") + e.what()), exit_internal};
  }
}

void print_table(const batch_summary& summary) {
  std::size_t width = 5;
  for (const summary_row& r : summary.rows) width = std::max(width, r.file.size());
  std::printf("%-*s  %-8s  %6s %6s  %9s  %8s  %9s\n", static_cast<int>(width), "image", "status", "x", "y",
              "slope_deg", "diam_mm", "time_ms");
  for (const summary_row& r : summary.rows) {
    if (r.status == "error")
      std::printf("%-*s  %-8s\n", static_cast<int>(width), r.file.c_str(), r.status.c_str());
    else if (r.perch)
      std::printf("%-*s  %-8s  %6.0f %6.0f  %9.1f  %8.1f  %9.2f\n", static_cast<int>(width), r.file.c_str(),
                  r.status.c_str(), static_cast<double>(r.perch->x), static_cast<double>(r.perch->y),
                  static_cast<double>(r.perch->slope_deg), static_cast<double>(r.perch->diameter_mm),
                  static_cast<double>(r.time_ms));
    else
      std::printf("%-*s  %-8s  %6s %6s  %9s  %8s  %9.2f\n", static_cast<int>(width), r.file.c_str(),
                  r.status.c_str(), "-", "-", "-", "-", static_cast<double>(r.time_ms));
  }
  std::printf("\nstatus      images\n");
  for (const char* status : {"ok", "no_perch", "no_tree", "error"})
    std::printf("%-10s  %6td\n", status, std::count_if(summary.rows.begin(), summary.rows.end(),
                                                         [&](const summary_row& r) { return r.status == status; }));
  std::printf("total       %6zu\n", summary.rows.size());
}

/// Writes summary.json and summary.csv into `dir`. Returns an error message.
std::string write_summary_files(const std::filesystem::path& dir, const batch_summary& summary) {
  if (std::string e = write_text(dir / "summary.json", summary_json(summary)); !e.empty()) return e;
  return write_text(dir / "summary.csv", summary_csv(summary));
}

int run_merge(int argc, const char* const* argv) {
  support::arg_parser args("perch batch --merge",
                           "Joins the summary files of `perch batch --shard K/N` runs (every shard 1..N once)\n"
                           "into one summary.json and summary.csv, rows sorted by file name.");
  args.add_positional("SHARD_DIR", "a shard's --out directory", support::arg_presence::one_or_more);
  args.add_flag("merge", "join shards (this mode)");
  args.add_option("out", "DIR", "where the merged summary goes (created if missing)");
  args.set_epilog("Exit status: the whole batch's (0, 2 if any input was unreadable, 1 internal failure),\n"
                  "2 when a shard is missing, given twice or not a shard's output.\n"
                  "Example: perch batch --merge out/shard-1 out/shard-2 --out out/all");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "batch", exit)) return exit;
  if (!args.has("out")) {
    report_error("batch", "missing option --out DIR");
    return exit_usage;
  }
  std::vector<batch_summary> shards;
  for (const std::string& dir : args.positionals()) {
    batch_summary s;
    if (const std::string e = read_summary(dir, s); !e.empty()) {
      report_error("batch", e);
      return exit_usage;
    }
    shards.push_back(std::move(s));
  }
  batch_summary merged;
  const std::filesystem::path out_dir(std::string(*args.value("out")));
  std::string problem = merge_summaries(std::move(shards), merged);
  if (problem.empty()) problem = make_output_dir(out_dir, "summary.json");
  if (!problem.empty()) {
    report_error("batch", problem);
    return exit_usage;
  }
  if (const std::string e = write_summary_files(out_dir, merged); !e.empty()) {
    report_error("batch", e);
    return exit_internal;
  }
  print_table(merged);
  std::printf("output: %s\n", out_dir.string().c_str());
  std::fflush(stdout);
  return merged.exit_code;
}

/// The whole batch's exit status: 1 after an internal failure, else 2 when an input was
/// unreadable or the folder holds no PNG, else 0.
int batch_exit_code(const std::vector<batch_record>& records, std::size_t files_in_input) {
  const auto any = [&](int code) {
    return std::any_of(records.begin(), records.end(), [&](const batch_record& r) { return r.exit_code == code; });
  };
  if (any(exit_internal)) return exit_internal;
  if (any(exit_usage) || files_in_input == 0) return exit_usage;
  return exit_ok;
}

bool merge_requested(int argc, const char* const* argv) {
  for (int i = 2; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--") return false;
    if (a == "--merge") return true;
  }
  return false;
}

}  // namespace

int run_batch(int argc, const char* const* argv) {
  if (merge_requested(argc, argv)) return run_merge(argc, argv);
  support::arg_parser args("perch batch",
                           "Runs detect on every PNG mask in DIR (not recursive), over --jobs threads,\n"
                           "writing OUT/NAME.json (and OUT/NAME.annotated.png with --annotate) per image,\n"
                           "OUT/summary.json and OUT/summary.csv (one row per input) and a table on stdout.\n"
                           "An unreadable file is reported and the batch goes on.");
  args.add_positional("DIR", "directory of tree masks (*.png)");
  args.add_option("out", "DIR", "output directory (created if missing)");
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_option("shard", "K/N", "process only the K-th of N slices of the sorted folder (inputs K, K+N, ...)");
  args.add_flag("merge", "join shards' summaries instead: perch batch --merge SHARD_DIR... --out DIR");
  args.add_flag("annotate", "also write an annotated picture per image");
  args.add_flag("quiet", "no progress bar");
  add_mask_options(args);
  add_pipeline_options(args, depth_option::not_offered);
  args.set_epilog("Exit status: 0; 2 bad arguments, no PNG in DIR, or any input unreadable (after the\n"
                  "rest was processed); 1 internal failure (out of memory, cannot write).\n"
                  "Example: perch batch examples/data --out build/demo --annotate --jobs 2\n"
                  "Across hosts: perch batch DIR --shard $K/4 --out out/$K, then\n"
                  "              perch batch --merge out/1 out/2 out/3 out/4 --out out/all");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "batch", exit)) return exit;
  run_config config;
  mask_reading reading;
  shard_spec shard;
  std::string problem = read_pipeline_options(args, depth_option::not_offered, config);
  if (problem.empty()) problem = read_mask_options(args, reading);
  if (problem.empty() && !args.has("out")) problem = "missing option --out DIR";
  if (const auto text = args.value("shard"); problem.empty() && text) problem = parse_shard(*text, shard);
  const auto jobs = args.get_int("jobs", 0, 0, 1024);
  if (problem.empty() && !jobs) problem = jobs.error;
  const std::filesystem::path in_dir(std::string(*args.positional("DIR")));
  const std::filesystem::path out_dir(std::string(args.value("out").value_or("")));
  std::vector<std::filesystem::path> all_files;
  if (problem.empty()) problem = list_pngs(in_dir, all_files);
  if (problem.empty()) problem = make_output_dir(out_dir, "summary.json");
  if (!problem.empty()) {
    report_error("batch", problem);
    return exit_usage;
  }
  std::vector<std::filesystem::path> files;
  for (std::size_t i = 0; i < all_files.size(); ++i)
    if (shard.holds(i)) files.push_back(all_files[i]);
  const bool annotate = args.flag("annotate");

  const unsigned workers = support::worker_count(files.size(), static_cast<unsigned>(jobs.value));
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());
  support::progress_options progress_options;
  if (args.flag("quiet")) progress_options.display = support::progress_display::off;
  support::progress_bar progress(files.size(), progress_options);
  const std::vector<batch_record> records =
      support::parallel_map(files.size(), static_cast<unsigned>(jobs.value), [&](std::size_t i, unsigned worker) {
        batch_record rec = process_guarded(files[i], out_dir, config, reading, annotate, *spaces[worker]);
        progress.tick();
        return rec;
      });
  progress.finish();

  batch_summary summary;
  summary.input = in_dir.string();
  if (args.has("shard")) summary.shard = shard;
  summary.files_in_input = all_files.size();
  summary.exit_code = batch_exit_code(records, all_files.size());
  for (const batch_record& r : records) {
    if (r.row.status == "error") report_error("batch", "skipped " + r.row.file + ": " + r.row.reason);
    for (const std::string& w : r.row.warnings)
      std::fprintf(stderr, "perch batch: warning: %s: %s\n", r.row.file.c_str(), w.c_str());
    summary.rows.push_back(r.row);
  }
  if (all_files.empty()) report_error("batch", "no PNG file in " + in_dir.string());
  if (const std::string e = write_summary_files(out_dir, summary); !e.empty()) {
    report_error("batch", e);
    return exit_internal;
  }
  print_table(summary);
  std::vector<float> times;
  for (const summary_row& r : summary.rows)
    if (r.status != "error") times.push_back(r.time_ms);
  std::printf("find_perch time: median %.2f ms, p95 %.2f ms (%zu analysed image%s, %u job%s)\n",
              static_cast<double>(percentile(times, 0.5)), static_cast<double>(percentile(times, 0.95)),
              times.size(), times.size() == 1 ? "" : "s", workers, workers == 1 ? "" : "s");
  std::printf("output: %s\n", out_dir.string().c_str());
  std::fflush(stdout);
  return summary.exit_code;
}

}  // namespace perch::tool
