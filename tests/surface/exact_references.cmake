# Test fixture of the exact surface specifications (surface_exact_test.cpp):
# extracts one mesh from CGAL's data archive (Debian's libcgal-demo) and
# computes exact polyhedral distances from each source with the oracle
# program (exact_geodesic_oracle.cpp, GPL, never installed). The meshes are
# not copied into the repository: their archive carries no licence of its
# own, so they are read from the installed package at test time.
#
#   cmake -DARCHIVE=data.tar.gz -DMESH=name -DSOURCES="0;2000"
#         -DORACLE=path -DOUT=dir -P exact_references.cmake
foreach(variable ARCHIVE MESH SOURCES ORACLE OUT)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "exact_references.cmake: ${variable} is not set")
  endif()
endforeach()
file(MAKE_DIRECTORY "${OUT}")
set(member "data/meshes/${MESH}.off")
if(NOT EXISTS "${OUT}/${member}")
  execute_process(COMMAND "${CMAKE_COMMAND}" -E tar xzf "${ARCHIVE}" "${member}"
                  WORKING_DIRECTORY "${OUT}" RESULT_VARIABLE status)
  if(NOT status EQUAL 0 OR NOT EXISTS "${OUT}/${member}")
    message(FATAL_ERROR "exact_references.cmake: cannot extract ${member} from ${ARCHIVE}")
  endif()
endif()
foreach(source IN LISTS SOURCES)
  set(reference "${OUT}/${MESH}.${source}.txt")
  if(NOT EXISTS "${reference}")
    execute_process(COMMAND "${ORACLE}" "${OUT}/${member}" "${source}" "${reference}" RESULT_VARIABLE status)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "exact_references.cmake: the oracle failed on ${MESH} from vertex ${source}")
    endif()
  endif()
endforeach()
