// SPDX-License-Identifier: BSL-1.0
#include "perch/bridge/gaps.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "support/find_perch_instances.hpp"
#include "support/synthetic_tree.hpp"

namespace {

using perch::image;
using perch::perch_outcome;
using perch::point2f;
using perch::support::draw_capsule;

constexpr float mm_per_px = 2.0f;  // every mask here: a 180 mm drone is 90 px, its reach 35 px

/// Draws a limb of radius `r` from `a` to `b`.
void limb(image<std::uint8_t>& m, point2f a, point2f b, float r) {
  draw_capsule(m.view(), a, b, r, r, std::uint8_t{1});
}

/// Clears the columns [x0, x1) of the rows [y0, y1).
void clear(image<std::uint8_t>& m, int x0, int y0, int x1, int y1) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) m(x, y) = 0;
}

/// A trunk rising from the bottom edge (40 px wide) and a level limb leaving it at y = 260, cut
/// at x = 200 by a gap `gap` px long: the near piece is too short for a window, the far piece
/// (`far_radius` px, `far_drop` px lower) long enough for several. The near piece's radius is
/// `near_radius`.
image<std::uint8_t> broken_limb(int gap, float far_radius = 10, int far_drop = 0,
                                float near_radius = 10) {
  image<std::uint8_t> m(640, 480);
  limb(m, {120, 200}, {120, 479}, 20);
  limb(m, {120, 260}, {230, 260}, near_radius);
  clear(m, 200, 0, 640, 480);
  const float y = 260.0f + static_cast<float>(far_drop);
  limb(m, {200.0f + static_cast<float>(gap) + far_radius, y}, {600, y}, far_radius);
  clear(m, 200, 0, 200 + gap, 480);
  return m;
}

perch::perch_options bridging(bool on) {
  perch::perch_options o;
  o.bridging.enabled = on;
  return o;
}

std::optional<perch::perch_result> find(const image<std::uint8_t>& m, perch::workspace& ws,
                                        const perch::perch_options& options) {
  auto found = perch::find_perch(m.view(), perch::tendon_claw{}, perch::fixed_scale{mm_per_px}, ws, options);
  REQUIRE(found);
  return std::move(*found);
}

/// A parent limb 40 px wide (80 mm) level at y = 300 on the trunk, and a child 16 px wide
/// (32 mm) rising from it at x = 360, its base cut off `cut` px above the parent's outline.
image<std::uint8_t> cut_child(int cut) {
  image<std::uint8_t> m(640, 480);
  limb(m, {120, 200}, {120, 479}, 20);
  limb(m, {360, 300}, {360, 100}, 8);
  clear(m, 200, 280 - cut, 640, 280);
  limb(m, {120, 300}, {600, 300}, 20);
  return m;
}

}  // namespace

TEST_CASE("gaps: two aligned pieces of a limb 3 px apart are bridged; the far piece is supported") {
  const image<std::uint8_t> m = broken_limb(3);
  const image<std::uint8_t> before = m;
  perch::workspace ws;
  const auto off = find(m, ws, bridging(false));
  CHECK(off->outcome == perch_outcome::no_perch);  // the far piece holds nothing up
  CHECK(off->bridges.empty());
  CHECK(off->rejections.front().constraint == "supported");
  CHECK(off->rejections.front().windows > 0);

  const auto on = find(m, ws, bridging(true));
  REQUIRE(on->bridges.size() == 1);
  const perch::perch_bridge& b = on->bridges.front();
  CHECK(b.kind == perch::bridge_kind::end_to_end);
  CHECK(b.gap_px == doctest::Approx(3).epsilon(0.35));
  CHECK(std::abs(b.from.x - 199) <= 1);
  CHECK(std::abs(b.to.x - 203) <= 1);
  CHECK(std::abs(b.from.y - 260) <= 1);
  CHECK(on->graph.component_count() == 1);
  REQUIRE(on->outcome == perch_outcome::found);
  for (const perch::perch_site& s : on->sites) {  // on the far piece, none across the bridge
    CHECK(std::min(s.window.base_end.x, s.window.tip_end.x) > 203);
    CHECK(s.window.grounded);
  }
  CHECK(std::equal(m.data(), m.data() + 640 * 480, before.data()));  // the caller's mask as it was
}

TEST_CASE("gaps: ends that do not face each other, a gap too wide, or unlike widths are not bridged") {
  perch::workspace ws;
  SUBCASE("the far piece 25 px lower: the ends pass each other") {
    const auto r = find(broken_limb(3, 10, 25), ws, bridging(true));
    CHECK(r->bridges.empty());
    CHECK(r->outcome == perch_outcome::no_perch);
  }
  SUBCASE("a gap of 12 px, over the 6 px cap (within it when the cap is 16 px)") {
    const image<std::uint8_t> m = broken_limb(12);
    CHECK(find(m, ws, bridging(true))->bridges.empty());
    perch::perch_options wider = bridging(true);
    wider.bridging.max_gap_px = 16;
    const auto r = find(m, ws, wider);
    REQUIRE(r->bridges.size() == 1);
    CHECK(r->bridges.front().gap_px == doctest::Approx(12).epsilon(0.1));
  }
  SUBCASE("a gap of 8 px on a limb 6 px wide: wider than its diameter (not when two may be)") {
    const image<std::uint8_t> m = broken_limb(8, 3, 0, 3);
    perch::perch_options wider = bridging(true);
    wider.bridging.max_gap_px = 16;
    CHECK(find(m, ws, wider)->bridges.empty());
    wider.bridging.max_gap_diameters = 2;
    CHECK(find(m, ws, wider)->bridges.size() == 1);
  }
  SUBCASE("a far piece 8 px wide after one 20 px wide: not one limb, nor a child of it") {
    const auto r = find(broken_limb(3, 4), ws, bridging(true));
    CHECK(r->bridges.empty());
    CHECK(r->outcome == perch_outcome::no_perch);
  }
}

TEST_CASE("gaps: a child cut 2 px off its parent is bridged, and keeps windows on the parent away") {
  const image<std::uint8_t> m = cut_child(2);
  perch::workspace ws;
  perch::perch_options options;
  options.ranking.top_k = 100;  // every viable window
  options.ranking.site_separation_mm = 0;
  // A window's end must keep the claw's reach (70 mm + 2 px: 37 px) from the child's surface,
  // the child counted from its base on the parent's axis: 37 + 8 + 20 px from x = 360.
  const auto clear_of_child = [](const perch::perch_result& r) {
    for (const perch::perch_site& s : r.sites) {
      const int near_end = std::min(s.window.base_end.x, s.window.tip_end.x);
      if (near_end > 360 && near_end - 360 < 37 + 8 + 20) return false;
    }
    return true;
  };
  options.bridging.enabled = false;
  const auto off = find(m, ws, options);
  CHECK(off->graph.component_count() == 2);
  CHECK_FALSE(clear_of_child(*off));  // the detached child's cut base is 22 px above the axis

  options.bridging.enabled = true;
  const auto on = find(m, ws, options);
  REQUIRE(on->bridges.size() == 1);
  CHECK(on->bridges.front().kind == perch::bridge_kind::end_to_body);
  CHECK(on->bridges.front().gap_px == doctest::Approx(2).epsilon(0.5));
  CHECK(std::abs(on->bridges.front().from.x - 360) <= 2);
  CHECK(on->graph.component_count() == 1);
  REQUIRE(on->outcome == perch_outcome::found);  // farther along the parent
  CHECK(clear_of_child(*on));
}

TEST_CASE("gaps: no allocation on a second call; reported in input pixels when downscaled") {
  const image<std::uint8_t> m = broken_limb(3);
  perch::workspace ws;
  const auto first = find(m, ws, {});
  REQUIRE(first->bridges.size() == 1);
  const perch::perch_bridge first_bridge = first->bridges.front();
  perch::test::allocation_scope scope;
  const auto second = perch::find_perch(m.view(), perch::tendon_claw{}, perch::fixed_scale{mm_per_px}, ws, {});
  CHECK(scope.count() == 0);
  REQUIRE(second);
  CHECK_FALSE(second->cold);
  REQUIRE(second->bridges.size() == 1);
  CHECK(second->bridges.front().from == first_bridge.from);

  perch::perch_options half;
  half.downscale = 0.5f;
  const auto reduced = find(m, ws, half);
  REQUIRE(reduced->bridges.size() == 1);
  CHECK(std::abs(reduced->bridges.front().from.x - 199) <= 2);
  CHECK(std::abs(reduced->bridges.front().to.x - 203) <= 2);
  CHECK(reduced->bridges.front().gap_px > 0);
  CHECK(reduced->bridges.front().gap_px <= 6);
}

TEST_CASE("gaps: bad bridging options are refused by name") {
  const image<std::uint8_t> m = broken_limb(3);
  perch::workspace ws;
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), -1.0f,
                          std::numeric_limits<float>::infinity()}) {
    perch::perch_options o;
    o.bridging.max_gap_px = bad;
    auto r = perch::find_perch(m.view(), perch::tendon_claw{}, perch::fixed_scale{mm_per_px}, ws, o);
    REQUIRE_FALSE(r);
    CHECK(r.error().code == perch::errc::invalid_parameter);
    CHECK(r.error().detail == "perch_options.bridging");
    o = {};
    o.bridging.max_gap_diameters = bad;
    CHECK_FALSE(perch::find_perch(m.view(), perch::tendon_claw{}, perch::fixed_scale{mm_per_px}, ws, o));
  }
  perch::perch_options none;
  none.bridging.max_bridges = 0;  // room for none: nothing bridged, no error
  const auto r = find(m, ws, none);
  CHECK(r->bridges.empty());
}

TEST_CASE("gaps: a limb's end is read off its centreline; pieces are the mask's components") {
  const image<std::uint8_t> m = broken_limb(3);
  perch::workspace ws;
  const auto r = find(m, ws, bridging(false));
  const perch::pixel offset = r->mask.offset;
  int ends_at_gap = 0;
  r->graph.for_each_node([&](const perch::skeleton_node& n) {
    if (n.kind != perch::node_kind::end) return;
    const perch::limb_end e = perch::end_of_limb(r->graph, n.id);
    REQUIRE(e.valid);
    const float x = e.tip.x() + static_cast<float>(offset.x);
    if (x < 195 || x > 215) return;  // the two ends at the gap
    ++ends_at_gap;
    CHECK(std::abs(e.tip.y() + static_cast<float>(offset.y) - 260) <= 1);
    CHECK(std::abs(e.outward.x()) == doctest::Approx(1).epsilon(0.01));
    CHECK(e.outward.x() * (x < 201 ? 1.0f : -1.0f) > 0);  // out of each piece, into the gap
    CHECK(e.radius_px == doctest::Approx(11).epsilon(0.05));  // 21 px wide
  });
  CHECK(ends_at_gap == 2);

  perch::workspace scratch;
  auto pieces = perch::mask_pieces::find(r->mask.runs, r->mask.pixels.height(), scratch);
  REQUIRE(pieces);
  const auto local = [&](int x, int y) { return perch::pixel{x - offset.x, y - offset.y}; };
  const std::int32_t near = pieces->at(local(190, 260)), far = pieces->at(local(210, 260));
  CHECK(near >= 0);
  CHECK(far >= 0);
  CHECK(pieces->at(local(201, 260)) == -1);  // the gap
  CHECK(pieces->at(local(120, 400)) == near);  // the trunk holds the near piece
  CHECK_FALSE(pieces->joined(near, far));
  pieces->join(near, far);
  CHECK(pieces->joined(near, far));
}
