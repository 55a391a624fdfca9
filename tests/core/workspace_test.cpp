// SPDX-License-Identifier: BSL-1.0
#include "perch/core/workspace.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <limits>
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
  auto r = ws.allocate<std::uint64_t>(std::numeric_limits<std::size_t>::max() / 4);
  REQUIRE(!r);
  CHECK(r.error().code == errc::size_overflow);
  auto empty = ws.allocate<int>(0);
  REQUIRE(empty);
  CHECK(empty->empty());
}

// AddressSanitizer's allocator reports a terabyte request as an error instead of returning null.
#if defined(__SANITIZE_ADDRESS__)
#define PERCH_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PERCH_TEST_ASAN 1
#endif
#endif
#if !defined(PERCH_TEST_ASAN)
TEST_CASE("workspace: the heap running out is a status, not an exception") {
  // A terabyte (half the address space on 32-bit targets): the default workspace's non-throwing
  // `new` returns null, and the workspace says out_of_memory. A kernel that overcommits
  // without limit (vm.overcommit_memory = 1) may hand the address space out instead.
  workspace ws;
  auto r = ws.allocate<std::byte>(workspace::max_request_bytes);
  if (r) {
    MESSAGE("the kernel handed out " << workspace::max_request_bytes << " bytes (overcommit)");
  } else {
    CHECK(r.error().code == errc::out_of_memory);
  }
  auto small = ws.allocate<int>(16);  // and the workspace still serves
  CHECK(small);
}
#endif

#if defined(__linux__) && !defined(PERCH_NO_HUGE_PAGE_HINT)
#include <sys/mman.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {
/// The VmFlags of the mapping of this process that holds `address` (/proc/self/smaps), or "".
std::string vm_flags_at(const void* address) {
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t from = 0, to = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> from >> dash >> to && dash == '-') {
      inside = at >= from && at < to;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}
}  // namespace

TEST_CASE("workspace: large blocks of the default resource are marked for huge pages (Linux)") {
  // Whether this kernel takes the hint at all (it may lack transparent huge pages).
  const std::size_t probe_bytes = std::size_t{4} << 20;
  void* mapping = ::mmap(nullptr, probe_bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                         -1, 0);
  REQUIRE(mapping != MAP_FAILED);
  const auto start = reinterpret_cast<std::uintptr_t>(mapping);
  const std::uintptr_t page = std::uintptr_t{2} << 20;
  const bool taken = ::madvise(reinterpret_cast<void*>((start + page - 1) / page * page), page,
                               MADV_HUGEPAGE) == 0;
  ::munmap(mapping, probe_bytes);
  if (std::getenv("PERCH_UNDER_EMULATION") != nullptr) {
    MESSAGE("qemu-user accepts MADV_HUGEPAGE and ignores it: nothing to check");
    return;
  }
  if (!taken) {
    MESSAGE("this kernel refuses MADV_HUGEPAGE: nothing to check");
    return;
  }
  perch::workspace ws;
  REQUIRE(ws.reserve(std::size_t{8} << 20));
  auto before = ws.allocate<std::byte>(std::size_t{3} << 20);  // 3 MiB in: inside a whole page
  auto probe = ws.allocate<std::byte>(64);
  REQUIRE(before);
  REQUIRE(probe);
  if (!std::ifstream("/proc/self/smaps")) {
    MESSAGE("no /proc/self/smaps to read the mapping's flags from: nothing to check");
    return;
  }
  const std::string flags = vm_flags_at(probe->data());
  REQUIRE(!flags.empty());
  CHECK_MESSAGE(flags.find(" hg") != std::string::npos, flags);
  // A user's resource is left as it is.
  std::pmr::monotonic_buffer_resource pool;
  perch::workspace own{&pool};
  REQUIRE(own.reserve(std::size_t{8} << 20));
  auto skipped = own.allocate<std::byte>(std::size_t{3} << 20);
  auto mine = own.allocate<std::byte>(64);
  REQUIRE(skipped);
  REQUIRE(mine);
  CHECK(vm_flags_at(mine->data()).find(" hg") == std::string::npos);
}
#endif
