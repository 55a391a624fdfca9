// SPDX-License-Identifier: BSL-1.0
#include "perch/core/image_view.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "support/ascii_art.hpp"

using perch::errc;
using perch::image_view;

// Concepts, positive and negative.
static_assert(perch::ImageView<image_view<const std::uint8_t>>);
static_assert(perch::BinaryView<image_view<const std::uint8_t>>);
static_assert(perch::BinaryView<image_view<const float>>);
static_assert(perch::MutableImageView<image_view<std::uint8_t>>);
static_assert(!perch::MutableImageView<image_view<const std::uint8_t>>);
static_assert(!perch::ImageView<int>);
static_assert(!perch::ImageView<std::vector<std::uint8_t>>);
struct not_testable {};
static_assert(!perch::BinaryView<image_view<const not_testable>>);
static_assert(std::is_trivially_copyable_v<image_view<std::uint8_t>>);

TEST_CASE("image_view: access, rows and sub-views over a padded buffer") {
  // A 5×3 image in a camera buffer with 3 pixels of padding per row (stride 8).
  std::array<std::uint8_t, 24> buffer{};
  for (std::size_t i = 0; i < buffer.size(); ++i) buffer[i] = static_cast<std::uint8_t>(i);
  image_view<std::uint8_t> view(buffer.data(), 5, 3, 8);
  CHECK(view.width() == 5);
  CHECK(view.height() == 3);
  CHECK(view.size() == 15);
  CHECK(view(0, 0) == 0);
  CHECK(view(4, 2) == 20);
  CHECK(view.row(1).size() == 5);
  CHECK(view.row(1)[2] == 10);
  view(1, 1) = 99;
  CHECK(buffer[9] == 99);

  image_view<const std::uint8_t> constant = view;  // mutable converts to const
  CHECK(constant(1, 1) == 99);

  auto sub = view.sub_view(1, 1, 3, 2);
  CHECK(sub.width() == 3);
  CHECK(sub.height() == 2);
  CHECK(sub.stride() == 8);
  CHECK(sub(0, 0) == 99);
  CHECK(sub(2, 1) == 19);

  auto clipped = view.sub_view(3, 2, 10, 10);
  CHECK(clipped.width() == 2);
  CHECK(clipped.height() == 1);
  auto outside = view.sub_view(7, 7, 2, 2);
  CHECK(outside.empty());
  CHECK(perch::validate(outside));
}

TEST_CASE("image_view: validate names every malformed view") {
  std::array<std::uint8_t, 16> buffer{};
  CHECK(perch::validate(image_view<std::uint8_t>(buffer.data(), 4, 4)));
  CHECK(perch::validate(image_view<std::uint8_t>()));
  CHECK(perch::validate_non_empty(image_view<std::uint8_t>()).error().code == errc::empty_image);
  CHECK(perch::validate(image_view<std::uint8_t>(nullptr, 4, 4)).error().code == errc::null_data);
  CHECK(perch::validate(image_view<std::uint8_t>(buffer.data(), -1, 4)).error().code ==
        errc::bad_dimensions);
  CHECK(perch::validate(image_view<std::uint8_t>(buffer.data(), 4, 4, 3)).error().code ==
        errc::stride_too_small);
  const int big = std::numeric_limits<int>::max();
  // Where ptrdiff_t has 32 bits, the rows of this view cannot even be addressed.
  CHECK(perch::validate(image_view<std::uint8_t>(buffer.data(), big, big)).error().code ==
        (sizeof(std::ptrdiff_t) >= 8 ? errc::image_too_large : errc::size_overflow));
  CHECK(perch::validate(image_view<std::uint8_t>(buffer.data(), 4, big,
                                                  std::numeric_limits<std::ptrdiff_t>::max() / 4))
            .error()
            .code == errc::size_overflow);
  CHECK(perch::same_size(image_view<std::uint8_t>(buffer.data(), 4, 4),
                         image_view<std::uint8_t>(buffer.data(), 2, 8))
            .error()
            .code == errc::size_mismatch);
}

TEST_CASE("image_view: fill and copy between strided views") {
  auto mask = perch::support::mask_from_ascii(R"(
    .#.
    ###
    .#.
  )");
  std::array<std::uint8_t, 5 * 4> buffer{};
  image_view<std::uint8_t> padded(buffer.data(), 3, 3, 5);
  perch::copy(mask.view(), padded);
  CHECK(perch::support::to_ascii(padded) == ".#.\n###\n.#.\n");
  perch::fill(padded.sub_view(0, 0, 1, 3), std::uint8_t{1});
  CHECK(perch::support::to_ascii(padded) == "##.\n###\n##.\n");
  CHECK(buffer[3] == 0);  // padding untouched
}
