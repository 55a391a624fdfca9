// SPDX-License-Identifier: BSL-1.0
#include "perch/core/image.hpp"

#include <doctest/doctest.h>

#include <cstdint>

TEST_CASE("image: owning image hands out views") {
  perch::image<std::uint16_t> img(4, 2, 3);
  CHECK(img.width() == 4);
  CHECK(img(3, 1) == 3);
  img(0, 1) = 8;
  perch::image_view<const std::uint16_t> v = img;
  CHECK(v(0, 1) == 8);
  CHECK(perch::validate_non_empty(v));
  perch::image<std::uint8_t> none(-3, 2);
  CHECK(none.width() == 0);
  CHECK(perch::validate_non_empty(none.view()).error().code == perch::errc::empty_image);
}
