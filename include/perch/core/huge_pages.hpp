// SPDX-License-Identifier: BSL-1.0
/// \file
/// `huge_page_resource`: workspace blocks in transparent huge pages, for large frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory_resource>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace perch {

/// A memory resource for an owning `workspace` (`workspace ws{&resource};`) whose blocks are
/// mapped in 2 MiB-aligned, 2 MiB-rounded pieces and marked for transparent huge pages
/// (Linux: `mmap` + `madvise(MADV_HUGEPAGE)`; used when
/// /sys/kernel/mm/transparent_hugepage/enabled is `madvise` or `always`).
///
/// Why: the medial axis and the distance transform touch a tree's pixels all over the frame
/// (the peeling goes round the whole tree once per distance level), so on large frames the
/// pipeline's time goes to TLB misses as much as to cache misses; with 2 MiB pages the
/// workspace of a 4000×3000 call (about 120 MB) needs some 60 TLB entries instead of 30 000.
/// It pays on large frames only (timings: docs/performance-log.md).
/// An owning `workspace` on the default resource now gives its own blocks the same hint on
/// Linux; this resource maps whole 2 MiB-aligned blocks itself, for setups that want that.
///
/// Without Linux it hands out ordinary aligned memory (`::operator new` with `std::nothrow`).
/// Never throws: a failed mapping returns nullptr, which `workspace` reports as `out_of_memory`.
/// Memory comes from the system, not the heap (a heap-allocation counter sees none). Compares
/// equal only to itself (recognising another instance would need RTTI).
class huge_page_resource final : public std::pmr::memory_resource {
 public:
  /// The granule blocks are aligned to and rounded up to on Linux.
  static constexpr std::size_t page_bytes = std::size_t{2} << 20;

 private:
  static constexpr std::size_t rounded(std::size_t bytes) noexcept {
    return (bytes + page_bytes - 1) / page_bytes * page_bytes;
  }

  void* do_allocate(std::size_t bytes, std::size_t alignment) noexcept override {
    if (bytes == 0) bytes = 1;
#if defined(__linux__)
    if (alignment > page_bytes || bytes > SIZE_MAX - 2 * page_bytes) return nullptr;
    const std::size_t size = rounded(bytes);
    // Map one page more than needed and trim both ends to a 2 MiB boundary.
    void* mapped = ::mmap(nullptr, size + page_bytes, PROT_READ | PROT_WRITE,
                          MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mapped == MAP_FAILED) return nullptr;
    const auto start = reinterpret_cast<std::uintptr_t>(mapped);
    const std::uintptr_t aligned = (start + page_bytes - 1) / page_bytes * page_bytes;
    if (aligned > start) ::munmap(mapped, aligned - start);
    const std::uintptr_t tail = start + size + page_bytes - (aligned + size);
    if (tail > 0) ::munmap(reinterpret_cast<void*>(aligned + size), tail);
    void* block = reinterpret_cast<void*>(aligned);
    (void)::madvise(block, size, MADV_HUGEPAGE);  // a hint: ordinary pages if refused
    return block;
#else
    return ::operator new(bytes, std::align_val_t{alignment}, std::nothrow);
#endif
  }

  void do_deallocate(void* block, std::size_t bytes, std::size_t alignment) noexcept override {
    if (block == nullptr) return;
#if defined(__linux__)
    (void)alignment;
    ::munmap(block, rounded(bytes == 0 ? 1 : bytes));
#else
    (void)bytes;
    ::operator delete(block, std::align_val_t{alignment});
#endif
  }

  bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override {
    return this == &other;
  }
};

}  // namespace perch
