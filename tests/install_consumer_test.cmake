# Installs the freshly built stvd into a scratch prefix, then configures,
# builds and runs examples/consumer against that prefix only: the test that
# `find_package(stvd COMPONENTS imaging)` with `stvd::stvd` and
# `stvd::imaging` (no ITK), and `find_package(stvd COMPONENTS itk)` with
# `stvd::itk` where it was built, work for a project outside this tree.
#
# cmake -DSTVD_BINARY_DIR=<build tree> -DCONSUMER_SOURCE_DIR=<examples/consumer>
#       -DWORK_DIR=<scratch dir> -DCONFIG=<build type> -DGENERATOR=<generator>
#       -DCXX_COMPILER=<compiler> [-DMAKE_PROGRAM=<make>] -P install_consumer_test.cmake
cmake_minimum_required(VERSION 3.20)

foreach(variable STVD_BINARY_DIR CONSUMER_SOURCE_DIR WORK_DIR CONFIG GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${variable} OR "${${variable}}" STREQUAL "")
    message(FATAL_ERROR "install_consumer_test.cmake: -D${variable}=... is required")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")
set(consumer_build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "install_consumer_test: ${step} failed (${result})")
  endif()
endfunction()

run("cmake --install" "${CMAKE_COMMAND}" --install "${STVD_BINARY_DIR}" --config "${CONFIG}"
    --prefix "${prefix}")

# LICENSE travels with the install, and pkg-config finds the core from the
# prefix alone: a program compiled and linked with its flags runs.
file(GLOB_RECURSE licence "${prefix}/share/doc/*/LICENSE")
if(NOT licence)
  message(FATAL_ERROR "install_consumer_test: LICENSE is not installed")
endif()
file(GLOB_RECURSE pc_files "${prefix}/*/pkgconfig/stvd.pc")
if(NOT pc_files)
  message(FATAL_ERROR "install_consumer_test: stvd.pc is not installed")
endif()
list(GET pc_files 0 pc_file)
get_filename_component(pc_dir "${pc_file}" DIRECTORY)
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
execute_process(COMMAND pkg-config --cflags --libs stvd RESULT_VARIABLE result OUTPUT_VARIABLE flags)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "install_consumer_test: pkg-config --cflags --libs stvd failed (${result})")
endif()
string(STRIP "${flags}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
file(MAKE_DIRECTORY "${WORK_DIR}/pkg-config")
file(WRITE "${WORK_DIR}/pkg-config/program.cpp" [=[
#include <cmath>
#include "stvd/stvd.hpp"
int main() {
  stvd::GridGeometry g;
  g.size = {5, 4, 3};
  const stvd::VoxelGridDomain domain(g, stvd::Stencil::full26());
  const auto metric = stvd::RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const stvd::PropagationResult r = stvd::propagate(domain, metric, {0});
  return std::fabs(r.distance[domain.vertexAt(4, 3, 2)] - std::sqrt(29.0)) < 1e-4 ? 0 : 1;
}
]=])
run("compiling with pkg-config's flags" "${CXX_COMPILER}" -std=c++17 "${WORK_DIR}/pkg-config/program.cpp"
    -o "${WORK_DIR}/pkg-config/program" ${flags})
run("running the pkg-config program" "${WORK_DIR}/pkg-config/program")

set(make_program "")
if(MAKE_PROGRAM)
  set(make_program "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
# The package registries are switched off so that only the prefix (or a
# system-wide install, rejected below) can provide stvd.
# The ITK file I/O too, when this build installed it.
file(GLOB_RECURSE itk_targets "${prefix}/*/stvd_itkTargets.cmake")
set(with_itk OFF)
if(itk_targets)
  set(with_itk ON)
endif()
run("configuring the consumer" "${CMAKE_COMMAND}" -S "${CONSUMER_SOURCE_DIR}"
    -B "${consumer_build}" -G "${GENERATOR}" ${make_program}
    "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    "-DCMAKE_PREFIX_PATH=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
    "-DSTVD_CONSUMER_WITH_ITK=${with_itk}")

# The package must have come from the scratch prefix, not from an older stvd
# installed elsewhere on the machine.
file(STRINGS "${consumer_build}/CMakeCache.txt" found_dir REGEX "^stvd_DIR:")
string(REGEX REPLACE "^stvd_DIR:[A-Z]+=" "" found_dir "${found_dir}")
file(REAL_PATH "${found_dir}" found_dir)
file(REAL_PATH "${prefix}" real_prefix)
string(FIND "${found_dir}/" "${real_prefix}/" position)
if(NOT position EQUAL 0)
  message(FATAL_ERROR "install_consumer_test: stvd was found in ${found_dir}, not in ${prefix}")
endif()

run("building the consumer" "${CMAKE_COMMAND}" --build "${consumer_build}" --config "${CONFIG}")

find_program(consumer stvd_consumer PATHS "${consumer_build}" "${consumer_build}/${CONFIG}"
             NO_DEFAULT_PATH REQUIRED)
run("running the consumer" "${consumer}")
find_program(imaging_consumer stvd_imaging_consumer PATHS "${consumer_build}" "${consumer_build}/${CONFIG}"
             NO_DEFAULT_PATH REQUIRED)
run("running the imaging consumer" "${imaging_consumer}" "${consumer_build}")
if(with_itk)
  find_program(itk_consumer stvd_itk_consumer PATHS "${consumer_build}" "${consumer_build}/${CONFIG}"
               NO_DEFAULT_PATH REQUIRED)
  run("running the ITK consumer" "${itk_consumer}" "${consumer_build}")
endif()
