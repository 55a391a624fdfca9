// SPDX-License-Identifier: BSL-1.0
#include "perch/core/huge_pages.hpp"

#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "allocation_counter.hpp"
#include "perch/pli.hpp"
#include "support/find_perch_instances.hpp"
#include "support/synthetic_tree.hpp"

using perch::huge_page_resource;

TEST_CASE("huge_page_resource: aligned, writable blocks of any size, given back") {
  huge_page_resource resource;
  for (const std::size_t bytes : {std::size_t{1}, std::size_t{4096}, huge_page_resource::page_bytes,
                                  huge_page_resource::page_bytes + 1, std::size_t{5} << 20}) {
    void* block = resource.allocate(bytes, 64);
    REQUIRE(block != nullptr);
    CHECK(reinterpret_cast<std::uintptr_t>(block) % 64 == 0);
    std::memset(block, 0xA5, bytes);  // every byte is mapped and writable
    CHECK(static_cast<unsigned char*>(block)[bytes - 1] == 0xA5);
    resource.deallocate(block, bytes, 64);
  }
  CHECK(resource.is_equal(resource));
  huge_page_resource other;
  CHECK(!resource.is_equal(other));
}

TEST_CASE("huge_page_resource: a workspace on it gives find_perch's results, no heap, no regrowth") {
  const auto tree = perch::support::benchmark_tree(640, 480, perch::support::tree_noise::clean);
  const perch::fixed_scale scale{tree.mm_per_px};
  perch::workspace plain;
  auto expected = perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, plain);
  REQUIRE(expected);
  REQUIRE(expected->outcome == perch::perch_outcome::found);

  huge_page_resource resource;
  perch::workspace ws{&resource};
  REQUIRE(perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, ws));
  const std::size_t blocks = ws.upstream_allocations();
  CHECK(blocks >= 1);
  perch::test::allocation_scope scope;
  auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, ws);
  CHECK(scope.count() == 0);
  CHECK(ws.upstream_allocations() == blocks);
  REQUIRE(found);
  REQUIRE(found->sites.size() == expected->sites.size());
  for (std::size_t i = 0; i < found->sites.size(); ++i) {
    CHECK(found->sites[i].window.centre == expected->sites[i].window.centre);
    CHECK(found->sites[i].penalty == expected->sites[i].penalty);
  }
}
