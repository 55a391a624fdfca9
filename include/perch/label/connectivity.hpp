// SPDX-License-Identifier: BSL-1.0
/// \file
/// `connectivity`: which neighbours join two pixels into one component.
#pragma once

#include <cstdint>

namespace perch {

/// Which pixels count as neighbours when growing a component.
/// `four`: the 4 edge neighbours (left, right, up, down).
/// `eight`: the 4 edge neighbours and the 4 corner (diagonal) neighbours.
/// A one-pixel-thin skeleton is 8-connected; its background holes are then counted with the
/// dual connectivity, `four` (Rosenfeld 1970, "Connectivity in digital pictures", J. ACM 17).
enum class connectivity : std::uint8_t { four, eight };

}  // namespace perch
