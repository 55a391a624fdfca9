// SPDX-License-Identifier: BSL-1.0
#include "perch/core/eigen_view.hpp"

#include <doctest/doctest.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>

using row_major_u8 = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

TEST_CASE("eigen_view: a row-major matrix and a strided map are used in place") {
  row_major_u8 m = row_major_u8::Zero(3, 4);
  m(1, 2) = 5;
  auto view = perch::view_of(m);
  CHECK(view.width() == 4);
  CHECK(view.height() == 3);
  CHECK(view(2, 1) == 5);
  view(0, 2) = 9;
  CHECK(m(2, 0) == 9);

  std::array<std::uint8_t, 3 * 6> frame{};
  frame[6 + 1] = 4;
  Eigen::Map<const row_major_u8, 0, Eigen::OuterStride<>> map(frame.data(), 3, 4,
                                                              Eigen::OuterStride<>(6));
  auto mapped = perch::view_of(map);
  CHECK(mapped.stride() == 6);
  CHECK(mapped(1, 1) == 4);
  CHECK(perch::validate(mapped));
}
