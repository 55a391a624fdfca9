# SPDX-License-Identifier: BSL-1.0
# perch_warnings: the warning flags for perch's own tests, examples and benchmarks. Never on
# perch::perch itself, so a user's build never inherits perch's warning policy.
add_library(perch_warnings INTERFACE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(perch_warnings INTERFACE
    -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wold-style-cast
    -Wnon-virtual-dtor -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
    -Wimplicit-fallthrough)
  if(PERCH_WARNINGS_AS_ERRORS)
    target_compile_options(perch_warnings INTERFACE -Werror)
  endif()
elseif(MSVC)
  target_compile_options(perch_warnings INTERFACE /W4 /permissive-)
  if(PERCH_WARNINGS_AS_ERRORS)
    target_compile_options(perch_warnings INTERFACE /WX)
  endif()
endif()
if(PERCH_FIRMWARE)
  target_compile_options(perch_warnings INTERFACE -fno-exceptions -fno-rtti)
  # GCC 12 flags std::vector's own construction as a "potential null pointer dereference" when
  # exceptions are off (operator new may then return null): a false positive in test code.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(perch_warnings INTERFACE -Wno-null-dereference)
  endif()
endif()
