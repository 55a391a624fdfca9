# SPDX-License-Identifier: BSL-1.0
cmake_policy(SET CMP0007 NEW)
# Checks a firmware image: no allocator, exception or RTTI symbol in it, and text + data
# (flash) and data + bss (RAM) within the budgets. Prints the image's sizes.
# -DIMAGE -DNM -DSIZE -DFLASH_BUDGET -DRAM_BUDGET
# Mangled names (no brackets to upset CMake's lists): operator new/new[]/delete/delete[],
# typeinfo objects and names, anything in std::pmr.
execute_process(COMMAND "${NM}" "${IMAGE}" OUTPUT_VARIABLE symbols RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${IMAGE}")
endif()
string(REPLACE "\n" ";" symbols "${symbols}")
list(FILTER symbols INCLUDE REGEX
  "_Znw|_Zna|_Zdl|_Zda|malloc|_sbrk|__cxa_throw|__cxa_allocate_exception|_ZTI|_ZTS|3pmr")
if(symbols)
  string(REPLACE ";" "\n" symbols "${symbols}")
  message(FATAL_ERROR "firmware image links what it must not:\n${symbols}")
endif()
execute_process(COMMAND "${SIZE}" "${IMAGE}" OUTPUT_VARIABLE table RESULT_VARIABLE status)
message("${table}")
string(REGEX MATCH "\n *([0-9]+)[ \t]+([0-9]+)[ \t]+([0-9]+)" row "${table}")
if(NOT row)
  message(FATAL_ERROR "cannot read ${SIZE}'s output")
endif()
math(EXPR flash "${CMAKE_MATCH_1} + ${CMAKE_MATCH_2}")
math(EXPR ram "${CMAKE_MATCH_2} + ${CMAKE_MATCH_3}")
message("flash ${flash} of ${FLASH_BUDGET} bytes, RAM ${ram} of ${RAM_BUDGET} bytes")
if(flash GREATER FLASH_BUDGET OR ram GREATER RAM_BUDGET)
  message(FATAL_ERROR "firmware image over budget")
endif()
