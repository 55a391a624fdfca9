// SPDX-License-Identifier: BSL-1.0
// Tests of the third synthetic tree family (examples/support/support/sympodial_tree.hpp) and its
// place in the population (population.hpp): determinism, the truth's structure, the truth's
// limbs on tree pixels of the mask (up to the defects), and the population's mix.
#include "support/population.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace st = perch::support;

namespace {

bool same_bytes(const perch::image<std::uint8_t>& a, const perch::image<std::uint8_t>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.view().size()) == 0;
}

st::sympodial_options options(st::tree_architecture arch, std::uint32_t seed) {
  st::sympodial_options o;
  o.width = 800;
  o.height = 600;
  o.seed = seed;
  o.architecture = arch;
  o.mm_per_px = 4.0f;
  o.trunk_diameter_mm = 200.0f;
  return o;
}

}  // namespace

TEST_CASE("make_sympodial_tree: same options, same bytes and truth; another seed differs") {
  st::sympodial_options o = options(st::tree_architecture::mixed, 5);
  o.softness_px = 1.0f;
  o.roughness = 0.3f;
  o.foliage = 0.6f;
  o.stubs = 3;
  o.twigs = 10;
  o.holes = 2;
  o.occlusions = 2;
  o.broken = 2;
  o.fragments = 3;
  o.second_tree = 0.6f;
  const st::synthetic_tree a = st::make_sympodial_tree(o);
  const st::synthetic_tree b = st::make_sympodial_tree(o);
  REQUIRE(a.limbs.size() == b.limbs.size());
  CHECK(same_bytes(a.mask, b.mask));
  for (std::size_t i = 0; i < a.limbs.size(); ++i) {
    CHECK(a.limbs[i].centreline == b.limbs[i].centreline);
    CHECK(a.limbs[i].diameter_px == b.limbs[i].diameter_px);
  }
  o.seed = 6;
  CHECK_FALSE(same_bytes(a.mask, st::make_sympodial_tree(o).mask));
  o.width = 0;
  CHECK(st::make_sympodial_tree(o).limbs.empty());
}

TEST_CASE("make_sympodial_tree: the truth's structure, and its limbs lie on tree pixels") {
  constexpr st::tree_architecture archs[] = {st::tree_architecture::sympodial, st::tree_architecture::monopodial,
                                             st::tree_architecture::mixed, st::tree_architecture::fastigiate};
  for (const st::tree_architecture arch : archs)
    for (const int bias : {-1, 0, 1}) {
      st::sympodial_options o = options(arch, 11u + static_cast<std::uint32_t>(bias + 1));
      o.threshold = bias < 0 ? 0.7f : 0.3f;
      o.outline_bias_px = bias;
      o.softness_px = 0.8f;
      o.roughness = 0.2f;
      o.holes = 2;
      o.occlusions = 1;
      o.fragments = 2;
      o.stubs = 2;
      o.twigs = 6;
      const st::synthetic_tree t = st::make_sympodial_tree(o);
      CAPTURE(st::to_string(arch));
      CAPTURE(bias);
      REQUIRE_FALSE(t.limbs.empty());
      CHECK(t.limbs[0].kind == st::limb_kind::trunk);
      CHECK(t.limbs[0].centreline[0].y() >= static_cast<float>(t.mask.height() - 1));
      std::size_t samples = 0, on = 0;
      for (std::size_t i = 0; i < t.limbs.size(); ++i) {
        const st::limb_truth& L = t.limbs[i];
        REQUIRE(L.centreline.size() >= 2);
        REQUIRE(L.diameter_px.size() == L.centreline.size());
        REQUIRE(L.arc_px.size() == L.centreline.size());
        CHECK_FALSE(L.exact_arc);
        if (L.kind == st::limb_kind::trunk || L.kind == st::limb_kind::fragment) {
          CHECK(L.parent == -1);
        } else {
          REQUIRE(L.parent >= 0);
          REQUIRE(static_cast<std::size_t>(L.parent) < i);  // parents first
          const st::limb_truth& P = t.limbs[static_cast<std::size_t>(L.parent)];
          CHECK((st::truth_point_at(P, L.parent_arc_px) - L.centreline[0]).norm() <= 0.01f);
        }
        // The limb's axis, where it is at least 3 px thick and inside the image, is tree.
        if (L.kind == st::limb_kind::twig) continue;
        for (float s = 0.0f; s <= st::length_px(L); s += 2.0f) {
          const Eigen::Vector2f p = st::truth_point_at(L, s);
          const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
          if (st::truth_diameter_at(L, s) < 3.0f || x < 0 || y < 0 || x >= t.mask.width() || y >= t.mask.height())
            continue;
          ++samples;
          on += t.mask(x, y) != 0 ? 1u : 0u;
        }
      }
      REQUIRE(samples > 100);
      CHECK(static_cast<double>(on) >= 0.97 * static_cast<double>(samples));  // holes and leaves aside
    }
}

TEST_CASE("population: sympodial members are deterministic and mixed, with and without a perch") {
  int with = 0, without = 0, met = 0;
  constexpr int members = 20;
  for (int i = 0; i < members; ++i) {
    const st::population_member m = st::population_tree(st::tree_family::sympodial, i);
    CHECK(m.family == st::tree_family::sympodial);
    CHECK(st::to_string(m.family) == "sympodial");
    CHECK_FALSE(m.kind.empty());
    const bool perch = st::perch_truth(m.tree).has_perch();
    (perch ? with : without) += 1;
    met += m.wish_met ? 1 : 0;
    if (i == 3) CHECK(same_bytes(m.tree.mask, st::population_tree(st::tree_family::sympodial, i).tree.mask));
    const int w = m.tree.mask.width();
    CHECK((w >= 640 && w <= 2000 && m.tree.mask.height() * 4 == w * 3));
    CHECK((m.tree.mm_per_px >= 1.5f && m.tree.mm_per_px <= 8.0f));
  }
  CHECK(with >= 12);
  CHECK(without >= 3);
  CHECK(met >= 17);
}
