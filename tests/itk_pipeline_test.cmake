# Installs the freshly built stvd into a scratch prefix, then configures,
# builds and runs examples/itk_pipeline against that prefix only (a project
# with `LANGUAGES CXX`, as an ITK program may have it): ITK reads the sample
# tensors and mask, the filter computes the map with progress 0 -> 100 %,
# ITK writes it, a path comes out as an ITK path, an abort from another
# thread stops within 100 ms; and the map must equal, bit for bit, the one
# the installed `stvd distance` writes from the same file.
#
# cmake -DSTVD_BINARY_DIR=<build tree> -DEXAMPLE_SOURCE_DIR=<examples/itk_pipeline>
#       -DSAMPLE_DIR=<sample_data/dti_philips_biobank> -DWORK_DIR=<scratch dir>
#       -DCONFIG=<build type> -DGENERATOR=<generator> -DCXX_COMPILER=<compiler>
#       [-DMAKE_PROGRAM=<make>] -P itk_pipeline_test.cmake
cmake_minimum_required(VERSION 3.20)

foreach(variable STVD_BINARY_DIR EXAMPLE_SOURCE_DIR SAMPLE_DIR WORK_DIR CONFIG GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${variable} OR "${${variable}}" STREQUAL "")
    message(FATAL_ERROR "itk_pipeline_test.cmake: -D${variable}=... is required")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")
set(build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "itk_pipeline_test: ${step} failed (${result})")
  endif()
endfunction()

run("cmake --install" "${CMAKE_COMMAND}" --install "${STVD_BINARY_DIR}" --config "${CONFIG}" --prefix "${prefix}")
set(make_program "")
if(MAKE_PROGRAM)
  set(make_program "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
run("configuring the example" "${CMAKE_COMMAND}" -S "${EXAMPLE_SOURCE_DIR}" -B "${build}" -G "${GENERATOR}"
    ${make_program} "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    "-DCMAKE_PREFIX_PATH=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
run("building the example" "${CMAKE_COMMAND}" --build "${build}" --config "${CONFIG}")

set(tensors "${SAMPLE_DIR}/dti_tensor_dipy5d.nii.gz")
set(mask "${SAMPLE_DIR}/dti_mask.nii.gz")
find_program(tool stvd PATHS "${prefix}/bin" NO_DEFAULT_PATH REQUIRED)
run("stvd distance" "${tool}" distance "${tensors}" --mask "${mask}" --seed-voxel 55,54,15
    -o "${WORK_DIR}/tool.nii.gz" -q)
find_program(example itk_pipeline PATHS "${build}" "${build}/${CONFIG}" NO_DEFAULT_PATH REQUIRED)
run("running the example" "${example}" "${tensors}" "${mask}" 55 54 15 70 40 15 "${WORK_DIR}/itk.nii.gz"
    "${WORK_DIR}/tool.nii.gz")
