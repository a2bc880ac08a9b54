# The library-only build, shared: configures this source tree with the one
# option STVD_LIBRARY_ONLY=ON and BUILD_SHARED_LIBS=ON (and without ITK, to
# be shorter: the core, the imaging adapter, tetmesh and surface_io), and
# checks that no tool, test, benchmark or Python target was configured.
# Unless CONFIGURE_ONLY, it then builds and installs it into a scratch
# prefix (a few CPU-minutes: scripts/check_library_build.sh, not CTest) and
# checks
# - libstvd.so's SONAME is versioned (libstvd.so.<major>.<minor>);
# - libstvd.so exports the namespace stvd and nothing of stvd::detail, and
#   every installed library resolves against the others (ldd -r);
# - LICENSE and the pkg-config file are installed, and a program compiled
#   and linked with `pkg-config --cflags --libs stvd` alone runs.
#
# cmake -DSOURCE_DIR=<source tree> -DWORK_DIR=<scratch dir> -DCXX_COMPILER=<compiler>
#       -DGENERATOR=<generator> [-DMAKE_PROGRAM=<make>] [-DCONFIGURE_ONLY=ON]
#       -P library_only_build.cmake
cmake_minimum_required(VERSION 3.20)
foreach(variable SOURCE_DIR WORK_DIR CXX_COMPILER GENERATOR)
  if(NOT DEFINED ${variable} OR "${${variable}}" STREQUAL "")
    message(FATAL_ERROR "library_only_build.cmake: -D${variable}=... is required")
  endif()
endforeach()

set(build "${WORK_DIR}/build")
set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "library_only_build: ${step} failed (${result}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
  set(run_errors "${err}" PARENT_SCOPE)
endfunction()

set(make_program "")
if(MAKE_PROGRAM)
  set(make_program "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
run("configuring" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${build}" -G "${GENERATOR}" ${make_program}
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    -DSTVD_LIBRARY_ONLY=ON -DBUILD_SHARED_LIBS=ON -DSTVD_WITH_ITK=OFF -DSTVD_WITH_TETGEN=OFF)
run("listing the targets" "${CMAKE_COMMAND}" --build "${build}" --target help)
foreach(unwanted stvd_tool stvd_core_tests stvd_python stvd_propagation_speed stvd_tetrahedralize)
  string(FIND "${run_output}" "${unwanted}" position)
  if(NOT position EQUAL -1)
    message(FATAL_ERROR "library_only_build: the library-only build has the target ${unwanted}")
  endif()
endforeach()
if(CONFIGURE_ONLY)
  message(STATUS "library-only configuration: no tool, tests, benchmarks or Python package")
  return()
endif()
include(ProcessorCount)
ProcessorCount(cores)
if(cores GREATER 2)
  set(cores 2)
endif()
run("building" "${CMAKE_COMMAND}" --build "${build}" --parallel ${cores})
run("installing" "${CMAKE_COMMAND}" --install "${build}" --prefix "${prefix}")

file(GLOB_RECURSE libraries "${prefix}/*/libstvd.so.*.*.*")
list(LENGTH libraries count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "library_only_build: expected one libstvd.so.X.Y.Z in the prefix, found: ${libraries}")
endif()
run("readelf" readelf -d "${libraries}")
if(NOT run_output MATCHES "Library soname: \\[libstvd\\.so\\.[0-9]+\\.[0-9]+\\]")
  message(FATAL_ERROR "library_only_build: libstvd.so has no versioned SONAME:\n${run_output}")
endif()
run("nm -D" nm -DC --defined-only "${libraries}")
string(REPLACE "\n" ";" lines "${run_output}")
set(exported_detail "")
foreach(line IN LISTS lines)
  # A symbol of stvd::detail itself (a function, possibly after its return
  # type, a class's typeinfo or vtable) must not be exported; a public
  # symbol whose template arguments or parameters mention a detail type
  # (stvd::makeLargeArray<stvd::detail::VertexRecord<true>>) is fine.
  if(line MATCHES "^[0-9a-f]+ [A-Za-z] ([^(<]* )?stvd::detail::")
    string(APPEND exported_detail "${line}\n")
  endif()
endforeach()
if(exported_detail)
  message(FATAL_ERROR "library_only_build: libstvd.so exports stvd::detail:\n${exported_detail}")
endif()
if(NOT run_output MATCHES "stvd::VoxelGridDomain::VoxelGridDomain")
  message(FATAL_ERROR "library_only_build: libstvd.so does not export the public API")
endif()

# Every installed library resolves against the others (a symbol one of
# them needs from libstvd.so must not have been made local).
get_filename_component(libdir "${libraries}" DIRECTORY)
file(GLOB installed "${libdir}/libstvd*.so.*.*.*")
foreach(library IN LISTS installed)
  run("ldd -r ${library}" "${CMAKE_COMMAND}" -E env "LD_LIBRARY_PATH=${libdir}" ldd -r "${library}")
  if("${run_output}${run_errors}" MATCHES "undefined symbol")
    message(FATAL_ERROR "library_only_build: ${library} has undefined symbols:\n${run_output}${run_errors}")
  endif()
endforeach()

file(GLOB_RECURSE licence "${prefix}/share/doc/*/LICENSE")
if(NOT licence)
  message(FATAL_ERROR "library_only_build: LICENSE is not installed")
endif()
file(GLOB_RECURSE pc_files "${prefix}/*/pkgconfig/stvd.pc")
if(NOT pc_files)
  message(FATAL_ERROR "library_only_build: stvd.pc is not installed")
endif()
list(GET pc_files 0 pc_file)
get_filename_component(pc_dir "${pc_file}" DIRECTORY)
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
run("pkg-config" pkg-config --cflags --libs stvd)
string(STRIP "${run_output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
file(WRITE "${WORK_DIR}/program.cpp" [=[
#include <cmath>
#include <cstdio>
#include "stvd/stvd.hpp"
int main() {
  stvd::GridGeometry g;
  g.size = {5, 4, 3};
  const stvd::VoxelGridDomain domain(g, stvd::Stencil::full26());
  const stvd::RiemannianMetric metric = stvd::RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const stvd::PropagationResult r = stvd::propagate(domain, metric, {0});
  const double d = r.distance[domain.vertexAt(4, 3, 2)];
  std::printf("%.6f\n", d);
  try {
    domain.vertexAt(5, 0, 0);
    return 1;
  } catch (const std::out_of_range&) {
  }
  return std::fabs(d - std::sqrt(29.0)) < 1e-4 ? 0 : 1;
}
]=])
run("compiling with pkg-config's flags" "${CXX_COMPILER}" -std=c++17 "${WORK_DIR}/program.cpp"
    -o "${WORK_DIR}/program" ${flags})
run("running the program" "${CMAKE_COMMAND}" -E env "LD_LIBRARY_PATH=${libdir}" "${WORK_DIR}/program")
message(STATUS "library-only shared build: ${libraries}, SONAME versioned, no stvd::detail exported, pkg-config works")
