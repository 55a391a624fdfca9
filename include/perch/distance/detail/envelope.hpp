/// \file
/// Private helpers of the distance stage: the lower envelope of parabolas of one foreground run
/// (the second phase of Meijster, Roerdink & Hesselink 2000), and a direct search that gives the
/// same distances on short runs.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

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

/// Runs of at most this many sites (thin limbs crossed by a row) take `nearest_sites_short`
/// (measured: EDT of the 1920×1080 tree mask 1.91 → 1.74 ms; 12, 20, 48 and 64 gain less).
inline constexpr int short_run_sites = 32;

/// The minimum of (u − i)² + g[i]² over the sites i of a short run (`m` sites, the first and last
/// background), written to `out[u]` for u in [1, m − 1): a search outward from u, which stops
/// once the offset alone costs as much as the best so far (the background sites 0 and m − 1
/// bound it from the start). No division; for short runs cheaper than building the envelope.
/// `m` ≤ `short_run_sites`.
inline void nearest_sites_short(std::uint32_t* g, int m, std::uint32_t* out) noexcept {
  // Heights are capped at 2^16 − 1 before squaring (a column 2^16 pixels deep would wrap to
  // 0): a run has at most 32 sites, so no capped site can be nearest (best ≤ 16²).
  constexpr std::uint32_t high = 0xFFFFu;
  for (int u = 1; u + 1 < m; ++u) g[u] = g[u] < high ? g[u] : high;
  for (int u = 1; u + 1 < m; ++u) {
    const auto left = static_cast<std::uint32_t>(u);
    const auto right = static_cast<std::uint32_t>(m - 1 - u);
    std::uint32_t best = left < right ? left * left : right * right;
    for (int k = 0; static_cast<std::uint32_t>(k * k) < best; ++k) {
      const auto k2 = static_cast<std::uint32_t>(k * k);
      const std::uint32_t below = g[u - k];
      const std::uint32_t above = g[u + k];
      const std::uint32_t v = k2 + (below < above ? below * below : above * above);
      best = v < best ? v : best;
    }
    out[u] = best;
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
