// SPDX-License-Identifier: BSL-1.0
/// \file
/// Private helpers of the distance stage: the lower envelope of parabolas of one foreground run
/// (the second phase of Meijster, Roerdink & Hesselink 2000), and a direct search within a
/// bounded reach that gives the same distances where the limb crossed by the run is thin.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace perch::detail {

/// Floor division for a positive divisor `b` (Meijster's `div` rounds down), given `inverse`
/// ≈ 1 / b. The quotient is estimated as a · inverse in double precision (a multiplication: no
/// division on the envelope's dependency chain), truncated (an inline conversion, where
/// `std::floor` is a library call without SSE4.1) and corrected exactly with integer products.
/// The estimate is within one of the quotient for |a| < 2^52; beyond (runs tens of millions of
/// pixels long) the quotient comes from an integer division.
[[nodiscard]] inline std::int64_t floor_div(std::int64_t a, std::int64_t b, double inverse) noexcept {
  constexpr std::int64_t exact_in_double = std::int64_t{1} << 52;
  std::int64_t q = a < exact_in_double && a > -exact_in_double
                       ? static_cast<std::int64_t>(static_cast<double>(a) * inverse)
                       : a / b;
  if (q * b > a) --q;
  if ((q + 1) * b <= a) ++q;
  return q;
}

/// Fills `inverse_twice[k]` = 1 / (2k) for k in [from, to) (entry 0, never read, is 0): the
/// divisors of `envelope_sq`'s intersections, for runs of up to `to` sites.
inline void fill_inverse_twice(double* inverse_twice, std::size_t from, std::size_t to) noexcept {
  for (std::size_t k = from; k < to; ++k)
    inverse_twice[k] = k == 0 ? 0.0 : 1.0 / (2.0 * static_cast<double>(k));
}

/// Meijster et al. 2000, phase 2, for one run of `m` sites `g[0..m)` whose first and last site
/// are background (g = 0): on return `site[u]` (u in [1, m-1)) is the site minimising
/// (u − i)² + g[i]², and the function value is `best[u]`.
/// `s` and `t` are scratch of m entries; `inverse_twice` has m entries (`fill_inverse_twice`).
/// Complexity O(m).
inline void envelope_sq(const std::uint32_t* g, int m, std::int32_t* s, std::int32_t* t,
                        std::int32_t* site, const double* inverse_twice) noexcept {
  auto f = [g](std::int64_t x, std::int64_t i) noexcept {
    const std::int64_t gi = g[i];
    return (x - i) * (x - i) + gi * gi;
  };
  auto sep = [g, inverse_twice](std::int64_t i, std::int64_t u) noexcept {
    const std::int64_t gi = g[i];
    const std::int64_t gu = g[u];
    return floor_div(u * u - i * i + gu * gu - gi * gi, 2 * (u - i), inverse_twice[u - i]);
  };
  // A site higher than half the run never reaches the envelope: every point of the run lies
  // within (m − 1)/2 of a background end site, nearer than g[u] ≤ f(x, u). So it is skipped
  // (no division); across a thick limb most sites are such.
  const auto never_lowest = static_cast<std::uint32_t>(m - 1);
  int q = 0;
  s[0] = 0;
  t[0] = 0;
  for (int u = 1; u < m; ++u) {
    if (2 * std::uint64_t{g[u]} > never_lowest) continue;
    while (q >= 0 && f(t[q], s[q]) > f(t[q], u)) --q;
    if (q < 0) {
      q = 0;
      s[0] = u;
    } else {
      const std::int64_t w = 1 + sep(s[q], u);
      if (w < m) {
        ++q;
        s[q] = u;
        t[q] = static_cast<std::int32_t>(w);
      }
    }
  }
  for (int u = m - 1; u >= 0; --u) {
    site[u] = s[q];
    if (u == t[q]) --q;
  }
}

/// The largest `reach` `nearest_sites_window` takes: its sums stay below 2^15.
inline constexpr int window_reach_limit = 120;

/// Runs whose reach (see `nearest_sites_window`) is at most this take the windowed search
/// instead of the envelope: at most 2·reach + 1 steps per eight pixels (one per pixel without
/// SSE2), fewer near the run's ends, against the envelope's few per pixel with a division
/// estimate and unpredictable branches. 64 rather than 32 because it is faster on large frames;
/// longer reaches gain nothing more (A/B timings: docs/performance-log.md).
#if defined(__SSE2__)
inline constexpr int window_reach_max = 64;
#else
inline constexpr int window_reach_max = 6;
#endif

#if defined(__SSE2__)
/// k² for k in [−window_reach_limit, window_reach_limit], eight times each: one aligned load
/// per offset in `nearest_sites_window` (building the broadcast took three instructions of its
/// five-instruction step).
struct offset_squares {
  alignas(16) std::int16_t at[2 * window_reach_limit + 1][8];
  constexpr offset_squares() noexcept : at{} {
    for (int k = -window_reach_limit; k <= window_reach_limit; ++k)
      for (std::int16_t& v : at[k + window_reach_limit]) v = static_cast<std::int16_t>(k * k);
  }
};
inline constexpr offset_squares window_offset_squares{};
#endif

/// Slots of int16 scratch `nearest_sites_window` needs for a run of `m` sites.
[[nodiscard]] constexpr std::size_t window_scratch(std::size_t m) noexcept {
  return m + 2 * static_cast<std::size_t>(window_reach_limit) + 16;
}

/// The minimum of (u − i)² + g[i]² over the sites i of a run (`m` sites, the first and last
/// background), written to `out[u]` for u in [1, m − 1), when `reach` ≥ min(g[u], u, m − 1 − u)
/// for every such u. Then the nearest site of u is within `reach` of it (site u itself and
/// the two background ends already bound the minimum by that squared), and a site higher than
/// `reach` is never nearest, so heights are capped at reach + 1 and every sum fits in 16 bits:
/// each pixel takes the minimum over the offsets within its reach, eight pixels at a time with
/// SSE2 (saturating 16-bit adds and minima; the eight share the largest of their distances to
/// the run's ends, if below `reach`), or one pixel at a time within its own
/// min(g[u], u, m − 1 − u) (`Vector` false, as without SSE2).
/// No division. `reach` ≤ `window_reach_limit`; `scratch` has `window_scratch(m)` slots.
template <bool Vector = true>
inline void nearest_sites_window(const std::uint32_t* g, int m, int reach, std::int16_t* scratch,
                                 std::uint32_t* out) noexcept {
  constexpr std::int16_t far = 0x7FFF;  // a site that does not exist
  const auto cap = static_cast<std::uint32_t>(reach + 1);
  // scratch[reach + i] = min(g[i], reach + 1)² for the sites, `far` around them.
  std::int16_t* h = scratch + reach;
  for (int i = -reach; i < 0; ++i) h[i] = far;
  for (int i = 0; i < m; ++i) {
    const std::uint32_t gi = g[i] < cap ? g[i] : cap;
    h[i] = static_cast<std::int16_t>(gi * gi);
  }
  for (int i = m; i < m + reach + 8; ++i) h[i] = far;
  int u = 1;
#if defined(__SSE2__)
  if constexpr (Vector) {
    auto eight = [&](int first) {  // the minima of pixels first … first + 7
      // Offsets within the reach of these pixels only: at most `reach`, and at most the
      // largest distance from one of them to an end of the run.
      const int last = first + 7 < m - 2 ? first + 7 : m - 2;
      const int to_end = last < m - 1 - first ? last : m - 1 - first;
      const int near = to_end < reach ? to_end : reach;
      // Offset k's sums: sites from h + first + k, k² from its row of the table.
      const std::int16_t* sites = h + first - near;
      const std::int16_t(*squares)[8] = window_offset_squares.at + window_reach_limit - near;
      auto sum = [&](int k) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(sites + k));
        return _mm_adds_epi16(v, _mm_load_si128(reinterpret_cast<const __m128i*>(squares[k])));
      };
      // Two minima, over the even and the odd offsets: two chains of dependent steps.
      __m128i even = _mm_set1_epi16(far);
      __m128i odd = even;
      const int offsets = 2 * near + 1;
      int k = 0;
      for (; k + 2 <= offsets; k += 2) {
        even = _mm_min_epi16(even, sum(k));
        odd = _mm_min_epi16(odd, sum(k + 1));
      }
      even = _mm_min_epi16(even, sum(k));  // the last, odd-numbered offset
      return _mm_min_epi16(even, odd);
    };
    const __m128i zero = _mm_setzero_si128();
    auto store = [&](std::uint32_t* to, __m128i best) {
      _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm_unpacklo_epi16(best, zero));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 4), _mm_unpackhi_epi16(best, zero));
    };
    if (m - 2 >= 8) {
      for (; u + 8 <= m - 1; u += 8) store(out + u, eight(u));
      if (u < m - 1) store(out + (m - 9), eight(m - 9));  // the last eight again, overlapping
      return;
    }
    std::uint32_t few[8];
    store(few, eight(1));
    for (; u < m - 1; ++u) out[u] = few[u - 1];
    return;
  }
#endif
  for (; u < m - 1; ++u) {
    int best = far;
    // The reach of pixel u alone, min(g[u], u, m − 1 − u): its nearest site is within it.
    const auto end_near = static_cast<std::uint32_t>(u < m - 1 - u ? u : m - 1 - u);
    const int near = static_cast<int>(g[u] < end_near ? g[u] : end_near);
    for (int k = -near; k <= near; ++k) {
      const int v = h[u + k] + k * k;
      best = v < best ? v : best;
    }
    out[u] = static_cast<std::uint32_t>(best);
  }
}

/// The same envelope over real-valued heights `g` with horizontal spacing² `sx2`: the site
/// minimising sx2·(u − i)² + g[i]². Intersections are computed in double precision.
inline void envelope_real(const float* g, int m, double sx2, std::int32_t* s, std::int32_t* t,
                          std::int32_t* site) noexcept {
  auto f = [g, sx2](double x, std::int32_t i) noexcept {
    const double gi = static_cast<double>(g[i]);
    const double dx = x - static_cast<double>(i);
    return sx2 * dx * dx + gi * gi;
  };
  int q = 0;
  s[0] = 0;
  t[0] = 0;
  for (int u = 1; u < m; ++u) {
    while (q >= 0 && f(t[q], s[q]) > f(t[q], u)) --q;
    if (q < 0) {
      q = 0;
      s[0] = u;
    } else {
      const double i = s[q];
      const double uu = u;
      const double gi = static_cast<double>(g[s[q]]);
      const double gu = static_cast<double>(g[u]);
      const double x = (sx2 * (uu * uu - i * i) + gu * gu - gi * gi) / (2.0 * sx2 * (uu - i));
      // The first integer where u is strictly better, clamped to the run (x may be huge).
      const double w = x < -1.0 ? 0.0 : (x >= m ? static_cast<double>(m) : std::floor(x) + 1.0);
      if (w < m) {
        ++q;
        s[q] = u;
        t[q] = static_cast<std::int32_t>(w);
      }
    }
  }
  for (int u = m - 1; u >= 0; --u) {
    site[u] = s[q];
    if (u == t[q]) --q;
  }
}

}  // namespace perch::detail
