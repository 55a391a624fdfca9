# SPDX-License-Identifier: BSL-1.0
# Install rules: headers, the exported perch::perch target, and a relocatable package config.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PERCH_CMAKE_DIR "${CMAKE_INSTALL_DATADIR}/cmake/perch")
install(TARGETS perch EXPORT perchTargets FILE_SET HEADERS)
install(EXPORT perchTargets NAMESPACE perch:: DESTINATION "${PERCH_CMAKE_DIR}")
configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/perchConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/perchConfig.cmake" INSTALL_DESTINATION "${PERCH_CMAKE_DIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/perchConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion ARCH_INDEPENDENT)
install(FILES "${PROJECT_BINARY_DIR}/perchConfig.cmake" "${PROJECT_BINARY_DIR}/perchConfigVersion.cmake"
  DESTINATION "${PERCH_CMAKE_DIR}")
