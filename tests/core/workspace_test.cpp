#include "perch/core/workspace.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <memory_resource>

#include "allocation_counter.hpp"

using perch::errc;
using perch::workspace;

TEST_CASE("workspace: owning workspace reuses its blocks after reset") {
  workspace ws;
  auto run = [&ws] {
    ws.reset();
    auto a = ws.allocate<std::int32_t>(100000);
    auto b = ws.allocate_zeroed<float>(5000);
    auto c = ws.allocate<std::uint8_t>(300000);
    REQUIRE(a);
    REQUIRE(b);
    REQUIRE(c);
    CHECK(reinterpret_cast<std::uintptr_t>(a->data()) % workspace::alignment == 0);
    CHECK(reinterpret_cast<std::uintptr_t>(b->data()) % workspace::alignment == 0);
    for (float f : *b) CHECK(f == 0.0f);
    (*a)[99999] = 7;
    (*c)[299999] = 7;
  };
  run();
  const auto blocks = ws.upstream_allocations();
  CHECK(blocks >= 1);
  perch::test::allocation_scope scope;
  run();
  run();
  CHECK(scope.count() == 0);
  CHECK(ws.upstream_allocations() == blocks);
  CHECK(ws.high_water() >= workspace::footprint<std::int32_t>(100000) +
                              workspace::footprint<float>(5000) +
                              workspace::footprint<std::uint8_t>(300000));
}

TEST_CASE("workspace: reserve makes one block that serves everything") {
  workspace ws;
  const std::size_t need = workspace::footprint<double>(1000) + workspace::footprint<char>(10);
  REQUIRE(ws.reserve(need));
  CHECK(ws.capacity() >= need);
  perch::test::allocation_scope scope;
  REQUIRE(ws.allocate<double>(1000));
  REQUIRE(ws.allocate<char>(10));
  CHECK(scope.count() == 0);
  CHECK(ws.used() == need);
}

TEST_CASE("workspace: a borrowed buffer never allocates and says how much it needs") {
  alignas(64) std::array<std::byte, 1024> buffer{};
  workspace ws{std::span<std::byte>(buffer)};
  CHECK(!ws.owns_memory());
  perch::test::allocation_scope scope;
  auto a = ws.allocate<std::uint32_t>(128);  // 512 bytes
  REQUIRE(a);
  CHECK(static_cast<void*>(a->data()) == static_cast<void*>(buffer.data()));
  auto b = ws.allocate<std::uint32_t>(200);  // 800 bytes: does not fit
  REQUIRE(!b);
  CHECK(b.error().code == errc::workspace_too_small);
  CHECK(b.error().needed == 512 + workspace::footprint<std::uint32_t>(200));
  CHECK(scope.count() == 0);
  CHECK(ws.reserve(4096).error().needed == 4096);
}

TEST_CASE("workspace: mark and rewind release temporaries") {
  workspace ws;
  REQUIRE(ws.allocate<int>(10));
  const auto used = ws.used();
  const auto mark = ws.mark();
  REQUIRE(ws.allocate<int>(1000));
  CHECK(ws.used() > used);
  ws.rewind(mark);
  CHECK(ws.used() == used);
}

TEST_CASE("workspace: takes any std::pmr::memory_resource") {
  std::array<std::byte, 1 << 18> arena{};
  std::pmr::monotonic_buffer_resource resource(arena.data(), arena.size(),
                                              std::pmr::null_memory_resource());
  workspace ws(&resource);
  perch::test::allocation_scope scope;
  REQUIRE(ws.allocate<std::uint16_t>(1000));
  CHECK(ws.upstream_allocations() == 1);
  CHECK(scope.count() == 0);
}

TEST_CASE("workspace: absurd sizes fail cleanly") {
  workspace ws;
  auto r = ws.allocate<std::uint64_t>(std::size_t{1} << 62);
  REQUIRE(!r);
  CHECK(r.error().code == errc::size_overflow);
  auto empty = ws.allocate<int>(0);
  REQUIRE(empty);
  CHECK(empty->empty());
}
