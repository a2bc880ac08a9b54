# Install rules of the core library: headers, the static or shared library,
# and the CMake package `stvd` (config, version and exported targets), so that
# a consumer writes
#   find_package(stvd REQUIRED)
#   target_link_libraries(app PRIVATE stvd::stvd)
# Optional components (the ITK adapter, ...) are added with
# stvd_install_component(); how is described in cmake/StvdPackaging.cmake.

include(CMakePackageConfigHelpers)
include(${PROJECT_SOURCE_DIR}/cmake/StvdPackaging.cmake)

install(TARGETS stvd EXPORT stvdTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Every public header, including stvd/detail/ (used by the inline templates
# and by propagation/propagation_definition.hpp for user-defined norms).
install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/include/stvd
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  FILES_MATCHING PATTERN "*.hpp")
install(EXPORT stvdTargets
  NAMESPACE stvd::
  FILE stvdTargets.cmake
  DESTINATION ${STVD_INSTALL_CMAKEDIR})

configure_package_config_file(
  ${PROJECT_SOURCE_DIR}/cmake/stvdConfig.cmake.in
  ${PROJECT_BINARY_DIR}/stvd_package/stvdConfig.cmake
  INSTALL_DESTINATION ${STVD_INSTALL_CMAKEDIR})
# Before 1.0 a minor release may change the API, so only the same major.minor
# version satisfies a request.
write_basic_package_version_file(
  ${PROJECT_BINARY_DIR}/stvd_package/stvdConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/stvd_package/stvdConfig.cmake
  ${PROJECT_BINARY_DIR}/stvd_package/stvdConfigVersion.cmake
  DESTINATION ${STVD_INSTALL_CMAKEDIR})

# pkg-config: `pkg-config --cflags --libs stvd` for builds without CMake (the
# core only; the ITK adapter needs ITK's own flags, which only CMake has).
file(RELATIVE_PATH STVD_PC_PREFIX_FROM_PCDIR "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" STVD_PC_PREFIX_FROM_PCDIR "${STVD_PC_PREFIX_FROM_PCDIR}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/stvd.pc.in ${PROJECT_BINARY_DIR}/stvd_package/stvd.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/stvd_package/stvd.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
