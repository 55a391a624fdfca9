// SPDX-License-Identifier: BSL-1.0
/// \file
/// `find_perch` for every built-in platform with every scale policy, on 8-bit mask views with
/// the default skeleton, compiled once (find_perch_instances.cpp, the CMake target
/// perch_find_perch_instances) for the tests and the perch tool. A translation unit that
/// includes this header uses those copies instead of compiling the whole pipeline again
/// (explicit instantiation declarations, C++20 [temp.explicit]): a build-time saving only; the
/// code is the same, compiled with the same flags and with perch's assertions on, as the tests
/// and the tool are. Benchmarks and users' code do not include it.
#pragma once

#include <cstdint>

#include "perch/pli.hpp"

/// Calls X(platform, scale policy) for each instance (each fact once: the declarations below and
/// the definitions in find_perch_instances.cpp expand this list).
#define PERCH_FIND_PERCH_INSTANCES(X)                                                     \
  X(tendon_claw, fixed_scale)                                                             \
  X(tendon_claw, trunk_prior)                                                             \
  X(tendon_claw, depth_scale)                                                             \
  X(tensile_tether, fixed_scale)                                                          \
  X(tensile_tether, trunk_prior)                                                          \
  X(tensile_tether, depth_scale)                                                          \
  X(metamorphic_quadrotor, fixed_scale)                                                   \
  X(metamorphic_quadrotor, trunk_prior)                                                   \
  X(metamorphic_quadrotor, depth_scale)                                                   \
  X(ornithopter, fixed_scale)                                                             \
  X(ornithopter, trunk_prior)                                                             \
  X(ornithopter, depth_scale)                                                             \
  X(treecreeper, fixed_scale)                                                             \
  X(treecreeper, trunk_prior)                                                             \
  X(treecreeper, depth_scale)

/// The signature of the instance for `Platform` and `Scale`.
#define PERCH_FIND_PERCH_INSTANCE(Platform, Scale)                                        \
  result<perch_result> find_perch(const image_view<const std::uint8_t>&, const Platform&, \
                                  const Scale&, const medial_axis&, workspace&,           \
                                  const perch_options&) noexcept;

namespace perch {

#define PERCH_FIND_PERCH_EXTERN(Platform, Scale) extern template PERCH_FIND_PERCH_INSTANCE(Platform, Scale)
PERCH_FIND_PERCH_INSTANCES(PERCH_FIND_PERCH_EXTERN)
#undef PERCH_FIND_PERCH_EXTERN

}  // namespace perch
