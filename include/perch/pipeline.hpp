// SPDX-License-Identifier: BSL-1.0
/// \file
/// The stages of `find_perch` (perch/pli.hpp) and what they share: its options, its result, and
/// the glue between the graph and the analysis (windows on limbs, their surroundings), so that
/// `analysis/` never includes `graph/` and the facade reads as the pipeline.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "perch/analysis.hpp"
#include "perch/bridge.hpp"
#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/graph.hpp"
#include "perch/label.hpp"
#include "perch/limits.hpp"
#include "perch/platform.hpp"
#include "perch/policy.hpp"
#include "perch/skeleton.hpp"

namespace perch {

/// A monotonic clock in nanoseconds, supplied by the caller (perch itself reads no clock, so
/// firmware without one can run it). E.g. a captureless lambda over `std::chrono::steady_clock`.
using clock_ns_fn = std::int64_t (*)() noexcept;

/// Milliseconds spent in each stage of `find_perch` (all 0 when no clock was given).
struct stage_timings {
  float prepare_ms = 0;   ///< bounding box, binarise, downscale, pinholes
  float distance_ms = 0;  ///< Euclidean distance transform
  float skeleton_ms = 0;  ///< skeletonisation
  float graph_ms = 0;     ///< pixel kinds, tracing, adjacency list
  float prune_ms = 0;     ///< scale, weighting (eq. 1) and pruning
  /// Gaps found and bridged; the stages from the distance transform to pruning, run again on
  /// the bridged mask, add their time to their own.
  float bridge_ms = 0;
  float windows_ms = 0;   ///< windows and their measures
  float ranking_ms = 0;   ///< constraints, scorer (eq. 3), ranking
  float total_ms = 0;
};

/// Options of `find_perch`. The platform supplies the drone's geometry and its policies; these
/// are the method's own knobs (defaults from the paper and DESIGN.md).
struct perch_options {
  float downscale = 1.0f;  ///< analyse the mask reduced by this factor ∈ (0, 1] (area-based)
  attitude camera{};       ///< camera roll, so slopes are measured against the true horizontal
  float stride_mm = 20.0f;             ///< distance between window starts
  float curvature_stencil_mm = 40.0f;  ///< see `window_options::curvature_stencil_mm`
  /// Eq. 1 weights and pruning thresholds. Its diameter range is the platform's grasp range
  /// (`platform_geometry::grasp_min_mm`, `grasp_max_mm`): left at its defaults here, since a
  /// platform states it once; `validate` refuses another.
  prune_options pruning{};
  limb_options limbs{};                ///< when windows run on through a junction
  obstacle_options obstacles{};        ///< which other limbs a window's clearance counts
  rank_options ranking{};              ///< top-k and the distance between ranked sites
  perch_limits limits{};  ///< what a mask may need at most (windows: 2^18 by default)
  /// Holes of the mask of at most this many input pixels (× downscale² in the analysed mask)
  /// are filled before the distance transform (`fill_small_holes`): a segmenter's pinholes
  /// and rasterisation pockets, which the skeleton would circle with a loop that cuts the
  /// branch in pieces. 0 keeps every hole. A site is never one of the filled pixels: a window
  /// whose middle falls on one moves it to the nearest tree pixel of its centreline, and a
  /// window with none (it runs over filled speckle only) is dropped.
  std::int32_t max_hole_px = 4;
  /// Small gaps a segmenter left in a limb, bridged in perch's copy of the mask before the
  /// analysis (`find_gap_bridges`; `perch_result::bridges` lists them). Their lengths are in
  /// input pixels.
  bridge_options bridging{};
  clock_ns_fn clock = nullptr;         ///< stage timings when given

  [[nodiscard]] status validate() const noexcept {
    if (!(downscale > 0.0f && downscale <= 1.0f))
      return fail(errc::invalid_parameter, "perch_options.downscale");
    for (const float v : {stride_mm, curvature_stencil_mm})
      if (!(std::isfinite(v) && v > 0)) return fail(errc::invalid_parameter, "perch_options");
    if (ranking.top_k == 0 || !(ranking.site_separation_mm >= 0))
      return fail(errc::invalid_parameter, "perch_options.ranking");
    PERCH_TRY(limits.validate());
    if (max_hole_px < 0) return fail(errc::invalid_parameter, "perch_options.max_hole_px");
    PERCH_TRY(bridging.validate());
    if (auto pruning_ok = pruning.validate(); !pruning_ok) return pruning_ok;
    if (pruning.diameter_min_mm != prune_options{}.diameter_min_mm ||
        pruning.diameter_max_mm != prune_options{}.diameter_max_mm)
      return fail(errc::invalid_parameter,
                  "perch_options.pruning.diameter_*: find_perch prunes with the platform's grasp range");
    if (auto limbs_ok = limbs.validate(); !limbs_ok) return limbs_ok;
    if (auto obstacles_ok = obstacles.validate(); !obstacles_ok) return obstacles_ok;
    return camera.validate();
  }
};

/// Why `find_perch` found what it found.
enum class perch_outcome : std::uint8_t {
  found,     ///< at least one site passed every constraint
  no_perch,  ///< the tree was analysed; no window passed every constraint (see diagnostics)
  no_tree,   ///< the mask has no tree pixel
};

[[nodiscard]] constexpr std::string_view to_string(perch_outcome o) noexcept {
  switch (o) {
    case perch_outcome::found:
      return "ok";
    case perch_outcome::no_perch:
      return "no_perch";
    case perch_outcome::no_tree:
      return "no_tree";
  }
  return "unknown";
}

/// A gap `find_perch` bridged (`perch_options::bridging`), in input pixels.
struct perch_bridge {
  pixel from{};  ///< the end whose axis the bridge carries on, where its piece of mask stops
  pixel to{};    ///< the other end (end to end), or where the end's axis meets the body
  float gap_px = 0;  ///< background between the two outlines along the bridge
  bridge_kind kind = bridge_kind::end_to_end;
};

/// Everything `find_perch` found. Spans and the graph live in the workspace: valid until the
/// workspace's next `reset()` (the next `find_perch` call on it).
///
/// Coordinates: `sites[i].window.centre` and `near_misses[i].window.centre` are in input-image
/// pixels; `window.first/last/middle` index the limb's polyline (`limbs[window.limb].points`;
/// `window.branch` is the graph edge under `middle`). The graph, limbs, skeleton and
/// distance map are in the analysed frame: local coordinates + `mask.offset`, and
/// `mask.to_input()` maps the analysed frame to input pixels (identity without downscale).
/// Lengths in px inside `window_measures` are analysed-frame pixels; everything in mm is metric.
struct perch_result {
  perch_outcome outcome = perch_outcome::no_tree;
  std::span<const perch_site> sites{};  ///< best first
  std::span<const rejection_count> rejections{};  ///< per constraint, in the platform's order
  std::span<const near_miss> near_misses{};       ///< per constraint
  std::uint32_t windows = 0;                      ///< windows measured
  std::uint32_t viable = 0;                       ///< windows that passed every constraint
  /// The most windows held at once (`windows` and those dropped after measuring, see
  /// `perch_options::max_hole_px`): what `perch_limits::windows` must allow.
  std::uint32_t windows_held = 0;
  float mm_per_px = 0;  ///< global scale, per input-image pixel
  std::string_view scale{};     ///< the scale policy's name
  float scale_uncertainty = 0;  ///< its relative uncertainty: every rule in mm held at both ends
  std::string_view platform{};  ///< the platform's name
  int width = 0, height = 0;    ///< input image size
  prepared_mask mask{};  ///< the analysed mask: cropped, reduced, pinholes filled, gaps bridged
  image_view<const std::uint32_t> dist2{};    ///< squared distances on the tree pixels of
                                              ///< `mask.pixels` (others not written), local
  image_view<const std::uint8_t> skeleton{};  ///< skeleton (1/0), local coordinates
  skeleton_graph graph{};                     ///< after pruning, local coordinates
  std::span<const skeleton_limb> limbs{};     ///< the graph's edges chained into limbs
  hole_fill_report holes{};                   ///< pinholes filled (`max_hole_px`)
  /// Gaps bridged before the analysis, shortest first (`perch_options::bridging`): each drawn
  /// into `mask`; no window runs across one.
  std::span<const perch_bridge> bridges{};
  prune_report pruning{};                     ///< what pruning removed
  stage_timings timing{};
  /// This call took new memory from the workspace's upstream (a first call, or a mask that
  /// needs more than any before): its time includes the kernel faulting those pages in. A
  /// warm call (false) allocates nothing.
  bool cold = false;
};

namespace detail {

/// Times stages with the caller's clock (a no-op without one).
class stage_clock {
 public:
  explicit stage_clock(clock_ns_fn clock) noexcept
      : clock_(clock), start_(clock ? clock() : 0), last_(start_) {}
  /// Milliseconds since the previous lap.
  float lap() noexcept {
    if (clock_ == nullptr) return 0;
    const std::int64_t now = clock_();
    const float ms = static_cast<float>(now - last_) * 1e-6f;
    last_ = now;
    return ms;
  }
  [[nodiscard]] float total() const noexcept {
    return clock_ ? static_cast<float>(last_ - start_) * 1e-6f : 0;
  }

 private:
  clock_ns_fn clock_;
  std::int64_t start_, last_;
};

/// Every limb's `limb_neighbourhood` (its points, radii, the owners it leaves out and an empty
/// gap cache), for `limb_clearance`.
[[nodiscard]] inline result<std::span<const limb_neighbourhood>> limb_neighbourhoods(
    std::span<const skeleton_limb> limbs, std::span<const owner_set> own, workspace& ws) noexcept {
  std::size_t total = 0;
  for (const skeleton_limb& l : limbs) total += l.points.size();
  auto out = ws.allocate<limb_neighbourhood>(limbs.size());
  auto gaps = ws.allocate<float>(total);
  auto reach = ws.allocate_zeroed<float>(total);
  PERCH_TRY(all_ok(out, gaps, reach));
  std::size_t used = 0;
  for (std::size_t l = 0; l < limbs.size(); ++l) {
    const std::size_t n = limbs[l].points.size();
    (*out)[l] = {limbs[l].points, limbs[l].radius_px, own[l], gaps->subspan(used, n),
                 reach->subspan(used, n)};
    used += n;
  }
  return std::span<const limb_neighbourhood>(*out);
}

/// A window whose middle point lies on a pinhole `find_perch` filled (background in the input
/// `mask`) moves its middle to the nearest point of its centreline that is tree in the input,
/// so that a site's pixel is always one of the mask's; false when there is none (the window
/// runs over filled pixels only). `points` are the limb's (local coordinates, `offset` to the
/// input's; full resolution only).
template <BinaryView Mask>
[[nodiscard]] bool middle_on_tree(const Mask& mask, std::span<const pixel> points, pixel offset,
                                  window_measures& w) noexcept {
  auto tree = [&](std::uint32_t i) {
    return static_cast<bool>(mask(points[i].x + offset.x, points[i].y + offset.y));
  };
  if (tree(w.middle)) return true;
  for (std::uint32_t d = 1; w.middle >= w.first + d || w.middle + d <= w.last; ++d) {
    std::uint32_t to = 0;
    if (w.middle >= w.first + d && tree(w.middle - d))
      to = w.middle - d;
    else if (w.middle + d <= w.last && tree(w.middle + d))
      to = w.middle + d;
    else
      continue;
    w.middle = to;
    w.centre = {points[to].x + offset.x, points[to].y + offset.y};
    return true;
  }
  return false;
}


/// `before[i]`: how many of `points[0, i)` lie on one of `bridges` (`before` holds at least
/// `points.size() + 1`).
inline void count_bridged_points(std::span<const pixel> points, std::span<const gap_bridge> bridges,
                                 std::span<std::uint32_t> before) noexcept {
  before[0] = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    before[i + 1] = before[i] + (on_gap_bridge(to_point(points[i]), bridges) ? 1u : 0u);
}

/// What the stages of `find_perch` hand on to one another (views and spans into the workspace).
template <class Scale>
struct pipeline_state {
  image_view<std::uint8_t> local{};   ///< the analysed box (`perch_result::mask.pixels`)
  row_runs runs{};                    ///< its runs, when listed
  const row_runs* listed = nullptr;   ///< `runs` when the skeletoniser reads them (and the graph)
  std::optional<Scale> scaled{};      ///< the scale policy for the analysed image
  scale_context context{};
  image_view<std::uint32_t> dist{};
  image_view<std::uint8_t> skeleton{};
  float mm_per_px = 0;                ///< global, analysed pixels
  std::span<float> node_distance{};   ///< per node, to its trunk
  edge_continuations next{};          ///< limb continuations
  std::span<branch_stretch> stretches{};  ///< per limb, outside its end junctions
  std::span<std::uint8_t> grounded{};     ///< per component
  limb_obstacles obstacles{};
  limb_clearance clearance{};         ///< reads `obstacles`: the state must not move
  bounded_vector<window_measures> windows{};
  bounded_vector<gap_bridge> bridges{};  ///< in local coordinates, room taken by `prepare_stage`
};

/// The input pixel of a point of the analysed frame (clamped: a reduced pixel of an odd-sized
/// input's last row or column is centred half a pixel past its edge).
[[nodiscard]] inline pixel input_pixel(const perch_result& out, point2f analysed) noexcept {
  const point2f c = out.mask.to_input(analysed);
  return pixel{std::clamp<std::int32_t>(static_cast<std::int32_t>(std::lround(c.x())), 0, out.width - 1),
               std::clamp<std::int32_t>(static_cast<std::int32_t>(std::lround(c.y())), 0, out.height - 1)};
}

/// Fills the analysed mask's holes of at most `options.max_hole_px` input pixels (found from
/// its runs, which are joined across them: a speckled mask with too many runs to list keeps
/// its holes), then holds its tree pixels to `options.limits` (the skeletoniser's memory grows
/// with them).
template <class Scale>
[[nodiscard]] status fill_pinholes(const perch_options& options, workspace& ws, perch_result& out,
                                   pipeline_state<Scale>& s) noexcept {
  const double factor2 =
      static_cast<double>(options.downscale) * static_cast<double>(options.downscale);
  const auto hole_px =
      static_cast<std::int64_t>(static_cast<double>(options.max_hole_px) * factor2);
  if (hole_px > 0 && s.runs.describes(s.local)) {
    auto filled = fill_small_holes(s.local, s.runs, hole_px, ws);
    PERCH_TRY(all_ok(filled));
    out.holes.filled += filled->filled;
    out.holes.filled_pixels += filled->filled_pixels;
    out.mask.tree_pixels += filled->filled_pixels;
  }
  const auto tree = static_cast<std::size_t>(out.mask.tree_pixels);
  if (options.limits.tree_pixels != 0 && tree > options.limits.tree_pixels)
    return fail(errc::capacity_exceeded, "perch_options.limits.tree_pixels", tree);
  return {};
}

/// Stage 1: the tree's bounding box, binarised, reduced, with a background border; its runs,
/// found once for the distance transform, the skeleton and its graph (listed while the box is
/// copied, or by a scan of the reduced copy; a speckled mask with more runs than `max_runs` is
/// scanned by each instead); the scale policy for it; and pinholes filled (their runs joined),
/// so that no skeleton loop splits a branch around one; and room for the bridges of gaps
/// (`options.bridging.max_bridges`), which outlives a rerun of the stages after it. A box or
/// tree beyond `options.limits` is refused before it takes memory.
template <BinaryView Mask, ScalePolicy Scale>
[[nodiscard]] status prepare_stage(const Mask& mask, const Scale& scale, const perch_options& options,
                                   workspace& ws, perch_result& out,
                                   pipeline_state<Scale>& s) noexcept {
  prepare_options preparing{.runs = runs_listing::list, .max_box_pixels = options.limits.box_pixels};
  auto prepared = prepare_mask(mask, ws, options.downscale, preparing);
  if (!prepared && prepared.error().code == errc::capacity_exceeded)  // the box's limit
    return fail(errc::capacity_exceeded, "perch_options.limits.box_pixels", prepared.error().needed);
  PERCH_TRY(all_ok(prepared));
  out.mask = *prepared;
  s.local = prepared->pixels;
  // Checked against the input before rescaling reads it (a depth view of another size, or a
  // null one, must not be resampled).
  PERCH_TRY(scale.validate(scale_context{mask.width(), mask.height(), 0, {}, {}, {}}));
  auto scaled = scale.rescaled(options.downscale, ws);
  PERCH_TRY(all_ok(scaled));
  s.scaled.emplace(*scaled);
  s.context = {prepared->analysed_width, prepared->analysed_height, 0, {}, prepared->offset, {}};
  PERCH_TRY(s.scaled->validate(s.context));
  s.runs = prepared->runs;
  PERCH_TRY(fill_pinholes(options, ws, out, s));
  auto bridges = bounded_vector<gap_bridge>::make(
      ws, options.bridging.enabled ? options.bridging.max_bridges : 0);
  PERCH_TRY(all_ok(bridges));
  s.bridges = *bridges;
  return {};
}

/// Stage 2: the squared distance of every tree pixel to the background.
template <class Scale>
[[nodiscard]] status distance_stage(workspace& ws, perch_result& out,
                                    pipeline_state<Scale>& s) noexcept {
  const int w = s.local.width(), h = s.local.height();
  auto dist2 = ws.allocate<std::uint32_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  PERCH_TRY(all_ok(dist2));
  s.dist = image_view<std::uint32_t>(dist2->data(), w, h);
  PERCH_TRY(distance_transform_sq_foreground(image_view<const std::uint8_t>(s.local), s.dist, ws, s.runs));
  out.dist2 = s.dist;
  return {};
}

/// Stage 3: the skeleton. A `RowRunSkeletoniser` takes the runs, and its skeleton lies inside
/// the mask, so the graph looks for skeleton pixels only inside the runs too.
template <Skeletoniser Skel, class Scale>
[[nodiscard]] status skeleton_stage(const Skel& skeletoniser, workspace& ws, perch_result& out,
                                    pipeline_state<Scale>& s) noexcept {
  const int w = s.local.width(), h = s.local.height();
  auto pixels = ws.allocate<std::uint8_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  PERCH_TRY(all_ok(pixels));  // the skeletoniser writes every pixel
  s.skeleton = image_view<std::uint8_t>(pixels->data(), w, h);
  const image_view<const std::uint8_t> tree_mask(s.local);
  const image_view<const std::uint32_t> dist(s.dist);
  if constexpr (RowRunSkeletoniser<Skel>) {
    s.listed = &s.runs;  // empty runs are ignored
    PERCH_TRY(skeletoniser(tree_mask, dist, s.skeleton, ws, s.runs));
  } else {
    s.listed = nullptr;
    PERCH_TRY(skeletoniser(tree_mask, dist, s.skeleton, ws));
  }
  out.skeleton = s.skeleton;
  return {};
}

/// Stage 4: the skeleton graph, once its pixels are known to be within the stated limit (its
/// memory grows with them), built within the stated nodes and branches.
template <class Scale>
[[nodiscard]] status graph_stage(const perch_options& options, workspace& ws, perch_result& out,
                                 pipeline_state<Scale>& s) noexcept {
  if (options.limits.skeleton_pixels != 0) {
    const std::size_t pixels = count_set_pixels(s.skeleton, runs_of(s.listed, s.skeleton));
    if (pixels > options.limits.skeleton_pixels)
      return fail(errc::capacity_exceeded, "perch_options.limits.skeleton_pixels", pixels);
  }
  const image_view<const std::uint8_t> skeleton(s.skeleton);
  const image_view<const std::uint32_t> dist(s.dist);
  // The graph's storage is taken for the stated nodes and branches; the build stops at them.
  const graph_options caps{.max_nodes = options.limits.graph_nodes,
                           .max_branches = options.limits.graph_branches};
  auto built = s.listed != nullptr ? build_skeleton_graph(skeleton, dist, ws, caps, *s.listed)
                                   : build_skeleton_graph(skeleton, dist, ws, caps);
  if (!built && built.error().code == errc::capacity_exceeded)  // only a stated cap is reachable
    return fail(errc::capacity_exceeded,
                built.error().detail == skeleton_graph_branches_detail
                    ? "perch_options.limits.graph_branches"
                    : "perch_options.limits.graph_nodes",
                built.error().needed);
  PERCH_TRY(all_ok(built));
  out.graph = std::move(*built);
  return {};
}

/// Stage 5: the scale (from the skeleton's pixels and widest radius, read off the graph), then
/// weighting (eq. 1) and pruning. Leaves running out of the analysed image are not weak.
template <Platform P, class Scale>
[[nodiscard]] status scale_and_prune_stage(const P& platform, const perch_options& options,
                                           workspace& ws, perch_result& out,
                                           pipeline_state<Scale>& s) noexcept {
  skeleton_graph& graph = out.graph;
  auto sample = ws.allocate<pixel>(graph.skeleton_pixels());
  auto scratch = ws.allocate<float>(graph.skeleton_pixels());
  PERCH_TRY(all_ok(sample, scratch));
  std::size_t k = 0;
  float max_radius = 0;
  graph.for_each_branch([&](const skeleton_branch& b) {
    for (std::size_t i = 0; i < b.points.size() && k < sample->size(); ++i) {
      (*sample)[k++] = b.points[i];
      max_radius = std::max(max_radius, b.radius_px[i]);
    }
  });
  graph.for_each_node([&](const skeleton_node& node) {
    max_radius = std::max(max_radius, node.radius_px);
    if (node.pixel_count > 0 && k < sample->size()) (*sample)[k++] = node.position;
  });
  s.context.max_distance_px = max_radius;
  s.context.sample = sample->first(k);
  s.context.scratch = *scratch;
  auto global = s.scaled->global_mm_per_px(s.context);
  PERCH_TRY(all_ok(global));
  s.mm_per_px = *global;
  if (!(std::isfinite(s.mm_per_px) && s.mm_per_px > 0))
    return fail(errc::invalid_parameter, "scale policy gave a non-positive mm/px");
  out.mm_per_px = s.mm_per_px * options.downscale;
  prune_options pruning = options.pruning;
  pruning.diameter_min_mm = platform.geometry.grasp_min_mm;
  pruning.diameter_max_mm = platform.geometry.grasp_max_mm;
  const prepared_mask& m = out.mask;
  const pixel_box frame{-m.offset.x, -m.offset.y, m.analysed_width - 1 - m.offset.x,
                        m.analysed_height - 1 - m.offset.y};
  auto report = prune_skeleton_graph(graph, s.mm_per_px, ws, pruning, frame);
  PERCH_TRY(all_ok(report));
  out.pruning = *report;
  return {};
}

/// Stage 6: small gaps a segmenter left (`find_gap_bridges` on the pruned graph: two aligned
/// ends of a limb, an end cut off the limb it grows from), each drawn into the analysed mask
/// and reported in input pixels. When there are any, the workspace goes back to `unbridged`
/// (where the distance stage began), the bridged mask's runs are listed anew and its new
/// pinholes filled: true, and the stages from the distance transform on run again on it.
/// Gap lengths are in input pixels in `options.bridging`, in analysed ones here.
template <class Scale>
[[nodiscard]] result<bool> bridge_stage(const perch_options& options,
                                        workspace::checkpoint unbridged, workspace& ws,
                                        perch_result& out, pipeline_state<Scale>& s) noexcept {
  if (s.bridges.capacity() == 0) return false;
  PERCH_TRY(find_gap_bridges(image_view<const std::uint8_t>(s.local),
                             image_view<const std::uint32_t>(s.dist), s.runs, out.graph,
                             options.bridging.max_gap_px * options.downscale, options.bridging,
                             options.limbs, ws, s.bridges));
  if (s.bridges.empty()) return false;
  ws.rewind(unbridged);
  out.mask.tree_pixels += draw_gap_bridges(s.local, s.bridges.items());
  const int w = s.local.width(), h = s.local.height();
  auto runs = find_row_runs(image_view<const std::uint8_t>(s.local), ws, max_runs(w, h));
  if (!runs && runs.error().code != errc::capacity_exceeded) return unexpected{runs.error()};
  s.runs = runs ? *runs : row_runs{};  // too many to list: the kernels scan the mask
  out.mask.runs = s.runs;
  PERCH_TRY(fill_pinholes(options, ws, out, s));
  auto reported = ws.allocate<perch_bridge>(s.bridges.size());
  PERCH_TRY(all_ok(reported));
  const point2f offset = to_point(out.mask.offset);  // local to analysed frame
  for (std::size_t i = 0; i < s.bridges.size(); ++i) {
    const gap_bridge& b = s.bridges[i];
    (*reported)[i] = {input_pixel(out, b.from + offset), input_pixel(out, b.to + offset),
                      b.gap_px / options.downscale, b.kind};
  }
  out.bridges = *reported;
  return true;
}

/// Stage 7: limbs (edges chained through the junctions where only side twigs leave), each
/// oriented from the end nearer the trunk and trimmed to outside its end junctions; and what
/// surrounds them: the grounded pieces of mask, the other limbs' discs for the clearance.
template <class Scale>
[[nodiscard]] status limb_stage(const perch_options& options, workspace& ws, perch_result& out,
                                pipeline_state<Scale>& s) noexcept {
  const skeleton_graph& graph = out.graph;
  auto node_distance = ws.allocate<float>(static_cast<std::size_t>(graph.topology().node_id_end()));
  auto next = ws.allocate<std::int32_t>(edge_continuations::ends_for(graph));
  PERCH_TRY(all_ok(node_distance, next));
  s.node_distance = *node_distance;
  s.next = edge_continuations(*next);
  PERCH_TRY(distances_to_trunk(graph, s.node_distance, ws));
  // A limb is a twig only if it is one at the coarse end of the scale's range.
  const float coarse_mm_per_px = s.mm_per_px * (1.0f + scale_uncertainty(*s.scaled));
  limb_continuations(graph, s.next, options.limbs,
                     options.obstacles.twig_radius_px(coarse_mm_per_px));
  auto traced = trace_limbs(graph, s.next, ws);
  PERCH_TRY(all_ok(traced));
  out.limbs = *traced;
  auto stretches = ws.allocate<branch_stretch>(out.limbs.size());
  const auto components = static_cast<std::size_t>(std::max<std::int32_t>(graph.component_count(), 0));
  auto grounded = ws.allocate<std::uint8_t>(components);
  auto component_area = ws.allocate<float>(components);
  PERCH_TRY(all_ok(stretches, grounded, component_area));
  s.stretches = *stretches;
  s.grounded = *grounded;
  for (std::size_t l = 0; l < out.limbs.size(); ++l)
    s.stretches[l] = limb_stretch(graph, s.next, out.limbs[l]);
  grounded_components(out.limbs, static_cast<float>(out.mask.analysed_height - 1 - out.mask.offset.y),
                      s.grounded, *component_area);
  auto obstacles = find_limb_obstacles(graph, out.limbs, s.next, s.stretches,
                                       image_view<const std::uint8_t>(s.skeleton),
                                       image_view<const std::uint32_t>(s.dist),
                                       runs_of(s.listed, s.skeleton), coarse_mm_per_px, ws,
                                       options.obstacles);
  PERCH_TRY(all_ok(obstacles));
  s.obstacles = *obstacles;
  auto surroundings = limb_neighbourhoods(out.limbs, s.obstacles.own, ws);
  PERCH_TRY(all_ok(surroundings));
  s.clearance = limb_clearance(s.obstacles.discs, *surroundings);
  return {};
}

/// Stage 8: windows one drone width long along every limb's stretch, and their measures.
/// Capacity: a stretch of n points is at most 1.5·n px long, so it has at most
/// 1.5·n / stride + 1 windows; `options.limits.windows` caps the total (capacity_exceeded).
template <BinaryView Mask, Platform P, class Scale>
[[nodiscard]] status window_stage(const Mask& mask, const P& platform, const perch_options& options,
                                  workspace& ws, perch_result& out,
                                  pipeline_state<Scale>& s) noexcept {
  window_options geometry;
  // One drone width even at the fine end of the scale's range.
  geometry.drone_width_mm =
      platform.geometry.drone_width_mm / (1.0f - scale_uncertainty(*s.scaled));
  geometry.claw_width_mm = platform.geometry.claw_width_mm;
  geometry.stride_mm = options.stride_mm;
  geometry.curvature_stencil_mm = options.curvature_stencil_mm;
  geometry.camera = options.camera;
  PERCH_TRY(geometry.validate());
  std::size_t longest = 0;
  std::size_t bound = 0;
  const float stride_px = options.stride_mm / s.mm_per_px;
  for (const branch_stretch stretch : s.stretches) {
    longest = std::max(longest, stretch.count);
    bound += static_cast<std::size_t>(1.5f * static_cast<float>(stretch.count) / stride_px) + 1;
  }
  auto windows = bounded_vector<window_measures>::make(ws, std::min(bound, options.limits.windows));
  auto window_scratch = ws.allocate<float>(window_scratch_floats(longest));
  auto diameters = ws.allocate<float>(longest);
  // Per limb point, how many before it lie on a bridge: a window must not run across one.
  std::size_t longest_limb = 0;
  if (!s.bridges.empty())
    for (const skeleton_limb& limb : out.limbs) longest_limb = std::max(longest_limb, limb.points.size());
  auto bridged_before = ws.allocate<std::uint32_t>(s.bridges.empty() ? 0 : longest_limb + 1);
  PERCH_TRY(all_ok(windows, window_scratch, diameters, bridged_before));
  s.windows = *windows;
  const prepared_mask& m = out.mask;
  for (std::size_t l = 0; l < out.limbs.size(); ++l) {
    const skeleton_limb& limb = out.limbs[l];
    const float from = s.node_distance[static_cast<std::size_t>(node_at_end(out.graph, limb.first_end))];
    const float to = s.node_distance[static_cast<std::size_t>(node_at_end(out.graph, limb.last_end))];
    const branch_stretch stretch = s.stretches[l];
    const auto points = limb.points.subspan(stretch.first, stretch.count);
    const auto radii = limb.radius_px.subspan(stretch.first, stretch.count);
    const std::span<float> widths = diameters->first(stretch.count);
    cross_section_diameters(image_view<const std::uint8_t>(s.local), points, radii, widths);
    branch_geometry g{points, radii, static_cast<std::int32_t>(l), limb.component,
                      to < from ? origin_end::back : origin_end::front, m.offset,
                      static_cast<std::uint32_t>(stretch.first), widths,
                      m.analysed_width, m.analysed_height,
                      limb.component < 0 || s.grounded[static_cast<std::size_t>(limb.component)] != 0};
    const std::size_t before = s.windows.size();
    const status measured =
        measure_windows(g, *s.scaled, s.mm_per_px, *window_scratch, s.windows, geometry);
    if (!measured && measured.error().code == errc::capacity_exceeded)
      return fail(errc::capacity_exceeded, "perch_options.limits.windows", measured.error().needed);
    PERCH_TRY(measured);
    out.windows_held = std::max(out.windows_held, static_cast<std::uint32_t>(s.windows.size()));
    const bool bridged = !s.bridges.empty() && s.windows.size() > before;
    if (bridged) count_bridged_points(limb.points, s.bridges.items(), *bridged_before);
    std::size_t kept = before;
    for (std::size_t i = before; i < s.windows.size(); ++i) {
      window_measures window = s.windows[i];
      if (bridged && (*bridged_before)[window.last + 1] != (*bridged_before)[window.first])
        continue;
      if (out.holes.filled > 0 && options.downscale == 1.0f &&
          !middle_on_tree(mask, limb.points, m.offset, window))
        continue;
      window.branch = limb.edge_at[window.middle];
      s.windows[kept++] = window;
    }
    s.windows.truncate(kept);
  }
  out.windows = static_cast<std::uint32_t>(s.windows.size());
  return {};
}

/// Stage 9: the platform's constraints and scorer (eq. 3), the ranked sites, and the sites and
/// near misses reported in input-image pixels (`input_pixel`).
template <Platform P, class Scale>
[[nodiscard]] status ranking_stage(const P& platform, const perch_options& options, workspace& ws,
                                   perch_result& out, pipeline_state<Scale>& s) noexcept {
  const tree_pixel_counter tree(image_view<const std::uint8_t>{s.local});
  const point2f up = options.camera.up();
  auto make_context = [&](const window_measures& m) {
    const std::span<const pixel> points = out.limbs[static_cast<std::size_t>(m.limb)].points;
    const pixel mid = points[m.middle];
    return window_context(tree, m, to_point(points[m.first]), to_point(points[m.last]),
                          std::sqrt(static_cast<float>(s.dist(mid.x, mid.y))), up, &s.clearance);
  };
  auto ranked = rank_windows(s.windows.items(), platform.constraints, platform.scorer,
                             make_context, ws, options.ranking, scale_uncertainty(*s.scaled));
  PERCH_TRY(all_ok(ranked));
  auto to_input = [&](window_measures& window) {
    window.centre = input_pixel(out, to_point(window.centre));
    window.base_end = input_pixel(out, to_point(window.base_end));
    window.tip_end = input_pixel(out, to_point(window.tip_end));
    window.mm_per_px *= options.downscale;
  };
  auto sites = ws.allocate<perch_site>(ranked->sites.size());
  auto misses = ws.allocate<near_miss>(ranked->near_misses.size());
  PERCH_TRY(all_ok(sites, misses));
  std::copy(ranked->sites.begin(), ranked->sites.end(), sites->begin());
  std::copy(ranked->near_misses.begin(), ranked->near_misses.end(), misses->begin());
  for (perch_site& site : *sites) to_input(site.window);
  for (near_miss& miss : *misses) to_input(miss.window);
  out.sites = *sites;
  out.rejections = ranked->rejections;
  out.near_misses = *misses;
  out.viable = ranked->viable;
  out.outcome = out.sites.empty() ? perch_outcome::no_perch : perch_outcome::found;
  return {};
}

}  // namespace detail

}  // namespace perch
