// SPDX-License-Identifier: BSL-1.0
// Reset and vector table of a bare Cortex-M7 (the MPS2 AN500 board qemu-system-arm emulates):
// FPU on, .data copied, .bss zeroed, static constructors run, main, exit through the board.
#include <cstdint>

#include "board.hpp"

extern "C" {
extern std::uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[];
extern std::uint32_t __stack_top[];
using init_function = void (*)();
extern init_function __init_array_start[], __init_array_end[];
int main();
[[noreturn]] void reset_handler();
}

namespace {

[[noreturn]] void fault_handler() { board::exit(3); }

void enable_fpu() {
  auto* const cpacr = reinterpret_cast<volatile std::uint32_t*>(0xE000ED88u);
  *cpacr = *cpacr | (0xFu << 20);  // CP10 and CP11: full access
  __asm__ volatile("dsb\n\tisb" ::: "memory");
}

}  // namespace

// Written without floating point, which is off until enable_fpu has run.
extern "C" [[noreturn]] void reset_handler() {
  enable_fpu();
  for (std::uint32_t *from = __data_load, *to = __data_start; to < __data_end;) *to++ = *from++;
  for (std::uint32_t* to = __bss_start; to < __bss_end;) *to++ = 0;
  for (init_function* f = __init_array_start; f < __init_array_end; ++f) (*f)();
  board::exit(main());
}

// Initial stack pointer, reset, NMI, hard fault, memory, bus and usage faults.
__attribute__((section(".vectors"), used)) const void* const vector_table[] = {
    __stack_top,
    reinterpret_cast<const void*>(&reset_handler),
    reinterpret_cast<const void*>(&fault_handler),
    reinterpret_cast<const void*>(&fault_handler),
    reinterpret_cast<const void*>(&fault_handler),
    reinterpret_cast<const void*>(&fault_handler),
    reinterpret_cast<const void*>(&fault_handler),
};
