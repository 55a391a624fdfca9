/// \file
/// perch: where a tree-perching drone should grasp a tree (the PLI method of "Perch Location
/// Identification", with the reference prototype's defects fixed and the paper's future work
/// done). The one include a user needs: every stage, in data-flow order, and `find_perch`.
///
///   mask → distance transform → skeleton → skeleton graph → weighting + pruning
///        → windows + measures → constraints → scorer → ranked perch sites + diagnostics
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>

#include "perch/analysis.hpp"
#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/graph.hpp"
#include "perch/label.hpp"
#include "perch/platform.hpp"
#include "perch/policy.hpp"
#include "perch/skeleton.hpp"

namespace perch {

/// A monotonic clock in nanoseconds, supplied by the caller (perch itself reads no clock, so
/// firmware without one can run it). E.g. a captureless lambda over `std::chrono::steady_clock`.
using clock_ns_fn = std::int64_t (*)() noexcept;

/// Milliseconds spent in each stage of `find_perch` (all 0 when no clock was given).
struct stage_timings {
  float prepare_ms = 0;   ///< bounding box, binarise, downscale
  float distance_ms = 0;  ///< Euclidean distance transform
  float skeleton_ms = 0;  ///< skeletonisation
  float graph_ms = 0;     ///< pixel kinds, tracing, adjacency list
  float prune_ms = 0;     ///< scale, weighting (eq. 1) and pruning
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
  prune_options pruning{};             ///< eq. 1 weights and pruning thresholds
  rank_options ranking{};              ///< top-k and the distance between ranked sites
  std::size_t max_windows = std::size_t{1} << 18;  ///< capacity: windows over the whole tree
  clock_ns_fn clock = nullptr;         ///< stage timings when given

  [[nodiscard]] status validate() const noexcept {
    if (!(downscale > 0.0f && downscale <= 1.0f))
      return fail(errc::invalid_parameter, "perch_options.downscale");
    for (const float v : {stride_mm, curvature_stencil_mm})
      if (!(std::isfinite(v) && v > 0)) return fail(errc::invalid_parameter, "perch_options");
    if (ranking.top_k == 0 || !(ranking.site_separation_mm >= 0))
      return fail(errc::invalid_parameter, "perch_options.ranking");
    if (max_windows == 0) return fail(errc::invalid_parameter, "perch_options.max_windows");
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

/// Everything `find_perch` found. Spans and the graph live in the workspace: valid until the
/// workspace's next `reset()` (the next `find_perch` call on it).
///
/// Coordinates: `sites[i].window.centre` is in input-image pixels. The graph, skeleton and
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
  float mm_per_px = 0;  ///< global scale, per input-image pixel
  std::string_view scale{};     ///< the scale policy's name
  std::string_view platform{};  ///< the platform's name
  int width = 0, height = 0;    ///< input image size
  prepared_mask mask{};                       ///< the analysed (cropped, reduced) mask
  image_view<const std::uint32_t> dist2{};    ///< squared distance map, local coordinates
  image_view<const std::uint8_t> skeleton{};  ///< skeleton (1/0), local coordinates
  skeleton_graph graph{};                     ///< after pruning, local coordinates
  prune_report pruning{};                     ///< what pruning removed
  stage_timings timing{};
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

/// The scale policy for the analysed image at `factor`.
template <ScalePolicy Scale>
[[nodiscard]] result<Scale> rescale(const Scale& scale, float factor, workspace& ws) noexcept {
  if constexpr (requires { scale.rescaled(factor, ws); }) {
    return scale.rescaled(factor, ws);
  } else {
    if (factor != 1.0f)
      return fail(errc::invalid_parameter, "this scale policy has no rescaled(): use downscale 1");
    return scale;
  }
}

/// The part of a branch's polyline outside the bodies of the junctions it joins.
struct branch_stretch {
  std::size_t first = 0;
  std::size_t count = 0;
};

/// A branch's skeleton runs on into its parent up to the junction node, inside the parent's
/// body, where it bends toward the node: a window there measures the parent, not the branch.
/// Leading and trailing points that lie inside the junction node's disc or inside the
/// inscribed disc of a point of another branch at that junction (|p − q| < r(q)) are left
/// out: the window starts where the branch leaves its parent's surface, however oblique the
/// fork (the parent's body reaches r_parent / sin θ along a limb leaving at θ). Ends and loops
/// keep all their points.
[[nodiscard]] inline branch_stretch outside_junctions(const skeleton_graph& graph,
                                                      const skeleton_branch& b) noexcept {
  auto inside = [&](node_id n, pixel p) {
    const skeleton_node node = graph.node(n);
    if (node.kind != node_kind::junction) return false;
    auto distance2 = [](pixel a, pixel c) {
      const float dx = static_cast<float>(a.x - c.x);
      const float dy = static_cast<float>(a.y - c.y);
      return dx * dx + dy * dy;
    };
    const float to_node2 = distance2(p, node.position);
    if (to_node2 < node.radius_px * node.radius_px) return true;
    // Points of the other branches within reach of p, walked from the junction outward.
    const float reach = std::sqrt(to_node2) + 2.0f * node.radius_px + 1.0f;
    bool covered = false;
    for (const incidence in : graph.topology().incidences(n)) {
      if (in.edge == b.id || covered) continue;
      const skeleton_branch other = graph.branch(in.edge);
      const std::size_t count = other.points.size();
      for (std::size_t k = 0; k < count && !covered; ++k) {
        const std::size_t i = in.direction == traversal::forward ? k : count - 1 - k;
        const pixel q = other.points[i];
        if (distance2(q, node.position) > reach * reach) break;
        covered = distance2(p, q) < other.radius_px[i] * other.radius_px[i];
      }
    }
    return covered;
  };
  std::size_t first = 0;
  std::size_t last = b.points.size();
  while (first < last && inside(b.from, b.points[first])) ++first;
  while (last > first && inside(b.to, b.points[last - 1])) --last;
  return {first, last - first};
}

}  // namespace detail

/// Bytes of workspace `find_perch` needs at most for a `width` × `height` mask (every pixel
/// tree, the worst case); give a borrowed workspace this much and it never fails for lack of
/// room. Real trees need far less: `workspace::high_water()` after a call says how much.
[[nodiscard]] inline std::size_t find_perch_workspace_bytes(int width, int height,
                                                           const perch_options& options = {}) noexcept {
  const int w = scaled_extent(width, options.downscale) + 2;
  const int h = scaled_extent(height, options.downscale) + 2;
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::size_t bytes = prepare_mask_workspace_bytes(width, height, options.downscale);
  bytes += workspace::footprint<std::uint32_t>(n) + workspace::footprint<std::uint8_t>(n);
  bytes += distance_workspace_bytes(w, h);
  bytes += skeleton_workspace_bytes(w, h);
  bytes += skeleton_graph_workspace_bytes(w, h, n);
  bytes += tree_pixel_counter::workspace_bytes(w, h);
  bytes += workspace::footprint<window_measures>(options.max_windows);
  bytes += 2 * workspace::footprint<float>(n) + (std::size_t{64} << 10);
  return bytes;
}

/// Finds where `platform` can perch on the tree of `mask` (non-zero = tree).
///
/// Runs the whole PLI pipeline on the tree's bounding box: distance transform, skeleton
/// (`skeletoniser`, medial axis by default), skeleton graph of every connected component,
/// weighting and pruning (paper eq. 1), windows one drone width long along every branch,
/// measures, the platform's constraints and scorer (paper eq. 3), and ranks the best
/// `options.ranking.top_k` sites at least `site_separation_mm` apart.
/// "No perch" and "no tree" are outcomes, not errors: the result then says why (rejections per
/// constraint and the near misses).
/// Errors: view errors of `mask` (null data, stride, size), invalid options, platform or scale
/// (with the parameter named), `capacity_exceeded` when the tree has more windows than
/// `options.max_windows`, `workspace_too_small` for a borrowed workspace (see
/// `find_perch_workspace_bytes`), and a scale policy's own errors (e.g. `no_valid_depth`).
/// Allocation: none once the workspace has grown to this mask's needs (a second call on a
/// similar mask allocates nothing). Resets `ws`: results of a previous call on it are gone.
/// Deterministic: the same input gives bit-identical output.
/// Complexity: linear in the tree's bounding-box pixels plus windows × window length.
template <BinaryView Mask, Platform P, ScalePolicy Scale, Skeletoniser Skel>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, const P& platform,
                                              const Scale& scale, const Skel& skeletoniser,
                                              workspace& ws,
                                              const perch_options& options = {}) noexcept {
  ws.reset();
  detail::stage_clock clock(options.clock);
  PERCH_TRY(validate_non_empty(mask));
  PERCH_TRY(options.validate());
  PERCH_TRY(validate_platform(platform));
  PERCH_TRY(options.pruning.validate());

  perch_result out;
  out.width = mask.width();
  out.height = mask.height();
  out.scale = Scale::name;
  out.platform = P::name;

  // 1. The tree's bounding box, binarised, reduced, with a background border.
  auto prepared = prepare_mask(mask, ws, options.downscale);
  if (!prepared) return unexpected{prepared.error()};
  out.mask = *prepared;
  const image_view<std::uint8_t> local = prepared->pixels;
  const int w = local.width();
  const int h = local.height();
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  auto scaled = detail::rescale(scale, options.downscale, ws);
  if (!scaled) return unexpected{scaled.error()};
  scale_context context{prepared->analysed_width, prepared->analysed_height, 0, {}, prepared->offset, {}};
  PERCH_TRY(scaled->validate(context));
  out.timing.prepare_ms = clock.lap();
  if (prepared->tree_pixels == 0) {
    out.timing.total_ms = clock.total();
    return out;
  }

  // 2. Distance transform and skeleton.
  auto dist2 = ws.allocate<std::uint32_t>(n);
  if (!dist2) return unexpected{dist2.error()};
  const image_view<std::uint32_t> dist(dist2->data(), w, h);
  PERCH_TRY(distance_transform_sq(image_view<const std::uint8_t>(local), dist, ws));
  out.dist2 = dist;
  out.timing.distance_ms = clock.lap();

  auto skeleton_pixels = ws.allocate_zeroed<std::uint8_t>(n);
  if (!skeleton_pixels) return unexpected{skeleton_pixels.error()};
  const image_view<std::uint8_t> skeleton(skeleton_pixels->data(), w, h);
  PERCH_TRY(skeletoniser(image_view<const std::uint8_t>(local),
                         image_view<const std::uint32_t>(dist), skeleton, ws));
  out.skeleton = skeleton;
  out.timing.skeleton_ms = clock.lap();

  // 3. The skeleton graph.
  auto built = build_skeleton_graph(image_view<const std::uint8_t>(skeleton),
                                    image_view<const std::uint32_t>(dist), ws);
  if (!built) return unexpected{built.error()};
  out.graph = std::move(*built);
  skeleton_graph& graph = out.graph;
  out.timing.graph_ms = clock.lap();

  // 4. Scale (from the skeleton: its widest point, or its depth), weighting and pruning.
  std::uint32_t max_d2 = 0;
  std::size_t skeleton_count = 0;
  for (int y = 1; y + 1 < h; ++y) {
    const std::uint8_t* s = &skeleton(0, y);
    const std::uint32_t* d = &dist(0, y);
    for (int x = 1; x + 1 < w; ++x)
      if (s[x] != 0) {
        max_d2 = std::max(max_d2, d[x]);
        ++skeleton_count;
      }
  }
  auto sample = ws.allocate<pixel>(skeleton_count);
  auto scratch = ws.allocate<float>(skeleton_count);
  if (!sample) return unexpected{sample.error()};
  if (!scratch) return unexpected{scratch.error()};
  std::size_t k = 0;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x)
      if (skeleton(x, y) != 0) (*sample)[k++] = pixel{x, y};
  context.max_distance_px = std::sqrt(static_cast<float>(max_d2));
  context.sample = *sample;
  context.scratch = *scratch;
  auto global = scaled->global_mm_per_px(context);
  if (!global) return unexpected{global.error()};
  const float mm_per_px = *global;
  if (!(std::isfinite(mm_per_px) && mm_per_px > 0))
    return fail(errc::invalid_parameter, "scale policy gave a non-positive mm/px");
  out.mm_per_px = mm_per_px * options.downscale;

  prune_options pruning = options.pruning;
  pruning.diameter_min_mm = platform.geometry.grasp_min_mm;
  pruning.diameter_max_mm = platform.geometry.grasp_max_mm;
  auto report = prune_skeleton_graph(graph, mm_per_px, ws, pruning);
  if (!report) return unexpected{report.error()};
  out.pruning = *report;
  out.timing.prune_ms = clock.lap();

  // 5. Windows along every branch outside the junctions' bodies, oriented from the end nearer
  //    the trunk.
  auto node_distance = ws.allocate<float>(static_cast<std::size_t>(graph.topology().node_id_end()));
  auto stretches = ws.allocate<detail::branch_stretch>(static_cast<std::size_t>(graph.topology().edge_id_end()));
  if (!node_distance) return unexpected{node_distance.error()};
  if (!stretches) return unexpected{stretches.error()};
  PERCH_TRY(distances_to_trunk(graph, *node_distance, ws));
  auto windows = bounded_vector<window_measures>::make(ws, options.max_windows);
  if (!windows) return unexpected{windows.error()};
  window_options geometry;
  geometry.drone_width_mm = platform.geometry.drone_width_mm;
  geometry.claw_width_mm = platform.geometry.claw_width_mm;
  geometry.stride_mm = options.stride_mm;
  geometry.curvature_stencil_mm = options.curvature_stencil_mm;
  geometry.camera = options.camera;
  PERCH_TRY(geometry.validate());
  std::size_t longest = 0;
  graph.for_each_branch([&](const skeleton_branch& b) {
    const detail::branch_stretch stretch = detail::outside_junctions(graph, b);
    (*stretches)[static_cast<std::size_t>(b.id)] = stretch;
    longest = std::max(longest, stretch.count);
  });
  auto window_scratch = ws.allocate<float>(window_scratch_floats(longest));
  if (!window_scratch) return unexpected{window_scratch.error()};
  status measured{};
  graph.for_each_branch([&](const skeleton_branch& b) {
    if (!measured) return;
    const float from = (*node_distance)[static_cast<std::size_t>(b.from)];
    const float to = (*node_distance)[static_cast<std::size_t>(b.to)];
    const detail::branch_stretch stretch = (*stretches)[static_cast<std::size_t>(b.id)];
    branch_geometry g{b.points.subspan(stretch.first, stretch.count),
                      b.radius_px.subspan(stretch.first, stretch.count), b.id, b.component,
                      to < from ? origin_end::back : origin_end::front, prepared->offset};
    measured = measure_windows(g, *scaled, mm_per_px, *window_scratch, *windows, geometry);
  });
  PERCH_TRY(measured);
  out.windows = static_cast<std::uint32_t>(windows->size());
  out.timing.windows_ms = clock.lap();

  // 6. Constraints, scorer, ranking.
  tree_pixel_counter tree;
  PERCH_TRY(tree.build(image_view<const std::uint8_t>(local), ws));
  const point2f up = options.camera.up();
  auto make_context = [&](const window_measures& m) {
    const skeleton_branch b = graph.branch(m.branch);
    const std::span<const pixel> points =
        b.points.subspan((*stretches)[static_cast<std::size_t>(m.branch)].first);
    const pixel mid = points[m.middle];
    return window_context(tree, m, to_point(points[m.first]), to_point(points[m.last]),
                          std::sqrt(static_cast<float>(dist(mid.x, mid.y))), up);
  };
  auto ranked = rank_windows(windows->items(), platform.constraints, platform.scorer,
                             make_context, ws, options.ranking);
  if (!ranked) return unexpected{ranked.error()};

  // Report sites in input-image pixels.
  auto sites = ws.allocate<perch_site>(ranked->sites.size());
  if (!sites) return unexpected{sites.error()};
  for (std::size_t i = 0; i < sites->size(); ++i) {
    perch_site s = ranked->sites[i];
    const point2f c = prepared->to_input(to_point(s.window.centre));
    s.window.centre = {static_cast<std::int32_t>(std::lround(c.x())),
                       static_cast<std::int32_t>(std::lround(c.y()))};
    s.window.mm_per_px *= options.downscale;
    (*sites)[i] = s;
  }
  out.sites = *sites;
  out.rejections = ranked->rejections;
  out.near_misses = ranked->near_misses;
  out.viable = ranked->viable;
  out.outcome = out.sites.empty() ? perch_outcome::no_perch : perch_outcome::found;
  out.timing.ranking_ms = clock.lap();
  out.timing.total_ms = clock.total();
  return out;
}

/// `find_perch` with the default skeleton (medial axis).
template <BinaryView Mask, Platform P, ScalePolicy Scale>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, const P& platform,
                                              const Scale& scale, workspace& ws,
                                              const perch_options& options = {}) noexcept {
  return find_perch(mask, platform, scale, medial_axis{}, ws, options);
}

/// `find_perch` for the paper's platform (tendon-driven claw) and scale (the trunk prior).
template <BinaryView Mask>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, workspace& ws,
                                              const perch_options& options = {}) noexcept {
  return find_perch(mask, tendon_claw{}, trunk_prior{}, medial_axis{}, ws, options);
}

}  // namespace perch
