# Compiles one translation unit (syntax and template instantiation only) and
# checks the outcome: with EXPECT=fail the compiler must refuse it and its
# messages must match REGEX; with EXPECT=pass it must accept it.
#   cmake -DCOMPILER=... -DSOURCE=... -DINCLUDE_DIR=... [-DDEFINE=NAME]
#         -DEXPECT=pass|fail [-DREGEX=...] -P check_compile.cmake
foreach(variable COMPILER SOURCE INCLUDE_DIR EXPECT)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "check_compile.cmake: -D${variable}=... is required")
  endif()
endforeach()
set(defines "")
if(DEFINE)
  set(defines "-D${DEFINE}")
endif()
execute_process(COMMAND "${COMPILER}" -std=c++17 -fsyntax-only ${defines} "-I${INCLUDE_DIR}" "${SOURCE}"
                RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(EXPECT STREQUAL "pass")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${SOURCE} ${defines} does not compile:\n${output}")
  endif()
elseif(EXPECT STREQUAL "fail")
  if(result EQUAL 0)
    message(FATAL_ERROR "${SOURCE} ${defines} compiles, but must not")
  endif()
  if(REGEX AND NOT output MATCHES "${REGEX}")
    message(FATAL_ERROR "${SOURCE} ${defines} fails to compile, but not for the expected reason "
                        "(no match for '${REGEX}'):\n${output}")
  endif()
else()
  message(FATAL_ERROR "check_compile.cmake: EXPECT must be pass or fail")
endif()
