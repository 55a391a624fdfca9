# SPDX-License-Identifier: BSL-1.0
# Cortex-M7 (hard-float FPv5, single and double precision) bare metal with Debian's
# gcc-arm-none-eabi and libstdc++-arm-none-eabi-newlib. Programs link newlib-nano; the firmware
# example adds semihosting (rdimon) so qemu can run it and print its result.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR cortex-m7)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(PERCH_CORTEX_M7_FLAGS "-mcpu=cortex-m7 -mthumb -mfloat-abi=hard -mfpu=fpv5-d16")
set(CMAKE_C_FLAGS_INIT "${PERCH_CORTEX_M7_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${PERCH_CORTEX_M7_FLAGS} -fno-exceptions -fno-rtti -ffunction-sections -fdata-sections")
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=nano.specs -Wl,--gc-sections")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(PERCH_SIZE_TOOL arm-none-eabi-size)
