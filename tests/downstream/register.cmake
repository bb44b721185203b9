# The installed package serves a downstream project: install the build tree into a fresh prefix,
# find_package(omnisfm), build and run a program against it, and run the installed omnisfm from
# its prefix. Included from tests/CMakeLists.txt.
# It installs every target, so it runs after the whole project is built (as ctest does).
add_test(NAME downstream_find_package
  COMMAND "${CMAKE_COMMAND}"
    "-DOMNISFM_BUILD_DIR=${omnisfm_BINARY_DIR}"
    "-DDOWNSTREAM_SOURCE_DIR=${CMAKE_CURRENT_LIST_DIR}"
    "-DCONFIG=$<CONFIG>"
    "-DGENERATOR=${CMAKE_GENERATOR}"
    "-DCXX_COMPILER=${CMAKE_CXX_COMPILER}"
    "-DOMNISFM_VERSION=${PROJECT_VERSION}"
    -P "${CMAKE_CURRENT_LIST_DIR}/downstream_test.cmake")
set_tests_properties(downstream_find_package PROPERTIES LABELS package TIMEOUT 600)
