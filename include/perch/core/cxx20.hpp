// SPDX-License-Identifier: BSL-1.0
/// \file
/// One clear error, not a thousand lines, when perch is compiled as C++17 or older: each main
/// header includes this first, and the missing include below ends the compilation there.
#pragma once

#if defined(_MSVC_LANG) ? _MSVC_LANG < 202002L : __cplusplus < 202002L
#error "perch needs C++20: compile with -std=c++20 (CMake: link perch::perch, which asks for cxx_std_20)"
#include <perch-needs-cxx20-compilation-stops-here>
#endif
