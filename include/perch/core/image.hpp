// SPDX-License-Identifier: BSL-1.0
/// \file
/// `image<T>`: an owning image for host code (tests, tools). Allocates, so the core never
/// includes it and firmware never needs it; every algorithm takes views.
#pragma once

#include <cstddef>
#include <vector>

#include "perch/core/image_view.hpp"

namespace perch {

/// A dense, owning `width` × `height` image of `T` (stride = width).
template <class T>
class image {
 public:
  using value_type = T;

  image() = default;
  image(int width, int height, T value = T{})
      : width_(width < 0 ? 0 : width), height_(height < 0 ? 0 : height),
        pixels_(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), value) {}

  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }
  [[nodiscard]] std::ptrdiff_t stride() const noexcept { return width_; }
  [[nodiscard]] T* data() noexcept { return pixels_.data(); }
  [[nodiscard]] const T* data() const noexcept { return pixels_.data(); }
  [[nodiscard]] T& operator()(int x, int y) noexcept { return view()(x, y); }
  [[nodiscard]] const T& operator()(int x, int y) const noexcept { return view()(x, y); }
  [[nodiscard]] auto row(int y) noexcept { return view().row(y); }
  [[nodiscard]] auto row(int y) const noexcept { return view().row(y); }

  [[nodiscard]] image_view<T> view() noexcept { return {pixels_.data(), width_, height_}; }
  [[nodiscard]] image_view<const T> view() const noexcept {
    return {pixels_.data(), width_, height_};
  }
  operator image_view<T>() noexcept { return view(); }              // NOLINT: implicit by design
  operator image_view<const T>() const noexcept { return view(); }  // NOLINT: implicit by design

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

}  // namespace perch
