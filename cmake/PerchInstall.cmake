# SPDX-License-Identifier: BSL-1.0
# Install rules: headers, the exported perch::perch target, and a relocatable package config.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PERCH_CMAKE_DIR "${CMAKE_INSTALL_DATADIR}/cmake/perch")
if(CMAKE_VERSION VERSION_GREATER_EQUAL 3.23)
  install(TARGETS perch EXPORT perchTargets FILE_SET HEADERS)
else()
  install(TARGETS perch EXPORT perchTargets)
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/perch" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
endif()
install(EXPORT perchTargets NAMESPACE perch:: DESTINATION "${PERCH_CMAKE_DIR}")

# perch::png, the optional component (its own export set, so perch::perch never needs zlib).
if(TARGET perch_png)
  install(TARGETS perch_png EXPORT perchPngTargets ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}")
  install(FILES "${PROJECT_SOURCE_DIR}/examples/png/png/png.hpp" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/png")
  install(EXPORT perchPngTargets NAMESPACE perch:: DESTINATION "${PERCH_CMAKE_DIR}")
endif()
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/perchConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/perchConfig.cmake" INSTALL_DESTINATION "${PERCH_CMAKE_DIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/perchConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion ARCH_INDEPENDENT)
install(FILES "${PROJECT_BINARY_DIR}/perchConfig.cmake" "${PROJECT_BINARY_DIR}/perchConfigVersion.cmake"
  DESTINATION "${PERCH_CMAKE_DIR}")
