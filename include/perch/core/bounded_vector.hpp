// SPDX-License-Identifier: BSL-1.0
/// \file
/// `bounded_vector<T>`: a vector over caller-provided storage with a fixed capacity. Growth past
/// the capacity is a status (`errc::capacity_exceeded`), never a reallocation or a silent drop.
#pragma once

#include <cstddef>
#include <span>
#include <type_traits>

#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// Fixed-capacity vector of trivially destructible, copy-assignable `T` over a span (usually from
/// a `workspace`).
template <class T>
class bounded_vector {
  static_assert(std::is_trivially_destructible_v<T> && std::is_copy_assignable_v<T>);

 public:
  using value_type = T;
  using iterator = T*;
  using const_iterator = const T*;

  constexpr bounded_vector() noexcept = default;
  constexpr explicit bounded_vector(std::span<T> storage) noexcept : storage_(storage) {}

  /// A vector of `capacity` slots drawn from `ws`.
  [[nodiscard]] static result<bounded_vector> make(workspace& ws, std::size_t capacity) noexcept {
    auto storage = ws.allocate<T>(capacity);
    PERCH_TRY(all_ok(storage));
    return bounded_vector(*storage);
  }

  /// Appends `item`; fails with `capacity_exceeded` (needed = size + 1) when full.
  [[nodiscard]] constexpr status push_back(const T& item) noexcept {
    if (size_ == storage_.size()) return fail(errc::capacity_exceeded, "bounded_vector", size_ + 1);
    storage_[size_++] = item;
    return {};
  }
  constexpr void pop_back() noexcept {
    PERCH_ASSERT(size_ > 0, "bounded_vector::pop_back on empty");
    --size_;
  }
  constexpr void clear() noexcept { size_ = 0; }
  /// Shrinks to `n` (≤ size).
  constexpr void truncate(std::size_t n) noexcept {
    PERCH_ASSERT(n <= size_, "bounded_vector::truncate beyond size");
    size_ = n;
  }

  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
  [[nodiscard]] constexpr std::size_t capacity() const noexcept { return storage_.size(); }
  [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] constexpr T& operator[](std::size_t i) noexcept {
    PERCH_ASSERT(i < size_, "bounded_vector: index out of range");
    return storage_[i];
  }
  [[nodiscard]] constexpr const T& operator[](std::size_t i) const noexcept {
    PERCH_ASSERT(i < size_, "bounded_vector: index out of range");
    return storage_[i];
  }
  [[nodiscard]] constexpr T& back() noexcept { return (*this)[size_ - 1]; }
  [[nodiscard]] constexpr T* begin() noexcept { return storage_.data(); }
  [[nodiscard]] constexpr T* end() noexcept { return storage_.data() + size_; }
  [[nodiscard]] constexpr const T* begin() const noexcept { return storage_.data(); }
  [[nodiscard]] constexpr const T* end() const noexcept { return storage_.data() + size_; }
  [[nodiscard]] constexpr std::span<T> items() noexcept { return storage_.first(size_); }
  [[nodiscard]] constexpr std::span<const T> items() const noexcept {
    return std::span<const T>(storage_).first(size_);
  }

 private:
  std::span<T> storage_{};
  std::size_t size_ = 0;
};

}  // namespace perch
