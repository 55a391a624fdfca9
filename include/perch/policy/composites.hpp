// SPDX-License-Identifier: BSL-1.0
/// \file
/// Composites: `all_of<...>` (a constraint made of constraints) and `weighted_sum<...>` (a
/// scorer made of scorers). Both model the concepts they combine, so they nest.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>
#include <tuple>
#include <utility>

#include "perch/policy/concepts.hpp"

namespace perch {

/// A window passes `all_of<Cs...>` when it passes every part. Diagnostics see the parts (leaves)
/// in declaration order, flattened through nested `all_of`s.
template <Constraint... Cs>
struct all_of {
  using is_composite_constraint = void;
  static constexpr std::string_view name = "all_of";
  std::tuple<Cs...> parts{};

  constexpr all_of() noexcept = default;
  constexpr explicit all_of(Cs... cs) noexcept : parts(std::move(cs)...) {}

  [[nodiscard]] constexpr status validate() const noexcept {
    status out{};
    std::apply([&out](const auto&... part) {
      ((out = out ? validate_policy(part) : out), ...);
    }, parts);
    return out;
  }
};

/// Number of leaf constraints in `C` (1 unless `C` is a composite).
template <class C>
inline constexpr std::size_t leaf_count = 1;
template <Constraint... Cs>
inline constexpr std::size_t leaf_count<all_of<Cs...>> = (std::size_t{0} + ... + leaf_count<Cs>);

/// Calls `fn(leaf, index)` for every leaf constraint of `c`, in order.
template <Constraint C, class Fn>
constexpr void for_each_leaf(const C& c, Fn&& fn, std::size_t first = 0) noexcept {
  if constexpr (CompositeConstraint<C>) {
    std::size_t index = first;
    std::apply([&](const auto&... part) {
      ((for_each_leaf(part, fn, index), index += leaf_count<std::remove_cvref_t<decltype(part)>>),
       ...);
    }, c.parts);
  } else {
    fn(c, first);
  }
}

/// The names of the leaves of `C`, in order (for diagnostics).
template <Constraint C>
[[nodiscard]] constexpr std::array<std::string_view, leaf_count<C>> leaf_names(const C& c) noexcept {
  std::array<std::string_view, leaf_count<C>> names{};
  for_each_leaf(c, [&names](const auto& leaf, std::size_t i) {
    names[i] = std::remove_cvref_t<decltype(leaf)>::name;
  });
  return names;
}

/// A penalty that is the weighted sum of other scorers' penalties: P = Σ wᵢ·Sᵢ(m).
/// Weights must be ≥ 0 and sum to 1 (within 1e-4), so a sum of [0, 1] penalties stays in [0, 1].
template <Scorer... Ss>
struct weighted_sum {
  static constexpr std::string_view name = "weighted_sum";
  std::array<float, sizeof...(Ss)> weights{};
  std::tuple<Ss...> parts{};

  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    float total = 0;
    std::size_t i = 0;
    std::apply([&](const auto&... part) { ((total += weights[i++] * part(m)), ...); }, parts);
    return total;
  }
  [[nodiscard]] status validate() const noexcept {
    float sum = 0;
    for (const float w : weights) {
      if (!(w >= 0 && std::isfinite(w))) return fail(errc::weights_not_normalised, "weighted_sum");
      sum += w;
    }
    if (std::abs(sum - 1.0f) > 1e-4f) return fail(errc::weights_not_normalised, "weighted_sum");
    status out{};
    std::apply([&out](const auto&... part) {
      ((out = out ? validate_policy(part) : out), ...);
    }, parts);
    return out;
  }
};

}  // namespace perch
