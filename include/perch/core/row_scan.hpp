// SPDX-License-Identifier: BSL-1.0
/// \file
/// Rows of an image view, and scanning, counting and binarising mask rows eight one-byte pixels
/// at a time (the usual mask); used by the mask preparation, the distance transform, the
/// labeller and the clearance counter.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace perch::detail {

/// Pointer to the first pixel of row `y` of an image view.
template <class V>
[[nodiscard]] constexpr auto* row_pointer(const V& view, int y) noexcept {
  return view.data() + static_cast<std::ptrdiff_t>(y) * view.stride();
}

/// True for one-byte integral pixels: eight of them can be tested as one 64-bit word.
template <class T>
inline constexpr bool byte_pixels = sizeof(T) == 1 && std::is_integral_v<std::remove_cv_t<T>>;

#if defined(__SSE2__)
/// Bit i set where pixel i of the sixteen one-byte pixels from `p` is zero.
template <class T>
[[nodiscard]] inline unsigned zero_mask16(const T* p) noexcept {
  const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  return static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128())));
}

/// Bit i set where pixel i of the sixteen from `p` breaks a run of non-zero (`NonZero`) or zero
/// pixels.
template <bool NonZero, class T>
[[nodiscard]] inline unsigned run_breaks16(const T* p) noexcept {
  const unsigned zeros = zero_mask16(p);
  return NonZero ? zeros : ~zeros & 0xFFFFu;
}
#endif

/// `skip_words` past the first sixteen pixels: sixteen per step (with SSE2; over background,
/// 64 per step), then eight-pixel words (the classic has-a-zero-byte test), which on
/// little-endian machines stop on the first pixel that differs (the lowest flagged byte of the
/// word that breaks the run: the test is exact there), elsewhere on that word's first pixel.
template <bool NonZero, class T>
[[nodiscard]] inline int skip_stretch(const T* row, int x, int width) noexcept {
#if defined(__SSE2__)
  if constexpr (!NonZero) {
    auto load = [row](int at) {
      return _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + at));
    };
    for (; x + 64 <= width; x += 64) {
      const __m128i any = _mm_or_si128(_mm_or_si128(load(x), load(x + 16)),
                                       _mm_or_si128(load(x + 32), load(x + 48)));
      if (_mm_movemask_epi8(_mm_cmpeq_epi8(any, _mm_setzero_si128())) != 0xFFFF) break;
    }
  }
  for (; x + 16 <= width; x += 16)
    if (const unsigned breaks = run_breaks16<NonZero>(row + x); breaks != 0)
      return x + std::countr_zero(breaks);
#endif
  constexpr std::uint64_t ones = 0x0101010101010101u;
  constexpr std::uint64_t highs = 0x8080808080808080u;
  while (x + 8 <= width) {
    std::uint64_t word = 0;
    std::memcpy(&word, row + x, sizeof word);
    const std::uint64_t differs = NonZero ? (word - ones) & ~word & highs : word;
    if (differs != 0) {
      if constexpr (std::endian::native == std::endian::little)
        x += std::countr_zero(differs) / 8;
      break;
    }
    x += 8;
  }
  return x;
}

/// Skips pixels of a byte row from `x` while they are non-zero (`NonZero` true) or zero
/// (`NonZero` false), stopping on the first that differs (but see `skip_stretch` for machines
/// other than little-endian). Short runs (noise) end within the first sixteen pixels (one SSE2
/// compare, inline); longer stretches go on in `skip_stretch`.
template <bool NonZero, class T>
[[nodiscard]] inline int skip_words(const T* row, int x, int width) noexcept {
  static_assert(byte_pixels<T>);
#if defined(__SSE2__)
  if (x + 16 <= width) {
    if (const unsigned breaks = run_breaks16<NonZero>(row + x); breaks != 0)
      return x + std::countr_zero(breaks);
    x += 16;
  }
#endif
  return skip_stretch<NonZero>(row, x, width);
}

/// Index of the first non-zero pixel of `row` in [x, width), or `width`.
template <class T>
[[nodiscard]] inline int next_set(const T* row, int x, int width) noexcept {
  if constexpr (byte_pixels<T>) x = skip_words<false>(row, x, width);
  while (x < width && !static_cast<bool>(row[x])) ++x;
  return x;
}

/// Index of the first zero pixel of `row` in [x, width), or `width`.
template <class T>
[[nodiscard]] inline int next_clear(const T* row, int x, int width) noexcept {
  if constexpr (byte_pixels<T>) x = skip_words<true>(row, x, width);
  while (x < width && static_cast<bool>(row[x])) ++x;
  return x;
}

/// Calls `visit(a, b)` for each run [a, b) of non-zero pixels of `row` inside [from, to), left
/// to right (a run is cut at `from` and `to`).
template <class T, class Visit>
inline void for_each_run_between(const T* row, int from, int to, Visit&& visit) noexcept {
  for (int a = next_set(row, from, to); a < to;) {
    const int b = next_clear(row, a, to);
    visit(a, b);
    a = next_set(row, b, to);
  }
}

/// Index of the last non-zero pixel of `row` in [from, width), or `from - 1`.
template <class T>
[[nodiscard]] inline int last_set(const T* row, int from, int width) noexcept {
  int x = width - 1;
  if constexpr (byte_pixels<T>) {
#if defined(__SSE2__)
    // Sixteen pixels per step, stopping on the last non-zero one.
    for (; x - 15 >= from; x -= 16)
      if (const unsigned set = ~zero_mask16(row + x - 15) & 0xFFFFu; set != 0)
        return x - 15 + (31 - std::countl_zero(set));
#endif
    for (; x - 7 >= from; x -= 8) {
      std::uint64_t word = 0;
      std::memcpy(&word, row + x - 7, sizeof word);
      if (word != 0) {  // little-endian: the highest set bit lies in the last non-zero byte
        if constexpr (std::endian::native == std::endian::little)
          x -= std::countl_zero(word) / 8;
        break;
      }
    }
  }
  while (x >= from && !static_cast<bool>(row[x])) --x;
  return x;
}

/// 1 in each byte of `word` that is non-zero, 0 in the others (no carry crosses a byte).
[[nodiscard]] constexpr std::uint64_t nonzero_bytes(std::uint64_t word) noexcept {
  constexpr std::uint64_t lows = 0x7F7F7F7F7F7F7F7Fu;
  return ((((word & lows) + lows) | word) & ~lows) >> 7;
}

/// The sum of the bytes of a word of 0/1 bytes, by one multiplication (a portable popcount is a
/// library call without -mpopcnt).
[[nodiscard]] constexpr std::uint32_t byte_sum(std::uint64_t ones) noexcept {
  return static_cast<std::uint32_t>((ones * 0x0101010101010101u) >> 56);
}

/// Calls `f(i)` for each non-zero byte of `word` (eight pixels read from memory), i ∈ [0, 8) in
/// memory order: one step per non-zero byte on little-endian machines.
template <class F>
inline void for_each_set_byte(std::uint64_t word, F&& f) noexcept {
  if constexpr (std::endian::native == std::endian::little) {
    for (std::uint64_t ones = nonzero_bytes(word); ones != 0; ones &= ones - 1)
      f(std::countr_zero(ones) / 8);
  } else {
    for (int i = 0; i < 8; ++i)
      if (((word >> (56 - 8 * i)) & 0xFFu) != 0) f(i);
  }
}

/// The number of non-zero pixels of `src[0, width)`, 16 or 8 one-byte pixels at a time; with
/// `Store`, also writes 1 to `dst[i]` for each non-zero `src[i]` and 0 for the others.
template <bool Store, class T>
[[nodiscard]] inline std::uint32_t nonzero_pass(const T* src, std::uint8_t* dst,
                                                int width) noexcept {
  std::uint32_t count = 0;
  int x = 0;
#if defined(__SSE2__)
  if constexpr (byte_pixels<T>) {  // sixteen pixels per step (SSE2: every x86-64)
    const __m128i zero = _mm_setzero_si128();
    const __m128i one = _mm_set1_epi8(1);
    __m128i sums = zero;  // two 64-bit lanes of byte sums
    for (; x + 16 <= width; x += 16) {
      const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + x));
      const __m128i ones = _mm_andnot_si128(_mm_cmpeq_epi8(v, zero), one);
      if constexpr (Store) _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + x), ones);
      sums = _mm_add_epi64(sums, _mm_sad_epu8(ones, zero));
    }
    count += static_cast<std::uint32_t>(_mm_cvtsi128_si32(sums)) +
             static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_unpackhi_epi64(sums, sums)));
  }
#endif
  if constexpr (byte_pixels<T>) {
    for (; x + 8 <= width; x += 8) {
      std::uint64_t word = 0;
      std::memcpy(&word, src + x, sizeof word);
      word = nonzero_bytes(word);
      if constexpr (Store) std::memcpy(dst + x, &word, sizeof word);
      count += byte_sum(word);
    }
  }
  for (; x < width; ++x) {
    const std::uint8_t v = static_cast<bool>(src[x]) ? 1 : 0;
    if constexpr (Store) dst[x] = v;
    count += v;
  }
  return count;
}

/// Writes 1 to `dst[i]` for each non-zero `src[i]` and 0 for the others, i ∈ [0, width);
/// returns the number of non-zero pixels.
template <class T>
[[nodiscard]] inline std::uint32_t binarise_row(const T* src, std::uint8_t* dst,
                                                int width) noexcept {
  return nonzero_pass<true>(src, dst, width);
}

/// The number of non-zero pixels of `row[0, width)`.
template <class T>
[[nodiscard]] inline std::uint32_t count_nonzero(const T* row, int width) noexcept {
  return nonzero_pass<false>(row, nullptr, width);
}

}  // namespace perch::detail
