// SPDX-License-Identifier: BSL-1.0
/// \file
/// Views over Eigen matrices in place: rows of the image are rows of a row-major matrix (or
/// columns of a column-major one, giving the transposed image). Eigen is at the boundary only.
#pragma once

#include <Eigen/Core>
#include <type_traits>

#include "perch/core/image_view.hpp"

namespace perch {

/// A view of a row-major Eigen matrix or map: width = cols, height = rows, stride = outerStride.
template <class Derived>
  requires(static_cast<bool>(Derived::IsRowMajor) && Derived::InnerStrideAtCompileTime == 1)
[[nodiscard]] auto view_of(Eigen::PlainObjectBase<Derived>& m) noexcept {
  return image_view<typename Derived::Scalar>(m.data(), static_cast<int>(m.cols()),
                                              static_cast<int>(m.rows()), m.outerStride());
}

/// A view of a row-major `Eigen::Map` (mutable or const).
template <class Plain, int Options, class Stride>
  requires(static_cast<bool>(Plain::IsRowMajor))
[[nodiscard]] auto view_of(const Eigen::Map<Plain, Options, Stride>& m) noexcept {
  using pointer = decltype(m.data());
  using scalar = std::remove_pointer_t<pointer>;
  return image_view<scalar>(m.data(), static_cast<int>(m.cols()), static_cast<int>(m.rows()),
                            m.outerStride());
}

}  // namespace perch
