// SPDX-License-Identifier: BSL-1.0
// perch eval: detect on synthetic trees (files from perch synth, or a built-in population made
// in memory), each chosen site judged by the full truth (support::perch_truth), reported with
// the paper's four outcomes per family, per rule broken, per knob and per knife-edge tree.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>

#include "support/json_writer.hpp"
#include "support/parallel_for.hpp"
#include "support/population.hpp"
#include "support/progress.hpp"
#include "truth.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

namespace st = perch::support;

/// The PLI paper's four outcomes (and an error: the tree could not be analysed).
enum class outcome : std::uint8_t { correct, incorrect, missed, correct_none, error };
constexpr std::size_t outcome_count = 5;
constexpr std::string_view outcome_keys[] = {"correct_location", "incorrect_location",
                                             "no_result_though_one_existed", "correctly_no_result",
                                             "error"};
constexpr std::string_view outcome_text[] = {"correct location", "incorrect location",
                                             "no result though one existed", "correctly no result",
                                             "error"};

/// A feasible stretch whose window centres span less than this is a knife-edge tree: one pixel
/// of measurement decides it.
constexpr float knife_edge_px = 3.0f;

/// Why an incorrect site is wrong: the truth's verdict of the window centred there (rules of
/// `perch_truth`), or `off_axis` (a feasible window there, but the site is farther than the
/// tolerance from its centreline), or `no_limb` (no limb near the site).
constexpr std::string_view cause_keys[] = {"clearance", "slope",   "bend",        "diameter",
                                           "resolution", "outside_image", "unsupported", "off_limb",
                                           "twig",      "bending", "off_axis",    "no_limb"};

/// Knobs of the populations in a fixed order (others, e.g. a file's kind, follow by name).
constexpr std::string_view knob_order[] = {"clean",     "none",      "noisy",    "bent",     "kinks",
                                           "crossings", "second",    "fragments", "overflow", "decurrent",
                                           "excurrent", "columnar",  "irregular", "sympodial", "monopodial",
                                           "mixed",     "fastigiate", "droop",   "stubs",    "foliage",
                                           "soft",      "rough",     "dilated",  "eroded",   "holes",
                                           "occluded",  "broken",    "coarse"};

struct tree_record {
  std::string name;    ///< file stem, or "arcs-12"
  std::string family;  ///< arcs, colonisation, sympodial, shapes
  std::string kind;    ///< knobs joined by '+' (population) or the truth file's kind
  std::vector<std::string> knobs;
  bool built_without_perch = false;
  bool truth_known = false;
  bool has_perch = false;
  bool knife_edge = false;
  std::size_t stretches = 0;
  float longest_px = 0;  ///< the longest stretch's span of window centres, px
  float tolerance_px = 0;
  outcome result = outcome::error;
  bool site = false;
  float x = 0, y = 0;
  float nearest_px = std::numeric_limits<float>::infinity();  ///< to a feasible window centre
  std::string cause;  ///< for an incorrect location
  float miss = 0;     ///< by how much, in `unit`
  std::string unit;
  std::string detail;  ///< the measure behind the cause, or the error
};

std::string fmt(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[200];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

/// The truth's rules for a platform. The tendon claw's are the truth's own definition
/// (`claw_spec`'s defaults, as tests/pli_accuracy_test.cpp uses them), never the pipeline's
/// tuning of its constraints (e.g. the margins it adds for measurement error); other platforms
/// get their declared values, a rule they lack never failing.
st::claw_spec spec_of(platform_id id, const platform_limits& l) {
  st::claw_spec s;
  if (id == platform_id::tendon_claw) return s;
  s.drone_width_mm = l.drone_width_mm;
  s.claw_mm = l.claw_width_mm;
  s.diameter_min_mm = l.diameter_min_mm;
  s.diameter_max_mm = l.diameter_max_mm;
  s.resolution_px = l.resolution_px;
  s.max_slope_deg = l.slope_max_deg;
  s.max_bend_deg = l.bend_max_deg;
  s.clearance_mm = l.has_clearance ? l.clearance_mm : 0.0f;
  s.border_margin_px = l.border_px;
  s.mass_kg = l.mass_kg > 0 ? l.mass_kg : 1.0f;
  s.max_stress_mpa = l.max_stress_mpa;
  return s;
}

/// Fills the cause of an incorrect site at `p`: the truth's verdict there and by how much.
void judge_site(tree_record& rec, const st::synthetic_tree& tree, const st::perch_truth& truth,
                Eigen::Vector2f p) {
  const st::claw_spec& spec = truth.spec();
  const float mmpp = tree.mm_per_px;
  const st::limb_location at = st::locate(tree, p, st::limb_set::without_twigs);
  if (at.limb < 0) {
    rec.cause = "no_limb";
    rec.detail = "no limb";
    return;
  }
  const st::window_truth w = truth.window(at.limb, at.arc_px);
  const float d_px = w.claw_diameter_mm / mmpp;
  switch (w.verdict) {
    case st::window_verdict::feasible:
      rec.cause = "off_axis";
      rec.miss = at.distance_px - rec.tolerance_px;
      rec.unit = "px";
      rec.detail = fmt("%.1f px off the centreline of a feasible window", static_cast<double>(at.distance_px));
      return;
    case st::window_verdict::clearance:
      rec.miss = spec.clearance_mm - w.clearance_mm;
      rec.unit = "mm";
      rec.detail = fmt("gap %.1f mm, %.1f short of %.0f", static_cast<double>(w.clearance_mm),
                       static_cast<double>(rec.miss), static_cast<double>(spec.clearance_mm));
      break;
    case st::window_verdict::slope:
      rec.miss = w.slope_deg - spec.max_slope_deg;
      rec.unit = "deg";
      rec.detail = fmt("slope %.1f deg, %.1f over %.0f", static_cast<double>(w.slope_deg),
                       static_cast<double>(rec.miss), static_cast<double>(spec.max_slope_deg));
      break;
    case st::window_verdict::bend:
      rec.miss = w.bend_deg - spec.max_bend_deg;
      rec.unit = "deg";
      rec.detail = fmt("bend %.1f deg, %.1f over %.0f", static_cast<double>(w.bend_deg),
                       static_cast<double>(rec.miss), static_cast<double>(spec.max_bend_deg));
      break;
    case st::window_verdict::diameter:
      rec.miss = w.claw_diameter_mm < spec.diameter_min_mm ? spec.diameter_min_mm - w.claw_diameter_mm
                                                           : w.claw_diameter_mm - spec.diameter_max_mm;
      rec.unit = "mm";
      rec.detail = fmt("diameter %.1f mm, %.1f outside %.0f", static_cast<double>(w.claw_diameter_mm),
                       static_cast<double>(rec.miss),
                       static_cast<double>(w.claw_diameter_mm < spec.diameter_min_mm ? spec.diameter_min_mm
                                                                                     : spec.diameter_max_mm));
      break;
    case st::window_verdict::resolution:
      rec.miss = std::max(spec.diameter_min_mm / mmpp + spec.resolution_px - d_px,
                          d_px + spec.resolution_px - spec.diameter_max_mm / mmpp);
      rec.unit = "px";
      rec.detail = fmt("diameter %.1f mm = %.2f px, %.2f px too close to the range's end",
                       static_cast<double>(w.claw_diameter_mm), static_cast<double>(d_px),
                       static_cast<double>(rec.miss));
      break;
    case st::window_verdict::outside_image:
      rec.miss = spec.border_margin_px - w.border_px;
      rec.unit = "px";
      rec.detail = fmt("%.1f px from the border, %.1f short of %.0f", static_cast<double>(w.border_px),
                       static_cast<double>(rec.miss), static_cast<double>(spec.border_margin_px));
      break;
    case st::window_verdict::bending:
      rec.miss = w.stress_mpa - spec.max_stress_mpa;
      rec.unit = "MPa";
      rec.detail = fmt("stress %.1f MPa, %.1f over %.1f", static_cast<double>(w.stress_mpa),
                       static_cast<double>(rec.miss), static_cast<double>(spec.max_stress_mpa));
      break;
    case st::window_verdict::off_limb: {
      const float half = 0.5f * truth.window_px();
      const float over = std::max(half - at.arc_px, at.arc_px + half - st::length_px(tree.limbs[static_cast<std::size_t>(at.limb)]));
      rec.miss = over * mmpp;
      rec.unit = "mm";
      rec.detail = fmt("the window runs %.1f mm off its limb's end", static_cast<double>(rec.miss));
      break;
    }
    case st::window_verdict::twig:
      rec.miss = spec.twig_max_mm - w.claw_diameter_mm;
      rec.unit = "mm";
      rec.detail = fmt("a twig (%.1f mm)", static_cast<double>(w.claw_diameter_mm));
      break;
    case st::window_verdict::unsupported:
      rec.miss = 1;
      rec.detail = "a detached piece of mask";
      break;
  }
  rec.cause = st::to_string(w.verdict);
}

/// Detect on `tree` (its mask), judged by its truth.
void evaluate(tree_record& rec, const st::synthetic_tree& tree, const st::claw_spec& spec,
              const run_config& config, workspace& ws) {
  const st::perch_truth truth(tree, spec);
  rec.truth_known = true;
  rec.has_perch = truth.has_perch();
  rec.stretches = truth.stretches().size();
  rec.longest_px = -1;
  Eigen::Vector2f longest_at = Eigen::Vector2f::Zero();
  for (const st::feasible_stretch& s : truth.stretches()) {
    const float span = s.arc_end_px - s.arc_begin_px - truth.window_px();
    if (span <= rec.longest_px) continue;
    rec.longest_px = span;
    longest_at = st::truth_point_at(tree.limbs[static_cast<std::size_t>(s.limb)], 0.5f * (s.arc_begin_px + s.arc_end_px));
  }
  rec.longest_px = std::max(rec.longest_px, 0.0f);
  rec.knife_edge = rec.has_perch && rec.longest_px < knife_edge_px;
  rec.tolerance_px = 3.0f + 0.03f * truth.window_px();

  analysis_request request;
  request.mask = &tree.mask;
  request.detect_json = false;
  const analysis_output out = analyse(request, config, ws);
  if (out.exit_code != exit_ok) {
    rec.detail = out.error;
    return;
  }
  if (out.sites.empty()) {
    rec.result = rec.has_perch ? outcome::missed : outcome::correct_none;
    if (rec.has_perch)
      rec.detail = fmt("feasible stretches: %.0f, the longest (%.0f px of centres) around ", static_cast<double>(rec.stretches),
                       static_cast<double>(rec.longest_px)) +
                   fmt("(%.0f, %.0f)", static_cast<double>(longest_at.x()), static_cast<double>(longest_at.y()));
    return;
  }
  const window_measures& m = out.sites.front().window;
  rec.site = true;
  rec.x = static_cast<float>(m.centre.x);
  rec.y = static_cast<float>(m.centre.y);
  const Eigen::Vector2f p(rec.x, rec.y);
  rec.nearest_px = truth.nearest_site(p).distance_px;
  if (rec.has_perch && rec.nearest_px <= rec.tolerance_px) {
    rec.result = outcome::correct;
    return;
  }
  rec.result = outcome::incorrect;
  judge_site(rec, tree, truth, p);
}

/// Counts of the outcomes over a set of trees.
struct tally {
  std::size_t trees = 0;
  std::size_t outcomes[outcome_count] = {};
  std::size_t with_perch = 0;
  std::size_t without_perch = 0;
  std::size_t false_perches = 0;  ///< a perch given on a tree with no feasible stretch
  std::size_t knife_edge = 0;
  std::size_t knife_edge_correct = 0;

  void add(const tree_record& r) {
    ++trees;
    ++outcomes[static_cast<std::size_t>(r.result)];
    if (r.truth_known) (r.has_perch ? with_perch : without_perch) += 1;
    if (r.truth_known && !r.has_perch && r.site) ++false_perches;
    if (r.knife_edge) {
      ++knife_edge;
      knife_edge_correct += r.result == outcome::correct ? 1 : 0;
    }
  }
  [[nodiscard]] std::size_t n(outcome o) const { return outcomes[static_cast<std::size_t>(o)]; }
  /// Correct locations / trees with a feasible stretch.
  [[nodiscard]] double success() const {
    return with_perch == 0 ? 0.0 : static_cast<double>(n(outcome::correct)) / static_cast<double>(with_perch);
  }
  /// The same without the knife-edge trees.
  [[nodiscard]] double success_without_knife_edge() const {
    const std::size_t d = with_perch - knife_edge;
    return d == 0 ? 0.0 : static_cast<double>(n(outcome::correct) - knife_edge_correct) / static_cast<double>(d);
  }
};

struct cause_tally {
  std::size_t count = 0;
  std::size_t false_perches = 0;
  std::string unit;
  double miss_sum = 0;
  float miss_max = 0;
  std::vector<std::string> trees;
};

/// Everything the report shows.
struct summary {
  tally all;
  std::vector<std::pair<std::string, tally>> families;  ///< in order of appearance
  std::vector<std::pair<std::string, tally>> knobs;     ///< `knob_order`, then by name
  std::map<std::string, cause_tally> causes;
  std::size_t built_without = 0, built_without_given = 0;
  tally knife;  ///< the knife-edge trees alone
};

tally& slot(std::vector<std::pair<std::string, tally>>& v, const std::string& key) {
  for (auto& [k, t] : v)
    if (k == key) return t;
  return v.emplace_back(key, tally{}).second;
}

summary summarise(const std::vector<tree_record>& records) {
  summary s;
  for (const tree_record& r : records) slot(s.families, r.family);  // order of appearance
  std::vector<std::string> knobs;
  for (const std::string_view k : knob_order)
    for (const tree_record& r : records)
      if (std::find(r.knobs.begin(), r.knobs.end(), k) != r.knobs.end()) {
        knobs.emplace_back(k);
        break;
      }
  std::vector<std::string> others;
  for (const tree_record& r : records)
    for (const std::string& k : r.knobs)
      if (std::find(std::begin(knob_order), std::end(knob_order), k) == std::end(knob_order) &&
          std::find(others.begin(), others.end(), k) == others.end())
        others.push_back(k);
  std::sort(others.begin(), others.end());
  knobs.insert(knobs.end(), others.begin(), others.end());
  for (const std::string& k : knobs) slot(s.knobs, k);
  for (const std::string_view c : cause_keys) s.causes[std::string(c)];
  for (const tree_record& r : records) {
    s.all.add(r);
    slot(s.families, r.family).add(r);
    for (const std::string& k : r.knobs) slot(s.knobs, k).add(r);
    if (r.knife_edge) s.knife.add(r);
    if (r.built_without_perch) {
      ++s.built_without;
      s.built_without_given += r.site ? 1 : 0;
    }
    if (r.result == outcome::incorrect) {
      cause_tally& c = s.causes[r.cause];
      ++c.count;
      c.false_perches += r.has_perch ? 0 : 1;
      c.unit = r.unit;
      c.miss_sum += static_cast<double>(r.miss);
      c.miss_max = c.count == 1 ? r.miss : std::max(c.miss_max, r.miss);
      c.trees.push_back(r.name);
    }
  }
  return s;
}

void print_tally_row(const char* label, const tally& t, int label_width) {
  std::printf("%-*s %6zu %8zu %8zu %9zu %9zu %12zu %8s %7zu %6zu", label_width, label, t.trees, t.with_perch,
              t.n(outcome::correct), t.n(outcome::incorrect), t.n(outcome::missed), t.n(outcome::correct_none),
              t.with_perch == 0 ? "-" : fmt("%.1f%%", 100.0 * t.success()).c_str(), t.false_perches,
              t.knife_edge);
  if (t.n(outcome::error) > 0) std::printf("  errors %zu", t.n(outcome::error));
  std::printf("\n");
}

void print_tally_header(const char* label, int label_width) {
  std::printf("%-*s %6s %8s %8s %9s %9s %12s %8s %7s %6s\n", label_width, label, "trees", "feasible", "correct",
              "incorrect", "no result", "correct none", "success", "false", "knife");
}

void write_tally(st::json_writer& json, const tally& t) {
  json.begin_object();
  json.member("trees", t.trees).member("with_perch", t.with_perch).member("without_perch", t.without_perch);
  json.member("success_rate", t.success()).member("false_perches", t.false_perches);
  json.member("knife_edge", t.knife_edge);
  json.key("outcomes").begin_object(st::json_layout::single_line);
  for (std::size_t k = 0; k < outcome_count; ++k) json.member(outcome_keys[k], t.outcomes[k]);
  json.end_object();
  json.end_object();
}

/// `--population SPEC`: "N" (every family, N each) or "family:N[,family:N]", where N may be
/// "A-B" (members A to B).
struct population_part {
  st::tree_family family = st::tree_family::arcs;
  int first = 0;
  int last = -1;
};

std::string parse_population(std::string_view spec, std::vector<population_part>& parts) {
  const auto number = [](std::string_view text, int& out) {
    if (text.empty() || text.size() > 7) return false;
    int v = 0;
    for (const char c : text) {
      if (c < '0' || c > '9') return false;
      v = v * 10 + (c - '0');
    }
    out = v;
    return true;
  };
  const auto range = [&](std::string_view text, population_part& p) {
    const std::size_t dash = text.find('-');
    if (dash == std::string_view::npos) {
      int n = 0;
      if (!number(text, n)) return false;
      p.first = 0;
      p.last = n - 1;
      return true;
    }
    return number(text.substr(0, dash), p.first) && number(text.substr(dash + 1), p.last) && p.last >= p.first;
  };
  const std::string bad = "--population: expected N, or arcs:N,colonisation:N,sympodial:N (N a count or A-B), not '" +
                          std::string(spec) + "'";
  if (spec.find(':') == std::string_view::npos) {
    population_part p;
    if (!range(spec, p)) return bad;
    parts.push_back(p);
    p.family = st::tree_family::colonisation;
    parts.push_back(p);
    p.family = st::tree_family::sympodial;
    parts.push_back(p);
    return {};
  }
  while (!spec.empty()) {
    const std::size_t comma = spec.find(',');
    const std::string_view item = spec.substr(0, comma);
    spec = comma == std::string_view::npos ? std::string_view() : spec.substr(comma + 1);
    const std::size_t colon = item.find(':');
    if (colon == std::string_view::npos) return bad;
    population_part p;
    const std::string_view name = item.substr(0, colon);
    if (name == "arcs")
      p.family = st::tree_family::arcs;
    else if (name == "colonisation")
      p.family = st::tree_family::colonisation;
    else if (name == "sympodial")
      p.family = st::tree_family::sympodial;
    else
      return "--population: unknown family '" + std::string(name) + "' (arcs, colonisation or sympodial)";
    if (!range(item.substr(colon + 1), p)) return bad;
    parts.push_back(p);
  }
  return {};
}

/// The knobs of a population member's kind ("noisy+kinks").
std::vector<std::string> split_knobs(const std::string& kind) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= kind.size()) {
    const std::size_t plus = kind.find('+', at);
    const std::string part = kind.substr(at, plus == std::string::npos ? std::string::npos : plus - at);
    if (!part.empty()) out.push_back(part);
    if (plus == std::string::npos) break;
    at = plus + 1;
  }
  return out;
}

/// The family and knobs of a truth file's kind ("noisy", "colonisation-decurrent-two-trees",
/// "sympodial-mixed+soft+stubs", "shape-y").
void classify_file(tree_record& rec) {
  constexpr std::string_view colonisation = "colonisation-";
  constexpr std::string_view sympodial = "sympodial-";
  if (rec.kind.starts_with(sympodial)) {
    rec.family = "sympodial";
    rec.knobs = split_knobs(rec.kind.substr(sympodial.size()));
  } else if (rec.kind.starts_with(colonisation)) {
    rec.family = "colonisation";
    const std::string rest = rec.kind.substr(colonisation.size());
    const std::size_t dash = rest.find('-');
    rec.knobs.push_back(rest.substr(0, dash));
    if (dash != std::string::npos) rec.knobs.push_back(rest.substr(dash + 1));
  } else if (rec.kind.starts_with("shape")) {
    rec.family = "shapes";
    rec.knobs.push_back(rec.kind);
  } else {
    rec.family = "arcs";
    if (!rec.kind.empty()) rec.knobs.push_back(rec.kind);
  }
}

/// The seed of a tree's segmenter gaps (--gaps): FNV-1a of its name, the same on every host.
std::uint32_t gap_seed(const std::string& name) {
  std::uint32_t h = 2166136261u;
  for (const char c : name) h = (h ^ static_cast<std::uint8_t>(c)) * 16777619u;
  return h;
}

void print_row(const tree_record& r, int width, int kind_width) {
  std::string site = r.site ? fmt("(%.0f, %.0f)", static_cast<double>(r.x), static_cast<double>(r.y)) : "-";
  std::string what = r.detail;
  if (r.result == outcome::incorrect) {
    what = r.cause + ": " + r.detail;
    if (r.truth_known && r.has_perch)
      what += fmt("; nearest feasible centre %.1f px (tolerance %.1f)", static_cast<double>(r.nearest_px),
                  static_cast<double>(r.tolerance_px));
    else
      what += "; the tree has no feasible stretch";
  }
  const char* perch = !r.truth_known ? "?" : r.knife_edge ? "knife" : r.has_perch ? "yes" : "no";
  std::printf("%-*s  %-*s  %-5s  %-28s  %-12s  %s\n", width, r.name.c_str(), kind_width, r.kind.c_str(), perch,
              std::string(outcome_text[static_cast<std::size_t>(r.result)]).c_str(), site.c_str(), what.c_str());
}

}  // namespace

int run_eval(int argc, const char* const* argv) {
  // Sequences are scored by their own subcommand, with its own options.
  for (int i = 2; i < argc; ++i)
    if (std::string_view(argv[i]).starts_with("--sequences")) return run_track_eval(argc, argv);
  st::arg_parser args(
      "perch eval",
      "Runs detect on synthetic trees and judges the best site by the trees' truth (the physical\n"
      "rules of support::perch_truth: border, clearance, diameter, resolution, slope, bend, bending,\n"
      "supported, not a twig), with the PLI paper's four outcomes: correct location, incorrect\n"
      "location, no result though one existed, correctly no result. The trees are the NAME.png of\n"
      "DIR that have a NAME.truth.json (perch synth), or --population: trees made in memory.");
  args.add_positional("DIR", "directory of masks and truth files (or --population)", st::arg_presence::optional);
  args.add_option("population", "SPEC",
                  "the built-in population instead of DIR: N (all three families, N trees each),\n"
                  "or arcs:N,colonisation:N,sympodial:N; N may be A-B (members A to B), e.g.\n"
                  "arcs:12-12 (sympodial: the third family, see perch synth --help)");
  args.add_option("magnify", "M", "population trees M times bigger (640-1280 px wide at 1, sympodial 640-2000)", "1");
  args.add_flag("known-scale", "use the truth's mm/px (fixed scale); the default with --population");
  args.add_option("outline-bias", "PX", "move every outline out by PX pixels first (-3 to 3): a segmenter that\n"
                                        "over- (PX > 0) or under-segments (PX < 0); the truth stays", "0");
  args.add_option("radius-bias", "PX", "draw every limb with its radius PX larger first, sub-pixel too (-2 to 2):\n"
                                       "a generator that rasterises otherwise (0.5: any covered pixel counts)", "0");
  args.add_option("gaps", "N", "cut N segmenter-like gaps (1-8 px) into each tree first: every other one\n"
                                "across a limb, the others at a child's base; the truth stays", "0");
  args.add_option("rows", "WHICH", "per-tree rows: all, failures or none (default: all for DIR, failures\n"
                                   "for --population)");
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_option("json", "OUT.json", "also write the scores as JSON");
  args.add_flag("quiet", "no progress bar");
  add_pipeline_options(args, depth_option::not_offered);
  args.set_epilog(
      "A site is correct when it lies within 3 px + 3 % of the window length of a feasible window\n"
      "centre (perch_truth::nearest_site). An incorrect site is explained by the truth's verdict of\n"
      "the window centred there (the first rule it breaks, and by how much: clearance gap short of\n"
      "70 mm, slope over 35 deg, ...), or off_axis (beside a feasible window, beyond the tolerance).\n"
      "Success rate = correct locations / trees with a feasible stretch; a false perch is a perch\n"
      "on a tree with none. Knife-edge trees (the longest feasible stretch spans < 3 px of window\n"
      "centres) are counted apart too. With --population the scale is the truth's unless\n"
      "--mm-per-px or --trunk-mm is given.\n"
      "JSON: {\"platform\", \"scale\", \"trees\", \"success_rate\", \"with_perch\", \"false_perches\",\n"
      "       \"outcomes\": {...}, \"families\": {family: tally}, \"causes\": {rule: {\"count\", \"unit\",\n"
      "       \"mean_miss\", \"max_miss\", \"trees\"}}, \"knobs\": {knob: tally}, \"knife_edge\": tally,\n"
      "       \"results\": [...]}\n"
      "Exit status: 0; 2 for bad arguments or an unreadable mask or truth file (its row says\n"
      "which); 1 for an internal failure.\n"
      "Tracking on synthetic approach sequences: perch eval --sequences N (see its --help).\n"
      "Examples: perch eval --population arcs:200,colonisation:200\n"
      "          perch eval --population sympodial:200 --trunk-mm 200\n"
      "          perch synth --seed 100 --count 30 --out /tmp/trees && perch eval /tmp/trees --known-scale");
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
  const auto magnify = args.get_int("magnify", 1, 1, 8);
  if (!magnify) {
    report_error("eval", magnify.error);
    return exit_usage;
  }
  const auto outline_bias = args.get_int("outline-bias", 0, -3, 3);
  if (!outline_bias) {
    report_error("eval", outline_bias.error);
    return exit_usage;
  }
  const auto radius_bias = args.get_double("radius-bias", 0.0, -2.0, 2.0);
  if (!radius_bias) {
    report_error("eval", radius_bias.error);
    return exit_usage;
  }
  const auto gaps = args.get_int("gaps", 0, 0, 64);
  if (!gaps) {
    report_error("eval", gaps.error);
    return exit_usage;
  }
  const bool population = args.has("population");
  const auto dir_arg = args.positional("DIR");
  if (population == dir_arg.has_value()) {
    report_error("eval", population ? "give DIR or --population, not both" : "give DIR or --population");
    return exit_usage;
  }
  const std::string rows = args.get_string("rows", population ? "failures" : "all").value;
  if (rows != "all" && rows != "failures" && rows != "none") {
    report_error("eval", "--rows must be all, failures or none, not " + rows);
    return exit_usage;
  }
  const platform_limits limits = limits_of(config.platform);
  if (limits.has_min_slope) {
    report_error("eval", "the synthetic truth has no rule for a minimum slope (platform " +
                             std::string(platform_names[static_cast<std::size_t>(config.platform)]) + ")");
    return exit_usage;
  }
  const st::claw_spec spec = spec_of(config.platform, limits);
  const bool known_scale = args.flag("known-scale") ||
                           (population && !args.has("mm-per-px") && !args.has("trunk-mm"));

  // The trees: files, or population members.
  std::vector<std::filesystem::path> masks;
  std::vector<std::pair<st::tree_family, int>> members;
  if (population) {
    std::vector<population_part> parts;
    if (const std::string e = parse_population(*args.value("population"), parts); !e.empty()) {
      report_error("eval", e);
      return exit_usage;
    }
    for (const population_part& p : parts)
      for (int i = p.first; i <= p.last; ++i) members.emplace_back(p.family, i);
    if (members.empty()) {
      report_error("eval", "--population selects no tree");
      return exit_usage;
    }
  } else {
    const std::filesystem::path dir{std::string(*dir_arg)};
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) {
      report_error("eval", dir.string() + " is not a directory");
      return exit_usage;
    }
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
  }
  const std::size_t count = population ? members.size() : masks.size();
  const unsigned workers = st::worker_count(count, static_cast<unsigned>(jobs.value));
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());
  st::progress_options progress_options;
  if (args.flag("quiet") || count < 20) progress_options.display = st::progress_display::off;
  st::progress_bar progress(count, progress_options);

  const auto config_for = [&](float mm_per_px) {
    run_config c = config;
    c.timing = false;
    if (known_scale) {
      c.scale.kind = scale_kind::fixed;
      c.scale.mm_per_px = mm_per_px;
    }
    return c;
  };
  const std::vector<tree_record> records =
      st::parallel_map(count, static_cast<unsigned>(jobs.value), [&](std::size_t i, unsigned worker) {
        tree_record rec;
        if (population) {
          st::population_member m = st::population_tree(members[i].first, members[i].second, magnify.value);
          rec.family = std::string(st::to_string(m.family));
          rec.name = rec.family + "-" + std::to_string(m.index);
          rec.kind = m.kind;
          rec.knobs = split_knobs(m.kind);
          rec.built_without_perch = m.built_without_perch;
          st::bias_radii(m.tree, static_cast<float>(radius_bias.value));
          st::shift_outline(m.tree.mask, outline_bias.value);
          st::cut_gaps(m.tree, gaps.value, gap_seed(rec.name));
          evaluate(rec, m.tree, spec, config_for(m.tree.mm_per_px), *spaces[worker]);
          progress.tick();
          return rec;
        }
        rec.name = masks[i].stem().string();
        truth_file truth;
        std::filesystem::path truth_path = masks[i];
        truth_path.replace_extension(".truth.json");
        if (std::string e = read_truth(truth_path, truth); !e.empty()) {
          rec.detail = std::move(e);
          progress.tick();
          return rec;
        }
        rec.kind = truth.kind;
        classify_file(rec);
        rec.built_without_perch = truth.kind == "no-perch";
        st::synthetic_tree tree;
        loaded_mask loaded;
        if (std::string e = load_mask(masks[i], mask_reading{}, loaded); !e.empty()) {
          rec.detail = std::move(e);
          progress.tick();
          return rec;
        }
        tree.mask = std::move(loaded.pixels);
        if (tree.mask.width() != truth.width || tree.mask.height() != truth.height) {
          rec.detail = masks[i].string() + " is not the truth's size";
          progress.tick();
          return rec;
        }
        tree.limbs = std::move(truth.limbs);
        tree.mm_per_px = truth.mm_per_px;
        st::bias_radii(tree, static_cast<float>(radius_bias.value));
        st::shift_outline(tree.mask, outline_bias.value);
        st::cut_gaps(tree, gaps.value, gap_seed(rec.name));
        evaluate(rec, tree, spec, config_for(truth.mm_per_px), *spaces[worker]);
        progress.tick();
        return rec;
      });
  progress.finish();

  const summary s = summarise(records);
  const std::string platform(platform_names[static_cast<std::size_t>(config.platform)]);
  const char* scale = known_scale ? "known" : (config.scale.kind == scale_kind::fixed ? "fixed" : "trunk prior");

  std::printf("perch eval: %zu trees, platform %s, scale %s; a site is correct within %s of a feasible window centre\n\n",
              s.all.trees, platform.c_str(), scale, "3 px + 3 % of the window");
  // Per-tree rows.
  if (rows != "none") {
    std::size_t width = 4, kind_width = 4;
    for (const tree_record& r : records) {
      width = std::max(width, r.name.size());
      kind_width = std::max(kind_width, r.kind.size());
    }
    bool header = false;
    for (const tree_record& r : records) {
      if (rows == "failures" && (r.result == outcome::correct || r.result == outcome::correct_none)) continue;
      if (!header) {
        std::printf("%-*s  %-*s  %-5s  %-28s  %-12s  %s\n", static_cast<int>(width), "tree",
                    static_cast<int>(kind_width), "kind", "perch", "outcome", "site", "truth at the site");
        header = true;
      }
      print_row(r, static_cast<int>(width), static_cast<int>(kind_width));
    }
    if (header) std::printf("\n");
  }

  // Outcomes per family and overall.
  int label_width = 14;
  for (const auto& [k, t] : s.knobs) label_width = std::max(label_width, static_cast<int>(k.size()));
  print_tally_header("family", label_width);
  for (const auto& [family, t] : s.families) print_tally_row(family.c_str(), t, label_width);
  if (s.families.size() > 1) print_tally_row("all", s.all, label_width);
  std::printf("(feasible: trees with a feasible stretch; no result: though one existed; success: correct /\n"
              " feasible; false: perches on trees without a feasible stretch; knife: knife-edge trees)\n\n");

  // Causes.
  std::size_t incorrect = s.all.n(outcome::incorrect);
  if (incorrect > 0) {
    std::printf("incorrect locations by the rule the chosen point breaks (the truth's verdict there)\n");
    std::printf("%-14s %6s %6s %11s %11s  %s\n", "rule", "sites", "false", "mean miss", "worst", "trees");
    for (const std::string_view key : cause_keys) {
      const cause_tally& c = s.causes.at(std::string(key));
      if (c.count == 0) continue;
      std::string names;
      for (std::size_t k = 0; k < c.trees.size() && k < 6; ++k) names += (k ? ", " : "") + c.trees[k];
      if (c.trees.size() > 6) names += ", ...";
      std::printf("%-14s %6zu %6zu %11s %11s  %s\n", std::string(key).c_str(), c.count, c.false_perches,
                  (fmt("%.1f ", c.miss_sum / static_cast<double>(c.count)) + c.unit).c_str(),
                  (fmt("%.1f ", static_cast<double>(c.miss_max)) + c.unit).c_str(), names.c_str());
    }
    std::printf("\n");
  }

  // Knobs.
  print_tally_header("knob", label_width);
  for (const auto& [knob, t] : s.knobs) print_tally_row(knob.c_str(), t, label_width);
  std::printf("\n");

  if (s.knife.trees > 0)
    std::printf("knife-edge trees (feasible window centres span < %.0f px): %zu: correct %zu, incorrect %zu, "
                "no result %zu; success without them %.1f%%\n",
                static_cast<double>(knife_edge_px), s.knife.trees, s.knife.n(outcome::correct),
                s.knife.n(outcome::incorrect), s.knife.n(outcome::missed), 100.0 * s.all.success_without_knife_edge());
  if (s.built_without > 0)
    std::printf("trees built without a perch: %zu, given a perch: %zu\n", s.built_without, s.built_without_given);
  std::printf("success rate: %.1f%% (%zu of %zu trees with a feasible stretch); false perches: %zu of %zu trees "
              "without one; errors: %zu\n",
              100.0 * s.all.success(), s.all.n(outcome::correct), s.all.with_perch, s.all.false_perches,
              s.all.without_perch, s.all.n(outcome::error));
  std::fflush(stdout);

  if (const auto path = args.value("json")) {
    st::json_writer json(st::json_style::pretty);
    json.begin_object();
    json.member("version", version);
    json.member("input", population ? std::string(*args.value("population")) : std::string(*dir_arg));
    json.member("platform", platform).member("scale", scale);
    json.member("source", population ? "population" : "files");
    json.member("tolerance", "3 px + 3 % of the window length");
    json.member("trees", s.all.trees).member("images", s.all.trees);
    json.member("success_rate", s.all.success());
    json.member("success_rate_without_knife_edge", s.all.success_without_knife_edge());
    json.member("with_perch", s.all.with_perch).member("without_perch", s.all.without_perch);
    json.member("false_perches", s.all.false_perches);
    json.key("outcomes").begin_object();
    for (std::size_t k = 0; k < outcome_count; ++k) json.member(outcome_keys[k], s.all.outcomes[k]);
    json.end_object();
    json.key("built_without_perch").begin_object(st::json_layout::single_line);
    json.member("trees", s.built_without).member("given_a_perch", s.built_without_given).end_object();
    json.key("knife_edge");
    write_tally(json, s.knife);
    json.key("families").begin_object();
    for (const auto& [family, t] : s.families) {
      json.key(family);
      write_tally(json, t);
    }
    json.end_object();
    json.key("causes").begin_object();
    for (const std::string_view key : cause_keys) {
      const cause_tally& c = s.causes.at(std::string(key));
      json.key(key).begin_object(st::json_layout::single_line);
      json.member("count", c.count).member("false_perches", c.false_perches).member("unit", c.unit);
      json.member("mean_miss", c.count == 0 ? 0.0 : c.miss_sum / static_cast<double>(c.count));
      json.member("max_miss", c.miss_max);
      json.key("trees").begin_array(st::json_layout::single_line);
      for (const std::string& t : c.trees) json.value(t);
      json.end_array();
      json.end_object();
    }
    json.end_object();
    json.key("knobs").begin_object();
    for (const auto& [knob, t] : s.knobs) {
      json.key(knob);
      write_tally(json, t);
    }
    json.end_object();
    json.key("results").begin_array();
    for (const tree_record& r : records) {
      json.begin_object(st::json_layout::single_line);
      json.member("image", r.name).member("family", r.family).member("kind", r.kind);
      json.member("has_perch", r.has_perch).member("knife_edge", r.knife_edge);
      json.member("outcome", outcome_keys[static_cast<std::size_t>(r.result)]);
      if (r.site) {
        json.member("x", r.x).member("y", r.y);
        if (std::isfinite(r.nearest_px)) json.member("nearest_feasible_px", r.nearest_px);
      }
      if (r.result == outcome::incorrect) json.member("cause", r.cause).member("miss", r.miss).member("unit", r.unit);
      json.member("detail", r.detail);
      json.end_object();
    }
    json.end_array();
    json.end_object();
    if (const std::string e = write_text(std::string(*path), std::move(json).take()); !e.empty()) {
      report_error("eval", e);
      return exit_internal;
    }
  }
  return s.all.n(outcome::error) > 0 ? exit_usage : exit_ok;
}

}  // namespace perch::tool
