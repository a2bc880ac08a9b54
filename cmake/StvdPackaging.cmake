# Packaging helpers shared by the core library and its optional adapters.
#
# The installed package is one CMake package `stvd` with a core and optional
# components, all imported under the namespace stvd:: from
#   <prefix>/<libdir>/cmake/stvd/
#     stvdConfig.cmake, stvdConfigVersion.cmake  (from cmake/stvdConfig.cmake.in)
#     stvdTargets.cmake                           (the core: stvd::stvd)
#     stvd_<component>Targets.cmake               (one per installed component)
#     stvd_<component>Dependencies.cmake          (find_package calls for it)
#
# Each component gets an export set of its own rather than joining the core's:
# a target in the core's set would put its dependencies (ITK, ...) into
# stvdTargets.cmake, and every consumer of the core alone would then have to
# find them. With one set per component, `find_package(stvd)` needs nothing
# beyond the C++ standard library and `find_package(stvd COMPONENTS itk)` finds
# ITK as well. stvdConfig.cmake loads a component when it is asked for and its
# files are installed; it does not need to know the component names when it is
# generated, so components may be added in any directory, before or after the
# core's install rules.
#
# Adding the ITK file I/O (target stvd_itk, alias stvd::itk), which links the
# component `imaging`, as component `itk`, in lib/itk/CMakeLists.txt:
#
#   set_target_properties(stvd_itk PROPERTIES EXPORT_NAME itk)  # -> stvd::itk
#   target_include_directories(stvd_itk PUBLIC
#     $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
#     $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
#   include(${PROJECT_SOURCE_DIR}/cmake/StvdPackaging.cmake)
#   stvd_install_component(itk
#     TARGETS stvd_itk
#     HEADER_DIRECTORIES ${CMAKE_CURRENT_SOURCE_DIR}/include/stvd
#     COMPONENTS imaging
#     DEPENDENCIES "ITK 5.2 COMPONENTS ITKCommon ITKIOImageBase ITKIONRRD ITKIONIFTI")
#
# Each DEPENDENCIES entry is the argument list of one find_package() call,
# written as in the adapter's own find_package() call, less REQUIRED.
# The consumer then writes
#
#   project(consumer LANGUAGES C CXX)  # C: ITK's package config runs a C check
#   find_package(stvd REQUIRED COMPONENTS itk)
#   target_link_libraries(app PRIVATE stvd::itk)
#
# A TetGen module (AGPL-3.0) would be added the same way, as a component of
# its own, so that linking stvd::stvd never pulls it in.

# No include guard: the file only defines a function and a variable, and the
# variable must be set in every directory that includes it.
include(GNUInstallDirs)

# Where the package's CMake files go, relative to the install prefix.
set(STVD_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/stvd")

# stvd_install_component(<name>
#   TARGETS <target>...                 libraries of the component
#   [HEADER_DIRECTORIES <dir>...]       installed into <prefix>/include/ like
#                                       install(DIRECTORY <dir> ...): a
#                                       directory .../include/stvd lands in
#                                       <prefix>/include/stvd; only *.hpp/*.h
#   [COMPONENTS <component>...]         other components its targets link,
#                                       loaded with it (itk: imaging)
#   [DEPENDENCIES "<package> <args>"...]  one find_package() per entry
#   [MODULE_PATHS <dir>...]             where their find modules are, if not
#                                       on CMake's own path
# )
function(stvd_install_component name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "TARGETS;HEADER_DIRECTORIES;COMPONENTS;DEPENDENCIES;MODULE_PATHS")
  if(NOT arg_TARGETS)
    message(FATAL_ERROR "stvd_install_component(${name}): TARGETS is required")
  endif()
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "stvd_install_component(${name}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()

  install(TARGETS ${arg_TARGETS} EXPORT stvd_${name}Targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT stvd_${name}Targets
    NAMESPACE stvd::
    FILE stvd_${name}Targets.cmake
    DESTINATION ${STVD_INSTALL_CMAKEDIR})
  foreach(dir IN LISTS arg_HEADER_DIRECTORIES)
    install(DIRECTORY ${dir} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
      FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
  endforeach()

  # Plain find_package() rather than find_dependency(): find_dependency()
  # passes the consumer's REQUIRED on, which would turn a missing dependency
  # of an OPTIONAL_COMPONENTS request into a fatal error. stvdConfig.cmake
  # reads _stvd_missing_dependencies and marks the component not found.
  set(content "# Packages that the stvd component '${name}' links against.\n")
  # A component it builds on is loaded first, with its own dependencies, so
  # that its imported targets exist when this component's are defined.
  foreach(component IN LISTS arg_COMPONENTS)
    string(APPEND content "if(EXISTS \"\${CMAKE_CURRENT_LIST_DIR}/stvd_${component}Targets.cmake\")\n")
    string(APPEND content "  include(\"\${CMAKE_CURRENT_LIST_DIR}/stvd_${component}Dependencies.cmake\")\n")
    string(APPEND content "  if(NOT _stvd_missing_dependencies)\n")
    string(APPEND content "    include(\"\${CMAKE_CURRENT_LIST_DIR}/stvd_${component}Targets.cmake\")\n")
    string(APPEND content "  endif()\n")
    string(APPEND content "else()\n")
    string(APPEND content "  list(APPEND _stvd_missing_dependencies \"the stvd component ${component}\")\n")
    string(APPEND content "endif()\n")
  endforeach()
  # Find modules outside CMake's own path (Debian's FindOpenVDB.cmake), for
  # this file only; a find module may set BUILD_SHARED_LIBS (FindOpenVDB
  # does), which must not leak into the consumer's project.
  if(arg_MODULE_PATHS)
    string(APPEND content "set(_stvd_saved_module_path \"\${CMAKE_MODULE_PATH}\")\n")
    string(APPEND content "set(_stvd_saved_shared \"\${BUILD_SHARED_LIBS}\")\n")
    foreach(path IN LISTS arg_MODULE_PATHS)
      string(APPEND content "list(APPEND CMAKE_MODULE_PATH \"${path}\")\n")
    endforeach()
  endif()
  foreach(dependency IN LISTS arg_DEPENDENCIES)
    string(REGEX MATCH "^[^ ]+" package "${dependency}")
    string(APPEND content "find_package(${dependency} \${_stvd_quiet})\n")
    string(APPEND content "if(NOT ${package}_FOUND)\n")
    string(APPEND content "  list(APPEND _stvd_missing_dependencies \"${dependency}\")\n")
    string(APPEND content "endif()\n")
  endforeach()
  if(arg_MODULE_PATHS)
    string(APPEND content "set(CMAKE_MODULE_PATH \"\${_stvd_saved_module_path}\")\n")
    string(APPEND content "set(BUILD_SHARED_LIBS \"\${_stvd_saved_shared}\")\n")
  endif()
  set(file "${PROJECT_BINARY_DIR}/stvd_package/stvd_${name}Dependencies.cmake")
  file(WRITE "${file}" "${content}")
  install(FILES "${file}" DESTINATION ${STVD_INSTALL_CMAKEDIR})
endfunction()
