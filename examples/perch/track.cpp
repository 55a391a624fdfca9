// SPDX-License-Identifier: BSL-1.0
// perch track FRAMES_DIR: find_perch on every frame of a directory (in name order) and the
// tracker across them, one JSON line per frame. perch synth --sequence: an approach sequence's
// frames, their truth and the true camera motion, for perch track.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include "annotate.hpp"
#include "report.hpp"
#include "perch/track.hpp"
#include "support/json_writer.hpp"
#include "support/sequence.hpp"
#include "tool.hpp"
#include "truth.hpp"

namespace perch::tool {
namespace {

namespace st = perch::support;

std::int64_t steady_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// Reads motion.csv: lines "frame,h00,h01,h02,h10,h11,h12,h20,h21,h22" (the motion from the
/// frame before to `frame`; '#' lines and a header without digits skipped). Returns an error
/// message (empty on success). A value that is not a number is kept as NaN: that frame's
/// motion is bad input, which the tracker reports.
std::string read_motion_csv(const std::filesystem::path& path, std::map<int, camera_motion>& out) {
  std::ifstream in(path);
  if (!in) return "cannot read " + path.string();
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#' || line.find_first_of("0123456789") == std::string::npos ||
        std::isalpha(static_cast<unsigned char>(line[0])))
      continue;
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
      fields.push_back(line.substr(start, comma - start));
    fields.push_back(line.substr(start));
    if (fields.size() != 10)
      return path.string() + ":" + std::to_string(line_number) + ": expected frame and 9 numbers";
    camera_motion m;
    for (std::size_t k = 0; k < 9; ++k) {
      char* end = nullptr;
      const float v = std::strtof(fields[k + 1].c_str(), &end);
      m.h[k] = end != fields[k + 1].c_str() ? v : std::numeric_limits<float>::quiet_NaN();
    }
    out[std::atoi(fields[0].c_str())] = m;
  }
  return {};
}

/// One per-frame value of a CSV (`--roll-csv`, `--scale-csv`), by frame number or file name.
struct per_frame_values {
  std::map<int, float> by_index;
  std::map<std::string, float> by_name;  ///< file name or stem

  /// The value for frame `index` read from `file`, if listed (a name before a number).
  [[nodiscard]] std::optional<float> find(int index, const std::filesystem::path& file) const {
    for (const std::string& name : {file.filename().string(), file.stem().string()})
      if (const auto it = by_name.find(name); it != by_name.end()) return it->second;
    if (const auto it = by_index.find(index); it != by_index.end()) return it->second;
    return std::nullopt;
  }
};

/// Reads lines "frame,value" or "name,value" ('#' lines and blank lines skipped; more columns
/// ignored). A first line whose second field does not start with a number is a header: the value is then the
/// column headed `column` (so `perch synth --sequence`'s camera.csv serves). Every value must be
/// a finite number in [lo, hi]. Returns an error message (empty on success).
std::string read_per_frame_csv(const std::filesystem::path& path, std::string_view column, float lo, float hi,
                               per_frame_values& out) {
  std::ifstream in(path);
  if (!in) return "cannot read " + path.string();
  std::string line;
  int line_number = 0;
  std::size_t value_column = 1;
  bool first = true;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
      fields.push_back(line.substr(start, comma - start));
    fields.push_back(line.substr(start));
    const std::string where = path.string() + ":" + std::to_string(line_number) + ": ";
    const auto number = [](const std::string& text, float& v) {
      char* end = nullptr;
      v = std::strtof(text.c_str(), &end);
      return end != text.c_str() && *end == '\0' && std::isfinite(v);
    };
    float v = 0;
    const auto text = [](const std::string& field) {  // nothing strtof reads ("nan" it does)
      char* end = nullptr;
      (void)std::strtof(field.c_str(), &end);
      return end == field.c_str();
    };
    if (first && fields.size() >= 2 && text(fields[1])) {  // a header
      first = false;
      const auto named = std::find(fields.begin(), fields.end(), column);
      if (named == fields.end()) return where + "the header names no column '" + std::string(column) + "'";
      value_column = static_cast<std::size_t>(named - fields.begin());
      if (value_column == 0) return where + "the first column must be the frame or its file name";
      continue;
    }
    first = false;
    if (fields.size() <= value_column || fields[0].empty())
      return where + "expected a frame number or file name, then " + std::string(column);
    if (!number(fields[value_column], v) || v < lo || v > hi)
      return where + std::string(column) + " '" + fields[value_column] + "' is not a number in [" +
             std::to_string(static_cast<int>(lo)) + ", " + std::to_string(static_cast<int>(hi)) + "]";
    const bool digits = std::all_of(fields[0].begin(), fields[0].end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits && fields[0].size() < 10)
      out.by_index[std::atoi(fields[0].c_str())] = v;
    else
      out.by_name[fields[0]] = v;
  }
  return {};
}

/// The PNG frames of `dir`, in name order.
std::vector<std::filesystem::path> frames_of(const std::filesystem::path& dir, std::string& error) {
  std::vector<std::filesystem::path> frames;
  std::error_code ec;
  std::filesystem::directory_iterator it(dir, ec);
  for (; !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    if (it->path().extension() == ".png") frames.push_back(it->path());
  if (ec) error = "cannot list " + dir.string() + ": " + ec.message();
  std::sort(frames.begin(), frames.end());
  return frames;
}

/// `"KEY": [x, y, z]` when `known`, else `"KEY": null`.
void write_point_or_null(st::json_writer& json, std::string_view key, const point3f& p, bool known) {
  if (known)
    write_point3(json, key, p);
  else
    json.key(key).null();
}

/// A track's id, state and pixel; with `metric` (--depth-dir) its camera-frame position in
/// metres (null while no frame has given it depth) and this frame's measurement of it (null
/// when it was not matched to a site with depth in this frame).
void write_track_fields(st::json_writer& json, const perch_track& t, bool metric) {
  json.key("id").value(static_cast<std::int64_t>(t.id))
      .key("state").value(to_string(t.state))
      .key("x").value(static_cast<double>(t.position_px.x()))
      .key("y").value(static_cast<double>(t.position_px.y()));
  if (!metric) return;
  write_point_or_null(json, "position_m", t.position_m, t.has_position);
  write_point_or_null(json, "measured_m", t.measured_m, t.measured);
}

/// `"doubtful"`: null, or why this frame did not confirm the target: not seen in it
/// (`"constraint": "unseen"`, the frames it has been unseen), or the rule its spot failed and by
/// how much (a target kept through a near miss within the rule's noise, or for a frame or two
/// beyond it).
void write_doubt(st::json_writer& json, const perch_track& t) {
  json.key("doubtful");
  if (!t.doubtful) {
    json.null();
    return;
  }
  if (t.misses > 0) {
    json.begin_object()
        .key("constraint").value(std::string_view("unseen"))
        .key("miss").value(static_cast<std::int64_t>(t.misses))
        .key("unit").value(std::string_view("frames"))
        .key("within_noise").value(false)
        .key("frames").value(static_cast<std::int64_t>(t.misses))
        .end_object();
    return;
  }
  json.begin_object()
      .key("constraint").value(t.failed_constraint)
      .key("miss").value(static_cast<double>(t.failed_by))
      .key("unit").value(t.failed_unit)
      .key("within_noise").value(t.marginal)
      .key("frames").value(static_cast<std::int64_t>(t.infeasible_streak))
      .end_object();
}

struct frame_report {
  int frame = 0;
  std::string input;
  std::string error;
  const tracking_result* tracked = nullptr;
  std::string_view motion_source = "identity";  ///< given, estimated or identity
  camera_motion motion{};
  float find_ms = 0, track_ms = 0;
  bool depth_wanted = false;  ///< --depth-dir: the line says what became of the frame's depth
  std::string_view depth;     ///< ok, missing, unreadable, wrong_size, no_valid_depth; empty: not looked for
  std::string depth_error;    ///< why, for unreadable and wrong_size
};

/// `"depth"` (with --depth-dir): what became of the frame's depth image, null when its mask
/// could not be read; and `"depth_error"` when there is one.
void write_depth(st::json_writer& json, const frame_report& f) {
  if (!f.depth_wanted) return;
  json.key("depth");
  if (f.depth.empty())
    json.null();
  else
    json.value(f.depth);
  if (!f.depth_error.empty()) json.key("depth_error").value(f.depth_error);
}

std::string frame_json(const frame_report& f) {
  st::json_writer json;
  const tracking_result& r = *f.tracked;
  json.begin_object()
      .key("frame").value(static_cast<std::int64_t>(f.frame))
      .key("input").value(f.input)
      .key("status").value(to_string(r.status));
  if (!f.error.empty()) json.key("error").value(f.error);
  write_depth(json, f);
  json.key("target");
  if (r.target != nullptr) {
    json.begin_object();
    write_track_fields(json, *r.target, f.depth_wanted);
    json.key("heading_deg").value(static_cast<double>(r.target->heading_deg))
        .key("slope_deg").value(static_cast<double>(r.target->slope_deg))
        .key("diameter_mm").value(static_cast<double>(r.target->diameter_mm))
        .key("penalty").value(static_cast<double>(r.target->penalty));
    write_doubt(json, *r.target);
    json.end_object();
  } else {
    json.null();
  }
  json.key("change");
  if (r.changed) {
    json.begin_object()
        .key("from").value(static_cast<std::int64_t>(r.change.from))
        .key("to").value(static_cast<std::int64_t>(r.change.to))
        .key("reason").value(to_string(r.change.reason));
    if (!r.change.constraint.empty())
      json.key("constraint").value(r.change.constraint)
          .key("miss").value(static_cast<double>(r.change.miss))
          .key("unit").value(r.change.unit)
          .key("frames").value(static_cast<std::int64_t>(r.change.frames));
    json.end_object();
  } else {
    json.null();
  }
  json.key("tracks").begin_array();
  for (const perch_track& t : r.tracks) {
    json.begin_object();
    write_track_fields(json, t, f.depth_wanted);
    json.key("age").value(static_cast<std::int64_t>(t.age))
        .key("hits").value(static_cast<std::int64_t>(t.hits))
        .key("misses").value(static_cast<std::int64_t>(t.misses))
        .key("penalty").value(static_cast<double>(t.penalty))
        .end_object();
  }
  json.end_array();
  json.key("motion").begin_object().key("source").value(f.motion_source);
  json.key("h").begin_array(st::json_layout::single_line);
  for (const float v : f.motion.h) json.value(static_cast<double>(v));
  json.end_array().end_object();
  json.key("timing_ms").begin_object()
      .key("find_perch").value(static_cast<double>(f.find_ms))
      .key("track").value(static_cast<double>(f.track_ms))
      .end_object();
  json.end_object();
  return std::move(json).take();
}

/// With --depth-dir: `config` with the frame's depth image (DEPTH_DIR/NAME of `file`) as its
/// scale, when that image can be read and has the mask's size; `report.depth` says which.
std::optional<run_config> with_frame_depth(const run_config& config, const std::filesystem::path& file,
                                           const image<std::uint8_t>& mask, frame_report& report) {
  if (!config.scale.depth_dir) return std::nullopt;
  const std::filesystem::path path = *config.scale.depth_dir / file.filename();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    report.depth = "missing";
    return std::nullopt;
  }
  run_config out = config;
  out.scale.depth_mm.emplace();
  if (std::string e = load_depth(path, *out.scale.depth_mm); !e.empty()) {
    report.depth = "unreadable";
    report.depth_error = std::move(e);
    return std::nullopt;
  }
  const image<std::uint16_t>& depth = *out.scale.depth_mm;
  if (depth.width() != mask.width() || depth.height() != mask.height()) {
    report.depth = "wrong_size";
    report.depth_error = "depth " + path.string() + " is " + std::to_string(depth.width()) + " x " +
                         std::to_string(depth.height()) + ", the mask " + std::to_string(mask.width()) + " x " +
                         std::to_string(mask.height());
    return std::nullopt;
  }
  report.depth = "ok";
  out.scale.kind = scale_kind::depth;
  return out;
}

/// `find_perch` with the tool's options (and the frame's depth when `depth` is not null), then
/// `tracker.update`; then `on_tracked(found or null, the platform's geometry, the tracking)`
/// while the workspace still holds the analysis.
template <class OnTracked>
tracking_result analyse_and_track(const image<std::uint8_t>& mask, const run_config& config, const run_config* depth,
                                  perch_tracker& tracker, motion_estimator& estimator, workspace& ws,
                                  frame_report& report, OnTracked&& on_tracked) {
  const std::int64_t t0 = steady_ns();
  bool depth_dropped = false;
  auto found = find_in_frame(mask, config, depth, ws, depth_dropped);
  const std::int64_t t1 = steady_ns();
  if (depth_dropped) report.depth = "no_valid_depth";
  if (!found) report.error = describe(found.error());
  if (found) {
    // The estimator sees every analysed frame, so its previous keypoints are the last frame's.
    const motion_estimate estimate = estimator.update(*found);
    if (report.motion_source != "given" && estimate.estimated) {
      report.motion = estimate.motion;
      report.motion_source = "estimated";
    }
  } else {
    estimator.reset();
  }
  const tracking_result r = tracker.update(found, report.motion);
  const std::int64_t t2 = steady_ns();
  report.find_ms = config.timing ? static_cast<float>(static_cast<double>(t1 - t0) * 1e-6) : 0;
  report.track_ms = config.timing ? static_cast<float>(static_cast<double>(t2 - t1) * 1e-6) : 0;
  on_tracked(found ? &*found : nullptr, geometry_of(config.platform), r);
  return r;
}

/// `--annotate DIR` and `--apng FILE`: a picture of every frame (`annotate_tracks`), written to
/// DIR/NAME.annotated.png and added to the animation.
class track_pictures {
 public:
  std::optional<std::filesystem::path> dir;  ///< --annotate
  std::optional<png::apng_encoder> apng;     ///< --apng
  int apng_width = 0;                        ///< --apng-width (0: the frames' width)
  std::uint16_t delay_ms = 100;              ///< --apng-delay-ms
  std::uint16_t hold_ms = 1000;              ///< --apng-hold-ms: frames where the target changes

  [[nodiscard]] bool wanted() const noexcept { return dir.has_value() || apng.has_value(); }

  /// Draws frame `index` (`mask` and `found` null when missing) and writes or adds it. Returns
  /// an error message. Every picture has the first readable frame's size (a frame of another
  /// size is drawn without its mask); a frame before that one has no size: no picture.
  [[nodiscard]] std::string add(int index, const std::filesystem::path& input, const image<std::uint8_t>* mask,
                                const perch_result* found, const platform_geometry& geometry,
                                const tracking_result& tracked, std::string_view error) {
    if (mask != nullptr && width_ == 0) {
      width_ = mask->width();
      height_ = mask->height();
    }
    if (width_ == 0) return {};
    std::string size_error;
    if (mask != nullptr && (mask->width() != width_ || mask->height() != height_)) {
      size_error = "a frame of " + std::to_string(mask->width()) + " x " + std::to_string(mask->height()) +
                   ", not the first frame's " + std::to_string(width_) + " x " + std::to_string(height_);
      error = size_error;
      mask = nullptr;
      found = nullptr;
    }
    const track_picture picture{.frame = index, .width = width_, .height = height_, .mask = mask, .found = found,
                                .tracked = &tracked, .error = error, .last_change_frame = last_change_frame_,
                                .last_change = last_change_};
    if (tracked.changed) {
      last_change_frame_ = index;
      last_change_ = tracked.change;
    }
    std::optional<image<png::rgb8>> full;
    if (dir) {
      full = annotate_tracks(picture, geometry, 0);
      const std::filesystem::path path = *dir / (input.stem().string() + ".annotated.png");
      if (const png::png_status written = png::write_png(path, image_view<const png::rgb8>(full->view())); !written)
        return written.error().message;
    }
    if (apng) {
      const bool same = full && (apng_width <= 0 || apng_width >= width_);
      const image<png::rgb8> scaled = same ? image<png::rgb8>{} : annotate_tracks(picture, geometry, apng_width);
      const png::png_status added = apng->add(same ? image_view<const png::rgb8>(full->view())
                                                   : image_view<const png::rgb8>(scaled.view()),
                                              tracked.changed ? hold_ms : delay_ms);
      if (!added) return added.error().message;
    }
    return {};
  }

 private:
  int width_ = 0, height_ = 0;
  int last_change_frame_ = -1;
  target_change last_change_{};
};

/// Reads --annotate, --apng and their options; creates the --annotate directory. Returns an
/// error message (empty on success).
std::string read_picture_options(const st::arg_parser& args, track_pictures& pictures) {
  const auto width = args.get_int("apng-width", 0, 0, 16384);
  const auto delay = args.get_int("apng-delay-ms", 100, 0, 65535);
  const auto hold = args.get_int("apng-hold-ms", 1000, 0, 65535);
  for (const std::string* e : {&width.error, &delay.error, &hold.error})
    if (!e->empty()) return *e;
  if (!args.has("apng"))
    for (const char* option : {"apng-width", "apng-delay-ms", "apng-hold-ms"})
      if (args.has(option)) return "--" + std::string(option) + " needs --apng";
  pictures.apng_width = width.value;
  pictures.delay_ms = static_cast<std::uint16_t>(delay.value);
  pictures.hold_ms = static_cast<std::uint16_t>(hold.value);
  if (std::string e = check_output_options(args, {"apng"}); !e.empty()) return e;
  if (args.has("apng")) pictures.apng.emplace();
  if (const auto dir = args.value("annotate")) {
    pictures.dir = std::filesystem::path(std::string(*dir));
    if (std::string e = make_output_dir(*pictures.dir, "frame.annotated.png"); !e.empty()) return "--annotate: " + e;
  }
  return {};
}

/// OUT/intrinsics.csv of `perch synth --sequence --depth`: a header and one line fx,fy,cx,cy.
std::string write_intrinsics(const std::filesystem::path& path, const pinhole& camera) {
  char text[200];
  std::snprintf(text, sizeof text, "fx,fy,cx,cy\n%.9g,%.9g,%.9g,%.9g\n", static_cast<double>(camera.fx),
                static_cast<double>(camera.fy), static_cast<double>(camera.cx), static_cast<double>(camera.cy));
  return write_text(path, text);
}

}  // namespace

int run_track(int argc, const char* const* argv) {
  st::arg_parser args(
      "perch track",
      "Runs detect on every PNG mask of FRAMES_DIR (in name order) and follows the perch across\n"
      "them with perch::perch_tracker: one JSON line per frame on stdout.");
  args.add_positional("FRAMES_DIR", "directory of masks, one per frame");
  args.add_option("motion", "motion.csv",
                  "camera motion per frame: lines 'frame,h00,h01,h02,h10,h11,h12,h20,h21,h22', the\n"
                  "homography from the previous frame's pixels to this frame's (perch synth\n"
                  "--sequence writes one); frames not listed: estimated from the masks");
  args.add_option("roll-csv", "FILE",
                  "camera roll per frame, degrees: lines 'frame,roll_deg' or 'name,roll_deg'\n"
                  "(frame number from 0 in name order, or file name); with a header line, the\n"
                  "column roll_deg (perch synth --sequence's camera.csv); others: --roll-deg");
  args.add_option("scale-csv", "FILE",
                  "known scale per frame, mm per input pixel: lines 'frame,mm_per_px' or\n"
                  "'name,mm_per_px', or the column mm_per_px (camera.csv); frames not\n"
                  "listed: --mm-per-px or --trunk-mm");
  args.add_option("annotate", "OUT_DIR",
                  "a picture of every frame, OUT_DIR/NAME.annotated.png (created if\n"
                  "missing): the mask, every track with its id (confirmed, tentative, lost),\n"
                  "the target and its heading, the change of target and its reason");
  args.add_option("apng", "OUT.png", "write those pictures as one animated PNG (APNG)");
  args.add_option("apng-width", "W", "the animation's width in pixels; 0: the frames' width", "0");
  args.add_option("apng-delay-ms", "MS", "how long each frame shows", "100");
  args.add_option("apng-hold-ms", "MS", "how long a frame where the target changes shows", "1000");
  add_pipeline_options(args, depth_option::per_frame);
  add_mask_options(args);
  args.set_epilog(
      "Each line: {\"frame\", \"input\", \"status\", \"target\": {\"id\", \"state\", \"x\", \"y\",\n"
      "\"heading_deg\", \"slope_deg\", \"diameter_mm\", \"penalty\", \"doubtful\": {\"constraint\", \"miss\",\n"
      "\"unit\", \"within_noise\", \"frames\"} or null} or null, \"change\": {\"from\", \"to\", \"reason\"[,\n"
      "\"constraint\", \"miss\", \"unit\", \"frames\"]} or null, \"tracks\": [{\"id\", \"state\", \"x\", \"y\", \"age\", \"hits\",\n"
      "\"misses\", \"penalty\"}], \"motion\": {\"source\": given|estimated|identity, \"h\"}, \"timing_ms\": {\"find_perch\", \"track\"}}.\n"
      "status: ok, no_perch, no_tree, wrong_size, bad_motion, missing_frame (an unreadable mask or\n"
      "a failed analysis, with \"error\").\n"
      "With --depth-dir, after \"status\": \"depth\": ok, missing, unreadable, wrong_size (with\n"
      "\"depth_error\") or no_valid_depth (no depth on the tree), null for an unreadable mask; a\n"
      "frame without usable depth is analysed with --scale-csv or the trunk prior. The target and\n"
      "each track gain \"position_m\": [x, y, z], the camera-frame position in metres (x right,\n"
      "y down, z along the optical axis) of the track's pixel at its depth, or null until a frame\n"
      "gave the track depth: the depth is predicted with the motion's scale (a limb that looks s\n"
      "times larger is s times nearer) and weighed against each frame's by their uncertainties\n"
      "(a depth image's millimetres against the motion's scale), so the position follows the\n"
      "approach and keeps following it while a track coasts; and \"measured_m\": this frame's\n"
      "unsmoothed measurement of the matched site, or null when not matched to a site with depth.\n"
      "Exit status: 0; 2 for bad arguments (a bad CSV, missing or bad intrinsics,\n"
      "an --annotate or --apng path that cannot be written); 1 when writing a picture fails.\n"
      "Example: perch synth --sequence 7 --out seq7 && perch track seq7 --motion seq7/motion.csv\n"
      "         --roll-csv seq7/camera.csv --scale-csv seq7/camera.csv --apng track.png\n"
      "         --apng-width 480 > seq7/track.jsonl\n"
      "With depth: perch synth --sequence 7 --depth --out seq7 && perch track seq7 --depth-dir\n"
      "         seq7/depth --fx 960 --fy 960 --cx 479.5 --cy 359.5 (seq7/intrinsics.csv's values)");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "track", exit)) return exit;
  run_config config;
  mask_reading reading;
  for (const std::string& e : {read_pipeline_options(args, depth_option::per_frame, config),
                               read_mask_options(args, reading)})
    if (!e.empty()) {
      report_error("track", e);
      return exit_usage;
    }
  track_pictures pictures;
  if (const std::string e = read_picture_options(args, pictures); !e.empty()) {
    report_error("track", e);
    return exit_usage;
  }
  const std::filesystem::path dir{std::string(*args.positional("FRAMES_DIR"))};
  std::string error;
  const std::vector<std::filesystem::path> frames = frames_of(dir, error);
  if (!error.empty() || frames.empty()) {
    report_error("track", error.empty() ? "no PNG frame in " + dir.string() : error);
    return exit_usage;
  }
  std::map<int, camera_motion> motions;
  if (args.has("motion"))
    if (const std::string e = read_motion_csv(std::string(*args.value("motion")), motions); !e.empty()) {
      report_error("track", e);
      return exit_usage;
    }
  per_frame_values rolls, scales;
  for (const auto& [option, column, lo, hi, values] :
       {std::tuple{"roll-csv", "roll_deg", -360.0f, 360.0f, &rolls}, std::tuple{"scale-csv", "mm_per_px", 1e-6f, 1e6f, &scales}})
    if (const auto path = args.value(option))
      if (const std::string e = read_per_frame_csv(std::string(*path), column, lo, hi, *values); !e.empty()) {
        report_error("track", "--" + std::string(option) + ": " + e);
        return exit_usage;
      }
  workspace ws;
  perch_tracker tracker({}, config.scale.depth_dir ? std::optional(config.scale.intrinsics) : std::nullopt);
  motion_estimator estimator;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    frame_report report;
    report.frame = static_cast<int>(i);
    report.input = frames[i].string();
    report.depth_wanted = config.scale.depth_dir.has_value();
    const auto given = motions.find(report.frame);
    if (given != motions.end()) {
      report.motion_source = "given";
      report.motion = given->second;
    }
    loaded_mask mask;
    tracking_result r;
    std::string picture_error;
    if (std::string e = load_mask(frames[i], reading, mask); !e.empty()) {
      report.error = std::move(e);
      estimator.reset();
      r = tracker.skip(report.motion);
      if (pictures.wanted())
        picture_error = pictures.add(report.frame, frames[i], nullptr, nullptr, geometry_of(config.platform), r,
                                     report.error);
    } else {
      run_config frame_config = config;
      if (const auto roll = rolls.find(report.frame, frames[i])) frame_config.roll_deg = *roll;
      if (const auto scale = scales.find(report.frame, frames[i])) {
        frame_config.scale.kind = scale_kind::fixed;
        frame_config.scale.mm_per_px = *scale;
      }
      const std::optional<run_config> depth_config = with_frame_depth(frame_config, frames[i], mask.pixels, report);
      r = analyse_and_track(mask.pixels, frame_config, depth_config ? &*depth_config : nullptr, tracker, estimator, ws,
                            report,
                            [&](const perch_result* found, const platform_geometry& geometry, const tracking_result& t) {
                              if (pictures.wanted())
                                picture_error = pictures.add(report.frame, frames[i], &mask.pixels, found, geometry, t,
                                                             report.error);
                            });
    }
    if (!picture_error.empty()) {
      report_error("track", picture_error);
      return exit_internal;
    }
    report.tracked = &r;
    if (const std::string e = write_text({}, frame_json(report) + "\n"); !e.empty()) {
      report_error("track", e);
      return exit_internal;
    }
  }
  if (pictures.apng)
    if (const png::png_status written = png::write_apng(std::string(*args.value("apng")), *pictures.apng); !written) {
      report_error("track", written.error().message);
      return exit_internal;
    }
  return exit_ok;
}

int run_synth_sequence(int argc, const char* const* argv) {
  st::arg_parser args(
      "perch synth --sequence",
      "Writes approach sequence I (support/sequence.hpp: a population tree filmed from 3x to 1x\n"
      "the distance with drift, roll, shake and segmentation noise): OUT/frame-NNNN.png (255 =\n"
      "tree), OUT/frame-NNNN.truth.json (the tree as seen in that frame), OUT/motion.csv (the\n"
      "true motion from each frame's predecessor, for perch track --motion) and OUT/camera.csv\n"
      "(frame, roll_deg, mm_per_px, scale).");
  args.add_option("sequence", "I", "sequence index (perch eval --sequences uses 0 … N-1)", "0");
  args.add_option("frames", "F", "frames", "90");
  args.add_option("family", "F", "the population family the tree comes from: arcs, colonisation or\n"
                                 "sympodial (as perch eval --sequences --family)", "arcs");
  args.add_option("out", "DIR", "output directory (created if missing)");
  args.add_flag("depth",
                "also write OUT/depth/frame-NNNN.png (16-bit, mm: the tree at the camera's\n"
                "distance, 0 elsewhere) and OUT/intrinsics.csv (fx,fy,cx,cy of that camera),\n"
                "for perch track --depth-dir");
  args.set_epilog(
      "Example: perch synth --sequence 7 --depth --out seq7 && perch track seq7 --depth-dir seq7/depth\n"
      "         --fx 960 --fy 960 --cx 479.5 --cy 359.5 (the values of seq7/intrinsics.csv)");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "synth", exit)) return exit;
  const auto index = args.get_int("sequence", 0, 0, 1000000);
  const auto frames = args.get_int("frames", 90, 1, 100000);
  for (const std::string* e : {&index.error, &frames.error})
    if (!e->empty()) {
      report_error("synth", *e);
      return exit_usage;
    }
  const std::string family_name = args.get_string("family", "arcs").value;
  const std::optional<st::tree_family> family = st::family_named(family_name);
  if (!family) {
    report_error("synth", "--family must be arcs, colonisation or sympodial, not " + family_name);
    return exit_usage;
  }
  if (!args.has("out")) {
    report_error("synth", "missing option --out DIR");
    return exit_usage;
  }
  const std::filesystem::path dir(std::string(*args.value("out")));
  const bool depth = args.flag("depth");
  std::string problem = make_output_dir(dir, "frame-0000.png");
  if (problem.empty() && depth) problem = make_output_dir(dir / "depth", "frame-0000.png");
  if (!problem.empty()) {
    report_error("synth", problem);
    return exit_usage;
  }
  st::sequence_options options;
  options.frames = frames.value;
  const st::approach_sequence seq = st::evaluation_sequence(index.value, options, *family);
  if (depth)
    if (const std::string e = write_intrinsics(dir / "intrinsics.csv", seq.camera()); !e.empty()) {
      report_error("synth", e);
      return exit_internal;
    }
  std::string motion_csv = "# frame,h00,h01,h02,h10,h11,h12,h20,h21,h22: previous frame -> this\n";
  std::string camera_csv = "frame,roll_deg,mm_per_px,scale\n";
  char line[400];
  for (int f = 0; f < seq.frames(); ++f) {
    const st::sequence_frame frame = seq.frame(f);
    char name[32];
    std::snprintf(name, sizeof name, "frame-%04d", f);
    image<std::uint8_t> png_mask(frame.mask.width(), frame.mask.height(), 0);
    for (int y = 0; y < png_mask.height(); ++y)
      for (int x = 0; x < png_mask.width(); ++x) png_mask(x, y) = frame.mask(x, y) != 0 ? 255 : 0;
    png::png_status written =
        png::write_png(dir / (std::string(name) + ".png"), image_view<const std::uint8_t>(png_mask.view()));
    if (written && depth)
      written = png::write_png(dir / "depth" / (std::string(name) + ".png"),
                               image_view<const std::uint16_t>(seq.depth_mm(frame).view()));
    if (!written) {
      report_error("synth", written.error().message);
      return exit_internal;
    }
    truth_file truth{"sequence", static_cast<std::uint32_t>(index.value), frame.mask.width(),
                     frame.mask.height(), frame.tree.mm_per_px, frame.tree.limbs};
    if (const std::string e = write_text(dir / (std::string(name) + ".truth.json"), truth_json(truth));
        !e.empty()) {
      report_error("synth", e);
      return exit_internal;
    }
    motion_csv += std::to_string(f);
    for (const float v : frame.motion.h) {
      std::snprintf(line, sizeof line, ",%.9g", static_cast<double>(v));
      motion_csv += line;
    }
    motion_csv += '\n';
    std::snprintf(line, sizeof line, "%d,%.6g,%.6g,%.6g\n", f, static_cast<double>(frame.roll_deg),
                  static_cast<double>(frame.tree.mm_per_px), static_cast<double>(frame.scale));
    camera_csv += line;
  }
  for (const auto& [file, text] : {std::pair{"motion.csv", &motion_csv}, std::pair{"camera.csv", &camera_csv}})
    if (const std::string e = write_text(dir / file, *text); !e.empty()) {
      report_error("synth", e);
      return exit_internal;
    }
  std::printf("sequence %d: %d frames in %s\n", index.value, seq.frames(), dir.string().c_str());
  return exit_ok;
}

}  // namespace perch::tool
