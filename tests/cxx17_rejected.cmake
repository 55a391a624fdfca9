# SPDX-License-Identifier: BSL-1.0
# `cmake -DCXX=... -DINCLUDE=... -DEIGEN=... -DHEADER=perch/pli.hpp -P cxx17_rejected.cmake`:
# compiling HEADER as C++17 must fail with perch's one clear message, in a few lines.
file(WRITE "${CMAKE_CURRENT_BINARY_DIR}/cxx17_${NAME}.cpp" "#include <${HEADER}>\nint main() {}\n")
execute_process(
  COMMAND "${CXX}" -std=c++17 -fsyntax-only "-I${INCLUDE}" -isystem "${EIGEN}"
          "${CMAKE_CURRENT_BINARY_DIR}/cxx17_${NAME}.cpp"
  RESULT_VARIABLE result ERROR_VARIABLE errors OUTPUT_VARIABLE output)
string(REGEX MATCHALL "\n" lines "${errors}${output}")
list(LENGTH lines line_count)
if(result EQUAL 0)
  message(FATAL_ERROR "${HEADER} compiled as C++17")
endif()
if(NOT errors MATCHES "perch needs C\\+\\+20")
  message(FATAL_ERROR "no 'perch needs C++20' in:\n${errors}")
endif()
if(line_count GREATER 20)
  message(FATAL_ERROR "${line_count} lines of errors, not one clear message:\n${errors}")
endif()
message(STATUS "${HEADER} as C++17: ${line_count} lines, perch's message")
