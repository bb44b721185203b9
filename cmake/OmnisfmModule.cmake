# omnisfm_add_module(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# A library libs/NAME with headers under include/omnisfm/NAME, exported as omnisfm::NAME.
function(omnisfm_add_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target omnisfm_${name})
  add_library(${target} ${ARG_SOURCES})
  add_library(omnisfm::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME omnisfm_${name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  omnisfm_warnings(${target})
  install(TARGETS ${target} EXPORT omnisfmTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/omnisfm DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

function(omnisfm_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wno-sign-compare)
endfunction()

# omnisfm_add_test(NAME [ONE_PROCESS_PER_SUITE] SOURCES ... DEPS ... [LABELS ...]
#                  [NOT_SANITIZED REGEX...])
# Labels: unit by default; sanitize for the tests the sanitizer build runs in CI (scripts/test.sh),
# but for those whose whole name a NOT_SANITIZED regular expression matches (whole runs of the
# estimators, numeric derivatives, statistics over thousands of draws: the sanitizers slow them
# about tenfold, and other tests run the same code there); long for the seed sweeps and
# long drives, which are given a cost so that a first run, with no timings yet, starts them before
# the short tests and two cores finish together.
function(omnisfm_add_test name)
  cmake_parse_arguments(ARG "ONE_PROCESS_PER_SUITE" "" "SOURCES;DEPS;LABELS;NOT_SANITIZED" ${ARGN})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  if(TARGET omnisfm_sanitizer_checks AND "sanitize" IN_LIST ARG_LABELS)
    add_dependencies(omnisfm_sanitizer_checks ${name})
  endif()
  omnisfm_warnings(${name})
  # OpenBLAS on one thread, as the programs set it (omnisfm::sfm::use_one_blas_thread), and the
  # command's image work too: the tests share the cores, where OpenCV's spinning threads cost.
  set(environment "OMNISFM_SOURCE_DIR=${PROJECT_SOURCE_DIR}" "OPENBLAS_NUM_THREADS=1"
      "OMNISFM_THREADS=1" ${OMNISFM_SANITIZER_ENVIRONMENT})
  if(ARG_ONE_PROCESS_PER_SUITE)
    omnisfm_add_suite_tests(${name} "${ARG_LABELS}" "${ARG_NOT_SANITIZED}" "${environment}")
    return()
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    TEST_LIST ${name}_tests
    DISCOVERY_TIMEOUT 60)
  # Lists (two labels, several variables) do not survive gtest_discover_tests' PROPERTIES, so
  # they are set by a file CTest reads after the discovered tests.
  set(cost 0)
  if("long" IN_LIST ARG_LABELS)
    set(cost 100)
  endif()
  set(properties_file "${CMAKE_CURRENT_BINARY_DIR}/${name}_properties.cmake")
  # CTest adds labels to a test's rather than replacing them: the NOT_SANITIZED tests are left
  # out of the list that is given the sanitize label.
  set(labels ${ARG_LABELS})
  list(REMOVE_ITEM labels sanitize)
  file(WRITE "${properties_file}"
       "if(${name}_tests)\n"
       "  set_tests_properties(\${${name}_tests} PROPERTIES\n"
       "    LABELS \"${labels}\" COST ${cost} ENVIRONMENT \"${environment}\")\n")
  if("sanitize" IN_LIST ARG_LABELS)
    file(APPEND "${properties_file}" "  set(sanitized \${${name}_tests})\n")
    if(ARG_NOT_SANITIZED)
      list(JOIN ARG_NOT_SANITIZED "|" not_sanitized)
      file(APPEND "${properties_file}"
           "  list(FILTER sanitized EXCLUDE REGEX \"^(${not_sanitized})\$\")\n")
    endif()
    file(APPEND "${properties_file}"
         "  set_tests_properties(\${sanitized} PROPERTIES LABELS sanitize)\n")
  endif()
  file(APPEND "${properties_file}" "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${properties_file}")
endfunction()

# One CTest test per gtest suite of `name` (ONE_PROCESS_PER_SUITE), for programs of many short
# tests whose start costs more than they do: a program linking MRPT starts in 0.4 s of processor
# time (0.8 s under the sanitizers), a camera contract test runs in milliseconds. The tests of a
# suite that a NOT_SANITIZED expression matches make a test of their own, without the sanitize
# label. A failure names its gtest test in the output, as before.
function(omnisfm_add_suite_tests name labels not_sanitized environment)
  set(sanitize FALSE)
  if("sanitize" IN_LIST labels)
    set(sanitize TRUE)
  endif()
  list(REMOVE_ITEM labels sanitize)
  set(directory ${CMAKE_CURRENT_SOURCE_DIR})
  configure_file(${PROJECT_SOURCE_DIR}/cmake/GtestSuites.cmake.in
                 ${CMAKE_CURRENT_BINARY_DIR}/${name}_suites.cmake.in @ONLY)
  file(GENERATE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/${name}_suites.cmake
       INPUT ${CMAKE_CURRENT_BINARY_DIR}/${name}_suites.cmake.in)
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES
               ${CMAKE_CURRENT_BINARY_DIR}/${name}_suites.cmake)
endfunction()
