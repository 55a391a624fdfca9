// SPDX-License-Identifier: BSL-1.0
// ARM semihosting: `bkpt 0xab` on M-profile cores (a Cortex-M7 board under qemu-system-arm or a
// debug probe), `svc 0xab` in Thumb state on A-profile cores (qemu-arm user mode).
#include <cstdint>

#include "board.hpp"

namespace {

enum : std::uint32_t { sys_write0 = 0x04, sys_exit_extended = 0x20 };
constexpr std::uint32_t application_exit = 0x20026;

std::uint32_t semihost(std::uint32_t operation, const void* argument) noexcept {
  register std::uint32_t r0 __asm__("r0") = operation;
  register const void* r1 __asm__("r1") = argument;
#if defined(__ARM_ARCH_PROFILE) && __ARM_ARCH_PROFILE == 'M'
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
#else
  __asm__ volatile("svc 0xab" : "+r"(r0) : "r"(r1) : "memory");
#endif
  return r0;
}

}  // namespace

namespace board {

void print(const char* text) noexcept { semihost(sys_write0, text); }

void print(std::int32_t value) noexcept {
  char digits[12];
  char* p = digits + sizeof digits;
  *--p = '\0';
  const bool negative = value < 0;
  auto magnitude = negative ? 0u - static_cast<std::uint32_t>(value) : static_cast<std::uint32_t>(value);
  do {
    *--p = static_cast<char>('0' + magnitude % 10);
    magnitude /= 10;
  } while (magnitude != 0);
  if (negative) *--p = '-';
  print(p);
}

void exit(int code) noexcept {
  const std::uint32_t block[2] = {application_exit, static_cast<std::uint32_t>(code)};
  semihost(sys_exit_extended, block);
  for (;;) {
  }
}

}  // namespace board
