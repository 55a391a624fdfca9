// SPDX-License-Identifier: BSL-1.0
// How the firmware example talks to the outside world: text out and an exit code, through ARM
// semihosting (a debugger or qemu carries them to the host).
#pragma once

#include <cstdint>

namespace board {

void print(const char* text) noexcept;
void print(std::int32_t value) noexcept;
[[noreturn]] void exit(int code) noexcept;

}  // namespace board
