// SPDX-License-Identifier: BSL-1.0
/// \file
/// `workspace`: the scratch memory every perch algorithm draws from, reused across calls so a
/// drone running at frame rate allocates nothing after its first frame.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory_resource>
#include <new>
#include <span>
#include <type_traits>

#include "perch/core/result.hpp"

#if defined(__linux__) && !defined(PERCH_NO_HUGE_PAGE_HINT)
#include <sys/mman.h>
#endif

namespace perch {

namespace detail {

/// Marks the whole 2 MiB pages inside [memory, memory + bytes) for transparent huge pages
/// (Linux; nothing elsewhere).
inline void hint_huge_pages(void* memory, std::size_t bytes) noexcept {
#if defined(__linux__) && !defined(PERCH_NO_HUGE_PAGE_HINT)
  constexpr std::uintptr_t page = std::uintptr_t{2} << 20;
  const auto start = reinterpret_cast<std::uintptr_t>(memory);
  const std::uintptr_t begin = (start + page - 1) / page * page;
  const std::uintptr_t end = (start + bytes) / page * page;
  if (end > begin) (void)::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)memory;
  (void)bytes;
#endif
}

/// An owning workspace's blocks from a `std::pmr::memory_resource` (the context), reached only
/// through the function pointers an owning constructor stores: the bump allocator itself names
/// no allocator, so a firmware image that only borrows a buffer links no heap, no `pmr` and no
/// exception or RTTI support.
struct pmr_blocks {
  static void* take(void* resource, std::size_t bytes, std::size_t alignment) noexcept {
    return static_cast<std::pmr::memory_resource*>(resource)->allocate(bytes, alignment);
  }
  static void* take_huge(void* resource, std::size_t bytes, std::size_t alignment) noexcept {
    void* memory = take(resource, bytes, alignment);
    if (memory != nullptr) hint_huge_pages(memory, bytes);
    return memory;
  }
  static void give_back(void* resource, void* block, std::size_t bytes,
                        std::size_t alignment) noexcept {
    static_cast<std::pmr::memory_resource*>(resource)->deallocate(block, bytes, alignment);
  }
};

/// The default owning workspace's blocks: the heap through the non-throwing aligned `new`, so
/// that running out of memory is `errc::out_of_memory`, not an exception escaping a `noexcept`
/// function (`std::pmr::new_delete_resource()` throws `std::bad_alloc`, which would end in
/// `std::terminate`), and hinted for huge pages.
struct heap_blocks {
  static void* take(void*, std::size_t bytes, std::size_t alignment) noexcept {
    void* memory = ::operator new(bytes, std::align_val_t{alignment}, std::nothrow);
    if (memory != nullptr) hint_huge_pages(memory, bytes);
    return memory;
  }
  static void give_back(void*, void* block, std::size_t, std::size_t alignment) noexcept {
    ::operator delete(block, std::align_val_t{alignment}, std::nothrow);
  }
};

}  // namespace detail

/// A bump allocator over one or more memory blocks.
///
/// - Owning (`workspace{}` or `workspace{resource}`): blocks come from the heap (the
///   non-throwing `new`: out of memory is `errc::out_of_memory`) or from a
///   `std::pmr::memory_resource` (which must not throw: `find_perch` is `noexcept`, so an
///   exception from it ends in `std::terminate`; return memory or fail in your own way).
///   `reset()` rewinds without freeing, so a
///   call that repeats the previous call's requests is served from the same blocks: no
///   allocation after warm-up. `reserve(bytes)` pre-sizes one block (use the stage's size query).
///   On Linux, the heap's blocks (and `new_delete_resource()`'s) are marked for transparent
///   huge pages (`madvise(MADV_HUGEPAGE)` on their whole 2 MiB pages; a hint, used when
///   /sys/kernel/mm/transparent_hugepage/enabled is `madvise` or `always`): the distance and
///   skeleton stages touch a large frame's pixels all over it, and with 4 KiB pages their time
///   goes to TLB misses as much as to cache misses. `PERCH_NO_HUGE_PAGE_HINT` turns it off.
/// - Borrowing (`workspace{std::span<std::byte>}`): serves only from the caller's buffer and
///   never allocates; a request that does not fit fails with `errc::workspace_too_small`, whose
///   `error::needed` says how many bytes the buffer needed at least.
///
/// The owning constructors are the only code that names an allocator; a program that only
/// borrows never instantiates them (its image holds no `operator new`, `malloc` or `pmr`).
///
/// Every allocation is aligned to, and rounded up to, `alignment` (64 bytes), so the bytes a
/// sequence of requests needs is the sum of `footprint<T>(n)`: size queries are exact.
/// Objects handed out must be trivially destructible: the workspace never runs destructors.
/// Not thread-safe: one workspace per thread.
class workspace {
 public:
  static constexpr std::size_t alignment = 64;
  static constexpr std::size_t max_blocks = 32;
  static constexpr std::size_t min_block_bytes = std::size_t{64} << 10;
  /// The largest single request: 1 TiB, or half the address space where `size_t` is narrower,
  /// so that rounding and summing request sizes never wraps.
  static constexpr std::size_t max_request_bytes =
      std::numeric_limits<std::size_t>::max() / 2 < (std::uint64_t{1} << 40)
          ? std::numeric_limits<std::size_t>::max() / 2
          : static_cast<std::size_t>(std::uint64_t{1} << 40);

  /// Bytes `n` objects of `T` take in a workspace (rounded up to `alignment`); exact for every
  /// `n` that `allocate` accepts (`n * sizeof(T) <= max_request_bytes`).
  template <class T>
  [[nodiscard]] static constexpr std::size_t footprint(std::size_t n) noexcept {
    return round_up(n * sizeof(T));
  }

  /// An owning workspace on the heap (non-throwing aligned `new`), its blocks hinted for huge
  /// pages on Linux.
  workspace() noexcept
      : take_(&detail::heap_blocks::take), give_back_(&detail::heap_blocks::give_back) {}

  /// An owning workspace drawing blocks from `upstream` (never null).
  explicit workspace(std::pmr::memory_resource* upstream) noexcept
      : upstream_(upstream),
        take_(upstream == std::pmr::new_delete_resource() ? &detail::pmr_blocks::take_huge
                                                          : &detail::pmr_blocks::take),
        give_back_(&detail::pmr_blocks::give_back) {
    PERCH_ASSERT(upstream != nullptr, "workspace: null memory resource");
  }

  /// A workspace that borrows `buffer` and never allocates.
  explicit workspace(std::span<std::byte> buffer) noexcept {
    const auto address = reinterpret_cast<std::uintptr_t>(buffer.data());
    const std::size_t skip = (alignment - address % alignment) % alignment;
    if (buffer.data() != nullptr && buffer.size() > skip) {
      blocks_[0] = {buffer.data() + skip, round_down(buffer.size() - skip)};
      block_count_ = blocks_[0].size > 0 ? 1 : 0;
    }
  }

  workspace(const workspace&) = delete;
  workspace& operator=(const workspace&) = delete;
  workspace(workspace&&) = delete;
  workspace& operator=(workspace&&) = delete;
  ~workspace() { release(); }

  /// `count` objects of trivially destructible `T`, default-initialised (indeterminate for
  /// scalars: write before reading), valid until `reset()` or a `rewind` past them.
  template <class T>
  [[nodiscard]] result<std::span<T>> allocate(std::size_t count) noexcept {
    static_assert(std::is_trivially_destructible_v<T>, "workspace never runs destructors");
    static_assert(alignof(T) <= alignment, "over-aligned type");
    if (count > max_request_bytes / sizeof(T)) return fail(errc::size_overflow, "workspace");
    if (count == 0) return std::span<T>{};
    auto bytes = allocate_bytes(footprint<T>(count));
    PERCH_TRY(all_ok(bytes));
    T* first = ::new (static_cast<void*>(*bytes)) T[count];
    return std::span<T>{first, count};
  }

  /// Like `allocate`, with every object value-initialised (zero for scalars).
  template <class T>
  [[nodiscard]] result<std::span<T>> allocate_zeroed(std::size_t count) noexcept {
    auto span = allocate<T>(count);
    if (span)
      for (T& item : *span) item = T{};
    return span;
  }

  /// Where the next allocation would start; `rewind` to it to free everything allocated since.
  struct checkpoint {
    std::size_t block = 0;
    std::size_t offset = 0;
  };
  [[nodiscard]] checkpoint mark() const noexcept { return {current_, offset_}; }
  void rewind(checkpoint c) noexcept {
    PERCH_ASSERT(c.block < current_ || (c.block == current_ && c.offset <= offset_),
                 "workspace::rewind past the current position");
    current_ = c.block;
    offset_ = c.offset;
  }

  /// Frees everything handed out (keeps the memory).
  void reset() noexcept { rewind({}); }

  /// Makes sure one block holds at least `bytes`, so a call needing that many never allocates.
  /// Owning: frees and replaces all blocks if needed (only between calls: must be reset).
  /// Borrowing: fails with `workspace_too_small` if the buffer is smaller.
  [[nodiscard]] status reserve(std::size_t bytes) noexcept {
    bytes = round_up(bytes);
    if (block_count_ == 1 && blocks_[0].size >= bytes) return {};
    if (!owns_memory()) {
      if (capacity() >= bytes) return {};
      return fail(errc::workspace_too_small, "workspace::reserve", bytes);
    }
    PERCH_ASSERT(current_ == 0 && offset_ == 0, "workspace::reserve while memory is in use");
    const std::size_t total = capacity() > bytes ? capacity() : bytes;
    release();
    return add_block(total);
  }

  /// Bytes the workspace holds in all its blocks.
  [[nodiscard]] std::size_t capacity() const noexcept {
    std::size_t total = 0;
    for (std::size_t i = 0; i < block_count_; ++i) total += blocks_[i].size;
    return total;
  }
  /// Bytes in use now (block tails skipped over count as used).
  [[nodiscard]] std::size_t used() const noexcept {
    std::size_t total = offset_;
    for (std::size_t i = 0; i < current_ && i < block_count_; ++i) total += blocks_[i].size;
    return total;
  }
  /// The most bytes ever in use at once: the buffer size a firmware user should give.
  [[nodiscard]] std::size_t high_water() const noexcept { return high_water_; }
  /// Number of blocks taken from the upstream resource so far (0 for a borrowing workspace).
  [[nodiscard]] std::size_t upstream_allocations() const noexcept { return upstream_count_; }
  [[nodiscard]] bool owns_memory() const noexcept { return take_ != nullptr; }

 private:
  struct block {
    std::byte* data = nullptr;
    std::size_t size = 0;
  };

  static constexpr std::size_t round_up(std::size_t n) noexcept {
    return (n + alignment - 1) / alignment * alignment;
  }
  static constexpr std::size_t round_down(std::size_t n) noexcept {
    return n / alignment * alignment;
  }

  result<std::byte*> allocate_bytes(std::size_t bytes) noexcept {
    const checkpoint entry = mark();
    while (current_ < block_count_) {
      if (blocks_[current_].size - offset_ >= bytes) {
        std::byte* out = blocks_[current_].data + offset_;
        offset_ += bytes;
        note_use();
        return out;
      }
      ++current_;  // the rest of this block is skipped; later blocks are larger
      offset_ = 0;
    }
    if (!owns_memory()) {
      current_ = entry.block;
      offset_ = entry.offset;
      const std::size_t needed = used() > max_request_bytes ? used() : used() + bytes;
      return fail(errc::workspace_too_small, "workspace", needed);
    }
    const std::size_t grow = capacity() > min_block_bytes ? capacity() : min_block_bytes;
    PERCH_TRY(add_block(bytes > grow ? bytes : grow));
    return allocate_bytes(bytes);
  }

  status add_block(std::size_t bytes) noexcept {
    if (block_count_ == max_blocks) return fail(errc::out_of_memory, "workspace: too many blocks");
    void* memory = take_(upstream_, bytes, alignment);
    if (memory == nullptr) return fail(errc::out_of_memory, "workspace");
    blocks_[block_count_++] = {static_cast<std::byte*>(memory), bytes};
    ++upstream_count_;
    return {};
  }

  void note_use() noexcept {
    const std::size_t now = used();
    if (now > high_water_) high_water_ = now;
  }

  void release() noexcept {
    if (owns_memory()) {
      for (std::size_t i = 0; i < block_count_; ++i)
        give_back_(upstream_, blocks_[i].data, blocks_[i].size, alignment);
      block_count_ = 0;
    }
    current_ = 0;
    offset_ = 0;
  }

  // Owning only: the upstream and how to take blocks from it and give them back.
  void* upstream_ = nullptr;
  void* (*take_)(void*, std::size_t, std::size_t) noexcept = nullptr;
  void (*give_back_)(void*, void*, std::size_t, std::size_t) noexcept = nullptr;
  std::array<block, max_blocks> blocks_{};
  std::size_t block_count_ = 0;
  std::size_t current_ = 0;
  std::size_t offset_ = 0;
  std::size_t high_water_ = 0;
  std::size_t upstream_count_ = 0;
};

}  // namespace perch
