// SPDX-License-Identifier: BSL-1.0
// perch synth: synthetic tree masks with their ground truth (and a few hand-made shapes).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <numbers>
#include <random>
#include <system_error>

#include "support/colonisation_tree.hpp"
#include "support/population.hpp"
#include "truth.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

namespace st = support;

/// What the i-th tree of a run looks like (i mod 6), so any 6 consecutive trees cover all.
enum class tree_kind : std::uint8_t { clean, bushy, noisy, two_trees, no_perch, small };
constexpr std::string_view kind_names[] = {"clean", "bushy", "noisy", "two-trees", "no-perch", "small"};

/// [lo, hi) from mt19937's specified output (no implementation-defined distributions).
float uniform(std::mt19937& rng, float lo, float hi) {
  const double u = static_cast<double>(rng()) * (1.0 / 4294967296.0);
  return lo + static_cast<float>(u * static_cast<double>(hi - lo));
}

struct synthetic {
  truth_file truth;
  image<std::uint8_t> mask;
};

synthetic make_synthetic(std::uint32_t seed, tree_kind kind) {
  std::mt19937 rng(seed);
  st::tree_options o;
  o.seed = seed;
  o.width = 960;
  o.height = 720;
  o.levels = 3;
  o.branches_per_node = 3;
  o.side_limbs = 1;
  if (kind == tree_kind::bushy) {
    o.width = 1024;
    o.height = 768;
    o.levels = 4;
    o.side_limbs = 2;
  } else if (kind == tree_kind::small) {
    o.width = 640;
    o.height = 480;
  } else if (kind == tree_kind::no_perch) {
    o.levels = 0;  // a bare trunk: 180 mm and near vertical, too thick and too steep
    o.side_limbs = 0;
  }
  const int full_width = o.width;
  if (kind == tree_kind::two_trees) o.width = full_width / 2;
  // The trunk spans 4–6 % of the full image width.
  o.trunk_diameter_mm = 180.0f;
  o.mm_per_px = 180.0f / (uniform(rng, 0.04f, 0.06f) * static_cast<float>(full_width));
  o.min_diameter_mm = uniform(rng, 14.0f, 24.0f);
  if (kind == tree_kind::noisy) {
    o.noise = uniform(rng, 1.5f, 3.0f);
    o.twigs = 16 + static_cast<int>(rng() % 12u);
    o.holes = 2;
  }

  truth_file truth;
  truth.kind = std::string(kind_names[static_cast<int>(kind)]);
  truth.seed = seed;
  truth.width = full_width;
  truth.height = o.height;
  truth.mm_per_px = o.mm_per_px;
  st::synthetic_tree tree = st::make_tree(o);
  truth.limbs = std::move(tree.limbs);
  if (kind == tree_kind::two_trees) {
    st::tree_options o2 = o;
    o2.seed = seed ^ 0x5bd1e995u;
    st::synthetic_tree second = st::make_tree(o2);
    image<std::uint8_t> mask(full_width, o.height, 0);
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        mask(x, y) = tree.mask(x, y);
        mask(x + o.width, y) = second.mask(x, y);
      }
    const auto first_count = static_cast<int>(truth.limbs.size());
    for (st::limb_truth limb : second.limbs) {
      for (Eigen::Vector2f& p : limb.centreline) p.x() += static_cast<float>(o.width);
      if (limb.parent >= 0) limb.parent += first_count;
      truth.limbs.push_back(std::move(limb));
    }
    tree.mask = std::move(mask);
  }
  return {std::move(truth), std::move(tree.mask)};
}

/// Crown forms of the colonisation family, by name (`--form`).
constexpr st::crown_form forms[] = {st::crown_form::decurrent, st::crown_form::excurrent,
                                    st::crown_form::columnar, st::crown_form::irregular};
constexpr std::string_view form_names[] = {"decurrent", "excurrent", "columnar", "irregular"};
/// What the i-th colonisation tree of a run carries (i mod 3).
constexpr std::string_view colonisation_variants[] = {"clean", "noisy", "two-trees"};

/// A space-colonisation tree (support/colonisation_tree.hpp): 960x720, a 150–300 mm trunk
/// spanning 3.5–6 % of the width (scale clamped to 1.5–8 mm/px); `variant` 1 adds outline
/// noise, pinholes, twigs and fragments, 2 a second tree and limbs leaving the frame.
synthetic make_colonisation_synthetic(std::uint32_t seed, std::size_t form, std::size_t variant) {
  std::mt19937 rng(seed ^ 0x2545f491u);
  st::colonisation_options o;
  o.seed = seed;
  o.width = 960;
  o.height = 720;
  o.form = forms[form];
  o.trunk_diameter_mm = uniform(rng, 150.0f, 300.0f);
  o.mm_per_px = std::clamp(
      o.trunk_diameter_mm / (uniform(rng, 0.035f, 0.06f) * static_cast<float>(o.width)), 1.5f, 8.0f);
  if (variant == 1) {
    o.noise = uniform(rng, 1.0f, 2.5f);
    o.holes = 3;
    o.twigs = 12 + static_cast<int>(rng() % 12u);
    o.fragments = 4 + static_cast<int>(rng() % 6u);
  } else if (variant == 2) {
    o.second_tree = uniform(rng, 0.45f, 0.75f);
    o.overflow = uniform(rng, 0.15f, 0.4f);
  }
  st::synthetic_tree tree = st::make_colonisation_tree(o);
  truth_file truth;
  truth.kind = "colonisation-" + std::string(form_names[form]) + "-" +
               std::string(colonisation_variants[variant]);
  truth.seed = seed;
  truth.width = o.width;
  truth.height = o.height;
  truth.mm_per_px = o.mm_per_px;
  truth.limbs = std::move(tree.limbs);
  return {std::move(truth), std::move(tree.mask)};
}

/// Member `index` of the sympodial population family (support/population.hpp, the same tree
/// `perch eval --population sympodial:N` judges as sympodial-INDEX), with its truth.
synthetic make_sympodial_synthetic(int index) {
  st::population_member m = st::population_tree(st::tree_family::sympodial, index);
  truth_file truth;
  truth.kind = "sympodial-" + m.kind;
  truth.seed = static_cast<std::uint32_t>(index);
  truth.width = m.tree.mask.width();
  truth.height = m.tree.mask.height();
  truth.mm_per_px = m.tree.mm_per_px;
  truth.limbs = std::move(m.tree.limbs);
  return {std::move(truth), std::move(m.tree.mask)};
}

/// Re-draws the mask of `truth` (every limb as tapered capsules), as make_tree does.
image<std::uint8_t> draw_truth(const truth_file& truth) {
  image<std::uint8_t> mask(truth.width, truth.height, 0);
  for (const st::limb_truth& limb : truth.limbs) {
    std::vector<float> radii(limb.diameter_px.size());
    for (std::size_t i = 0; i < radii.size(); ++i) radii[i] = 0.5f * limb.diameter_px[i];
    st::draw_polyline(mask.view(), limb.centreline, radii);
  }
  return mask;
}

/// A straight limb from `a` to `b`, diameters `da` → `db` px.
st::limb_truth straight(Eigen::Vector2f a, Eigen::Vector2f b, float da, float db, int parent, int level) {
  st::limb_truth limb;
  limb.kind = parent < 0 ? st::limb_kind::trunk : st::limb_kind::limb;
  limb.parent = parent;
  limb.level = level;
  limb.centreline = {a, b};
  limb.diameter_px = {da, db};
  limb.arc_px = {0.0f, (b - a).norm()};
  limb.base_heading_rad = std::atan2(b.x() - a.x(), a.y() - b.y());
  limb.curvature_per_px = 0;
  return limb;
}

/// The hand-made shapes (3 mm/px, so the 60 px trunk is the 180 mm of the trunk prior):
/// one near-level limb; a Y with one steep and one feasible arm; steep limbs only (no perch).
std::vector<std::pair<std::string, truth_file>> make_shapes() {
  std::vector<std::pair<std::string, truth_file>> out;
  auto base = [](std::string kind) {
    truth_file t;
    t.kind = std::move(kind);
    t.width = 800;
    t.height = 600;
    t.mm_per_px = 3.0f;
    return t;
  };
  {
    truth_file t = base("shape-limb");
    t.limbs.push_back(straight({300, 629}, {300, 140}, 60, 44, -1, 0));
    t.limbs.push_back(straight({300, 330}, {740, 306}, 24, 16, 0, 1));
    out.emplace_back("shape-limb", std::move(t));
  }
  {
    truth_file t = base("shape-y");
    t.limbs.push_back(straight({400, 629}, {400, 380}, 60, 50, -1, 0));
    t.limbs.push_back(straight({400, 380}, {180, 110}, 36, 22, 0, 1));
    t.limbs.push_back(straight({400, 380}, {740, 240}, 34, 22, 0, 1));
    out.emplace_back("shape-y", std::move(t));
  }
  {
    truth_file t = base("shape-steep");
    t.limbs.push_back(straight({420, 629}, {430, 60}, 60, 40, -1, 0));
    t.limbs.push_back(straight({425, 420}, {230, 120}, 26, 16, 0, 1));
    t.limbs.push_back(straight({428, 300}, {610, 40}, 24, 14, 0, 1));
    out.emplace_back("shape-steep", std::move(t));
  }
  return out;
}

std::string write_pair(const std::filesystem::path& dir, const std::string& name, const truth_file& truth,
                       const image<std::uint8_t>& mask) {
  image<std::uint8_t> png_mask(mask.width(), mask.height(), 0);
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x) png_mask(x, y) = mask(x, y) != 0 ? 255 : 0;
  const png::write_options options{.filter = png::filter_choice::minimum_sum, .compression_level = 9};
  const png::png_status written =
      png::write_png(dir / (name + ".png"), image_view<const std::uint8_t>(png_mask.view()), options);
  if (!written) return written.error().message;
  return write_text(dir / (name + ".truth.json"), truth_json(truth));
}

}  // namespace

int run_synth(int argc, const char* const* argv) {
  // Approach sequences have their own options (track.cpp).
  for (int i = 2; i < argc; ++i)
    if (std::string_view(argv[i]).starts_with("--sequence")) return run_synth_sequence(argc, argv);
  support::arg_parser args("perch synth",
                           "Writes synthetic tree masks (OUT/synth-SEED.png, 255 = tree) with their ground\n"
                           "truth (OUT/synth-SEED.truth.json) for perch eval. Tree i of the run has seed\n"
                           "SEED + i and kind i mod 6: clean, bushy, noisy (outline noise, twigs, holes),\n"
                           "two-trees, no-perch (a bare trunk), small (640x480).\n"
                           "--family colonisation grows trees by space colonisation instead (crown\n"
                           "form --form, or all four in turn; tree i is clean, noisy (outline noise,\n"
                           "pinholes, twigs, detached fragments) or two-trees (a second tree, limbs\n"
                           "leaving the frame) by i mod 3).\n"
                           "--family sympodial writes members SEED … SEED+N-1 of the population's third\n"
                           "family (perch eval --population sympodial:N calls them sympodial-I): 3-D turtle\n"
                           "forks and leaders, pipe-model diameters, stubs, sampled coverage thresholded\n"
                           "per tree, foliage, rough or biased outlines, occluding leaves, broken thin\n"
                           "limbs; 640x480 to 2000x1500; the kind lists the member's knobs.");
  args.add_option("seed", "S", "seed of the first tree", "1");
  args.add_option("count", "N", "number of trees", "6");
  args.add_option("out", "DIR", "output directory (created if missing)");
  args.add_option("family", "F", "rules (make_tree), colonisation (space colonisation) or sympodial\n"
                                 "(the population's third family)", "rules");
  args.add_option("form", "FORM",
                  "colonisation crown: decurrent, excurrent, columnar, irregular or mixed", "mixed");
  args.add_flag("shapes", "also write the hand-made shapes shape-limb, shape-y, shape-steep");
  args.set_epilog("Approach sequences for perch track: perch synth --sequence I (see its --help).\n"
                  "Example (the sample data): perch synth --seed 1 --count 6 --shapes --out examples/data");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "synth", exit)) return exit;
  const auto seed = args.get_integer<std::uint32_t>("seed", 1u, 0u, 0xFFFFFFF0u);
  const auto count = args.get_int("count", 6, 0, 100000);
  for (const std::string* e : {&seed.error, &count.error})
    if (!e->empty()) {
      report_error("synth", *e);
      return exit_usage;
    }
  if (!args.has("out")) {
    report_error("synth", "missing option --out DIR");
    return exit_usage;
  }
  const std::string family = args.get_string("family", "rules").value;
  const std::string form_name = args.get_string("form", "mixed").value;
  if (family != "rules" && family != "colonisation" && family != "sympodial") {
    report_error("synth", "--family must be rules, colonisation or sympodial, not " + family);
    return exit_usage;
  }
  std::size_t form = std::size(forms);  // mixed
  for (std::size_t f = 0; f < std::size(forms); ++f)
    if (form_name == form_names[f]) form = f;
  if (form == std::size(forms) && form_name != "mixed") {
    report_error("synth", "unknown --form " + form_name);
    return exit_usage;
  }
  const std::filesystem::path dir(std::string(*args.value("out")));
  if (const std::string e = make_output_dir(dir, "synth-1.png"); !e.empty()) {
    report_error("synth", e);
    return exit_usage;
  }
  for (int i = 0; i < count.value; ++i) {
    const std::uint32_t s = seed.value + static_cast<std::uint32_t>(i);
    const auto index = static_cast<std::size_t>(i);
    const synthetic made =
        family == "sympodial" ? make_sympodial_synthetic(static_cast<int>(s))
        : family == "colonisation"
            ? make_colonisation_synthetic(s, form < std::size(forms) ? form : index % std::size(forms),
                                          index % std::size(colonisation_variants))
            : make_synthetic(s, static_cast<tree_kind>(i % 6));
    const truth_file& truth = made.truth;
    const std::string name = "synth-" + std::to_string(s);
    if (const std::string e = write_pair(dir, name, truth, made.mask); !e.empty()) {
      report_error("synth", e);
      return exit_internal;
    }
    std::printf("%s  %s\n", name.c_str(), truth.kind.c_str());
  }
  if (args.flag("shapes")) {
    for (const auto& [name, truth] : make_shapes()) {
      if (const std::string e = write_pair(dir, name, truth, draw_truth(truth)); !e.empty()) {
        report_error("synth", e);
        return exit_internal;
      }
      std::printf("%s  %s\n", name.c_str(), truth.kind.c_str());
    }
  }
  return exit_ok;
}

}  // namespace perch::tool
