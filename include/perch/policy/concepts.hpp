// SPDX-License-Identifier: BSL-1.0
/// \file
/// The `Constraint` and `Scorer` concepts: what a user's policy type must provide. Checked in
/// `find_perch`'s signature (through `Platform`), so a wrong type fails at the user's call with
/// the name of the unmet requirement.
#pragma once

#include <concepts>
#include <string_view>

#include "perch/analysis/clearance.hpp"
#include "perch/analysis/measures.hpp"

namespace perch {

/// A constraint judged on a window's measures alone: `c(m)` returns by how much `m` misses
/// (in the constraint's unit, `C::unit`), 0 when it passes.
template <class C>
concept GeometricConstraint = requires(const C& c, const window_measures& m) {
  { C::name } -> std::convertible_to<std::string_view>;
  { C::unit } -> std::convertible_to<std::string_view>;
  { c(m) } noexcept -> std::convertible_to<float>;
};

/// A constraint that also looks around the window (clearance): `c(m, context)`. Evaluated only
/// for windows that passed every geometric constraint, since its queries cost more.
template <class C>
concept ContextConstraint = requires(const C& c, const window_measures& m,
                                     const window_context& context) {
  { C::name } -> std::convertible_to<std::string_view>;
  { C::unit } -> std::convertible_to<std::string_view>;
  { c(m, context) } noexcept -> std::convertible_to<float>;
};

/// A composite of constraints (`all_of<...>`): exposes its parts to diagnostics.
template <class C>
concept CompositeConstraint = requires { typename C::is_composite_constraint; };

/// Anything perch accepts as a constraint.
template <class C>
concept Constraint = GeometricConstraint<C> || ContextConstraint<C> || CompositeConstraint<C>;

/// A scorer: `s(m)` is the penalty of a viable window (lower ranks first), with a name.
template <class S>
concept Scorer = requires(const S& s, const window_measures& m) {
  { S::name } -> std::convertible_to<std::string_view>;
  { s(m) } noexcept -> std::convertible_to<float>;
};

/// Checks a policy's parameters when it has a `validate()`; policies without one are valid.
template <class P>
[[nodiscard]] constexpr status validate_policy(const P& policy) noexcept {
  if constexpr (requires { { policy.validate() } -> std::same_as<status>; }) {
    return policy.validate();
  } else {
    return {};
  }
}

}  // namespace perch
