# Installs an omnisfm build tree into a fresh prefix, runs the installed omnisfm from there (with
# no LD_LIBRARY_PATH: it must find its libraries through its RPATH), then configures, builds and
# runs the downstream project in tests/downstream against it with find_package(omnisfm).
#
#   cmake -DOMNISFM_BUILD_DIR=<build> [-DDOWNSTREAM_SOURCE_DIR=<this directory>]
#         [-DCONFIG=<build type>] [-DGENERATOR=<generator>] [-DCXX_COMPILER=<compiler>]
#         [-DOMNISFM_VERSION=<the version --version must print>] -P downstream_test.cmake
#
# The build tree must be fully built: `cmake --install` installs every target.
cmake_minimum_required(VERSION 3.16)

if(NOT OMNISFM_BUILD_DIR)
  message(FATAL_ERROR "downstream_test: pass -DOMNISFM_BUILD_DIR=<omnisfm build tree>")
endif()
if(NOT DOWNSTREAM_SOURCE_DIR)
  set(DOWNSTREAM_SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}")
endif()

set(work_dir "${OMNISFM_BUILD_DIR}/downstream_test")
set(prefix "${work_dir}/prefix")
set(downstream_build_dir "${work_dir}/build")
file(REMOVE_RECURSE "${work_dir}")
# A DESTDIR from the environment would move the installed files away from the prefix; a library
# path would hide a missing RPATH.
unset(ENV{DESTDIR})
unset(ENV{LD_LIBRARY_PATH})

function(run_step description)
  message(STATUS "downstream_test: ${description}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "downstream_test: ${description} failed: ${status}")
  endif()
endfunction()

set(config_args)
if(CONFIG)
  set(config_args --config "${CONFIG}")
endif()

run_step("installing ${OMNISFM_BUILD_DIR} into ${prefix}"
  "${CMAKE_COMMAND}" --install "${OMNISFM_BUILD_DIR}" --prefix "${prefix}" ${config_args})

# The installed program, from its prefix: --version, and one verb on the installed camera file.
set(installed "${prefix}/bin/omnisfm")
execute_process(COMMAND "${installed}" --version RESULT_VARIABLE status OUTPUT_VARIABLE version
                ERROR_VARIABLE error)
if(NOT status EQUAL 0 OR NOT version MATCHES "${OMNISFM_VERSION}")
  message(FATAL_ERROR
          "downstream_test: ${installed} --version failed (${status}): ${version}${error}")
endif()
file(WRITE "${work_dir}/points.vnl" "# x y z\n2 0 -1\n")
execute_process(COMMAND "${installed}" project
                        --camera "${prefix}/share/omnisfm/cameras/equiangular.ini"
                INPUT_FILE "${work_dir}/points.vnl"
                RESULT_VARIABLE status OUTPUT_VARIABLE projected ERROR_VARIABLE error)
if(NOT status EQUAL 0 OR NOT projected MATCHES "^# u v\n[0-9.]+ [0-9.]+\n$")
  message(FATAL_ERROR
          "downstream_test: ${installed} project failed (${status}): ${projected}${error}")
endif()
message(STATUS "downstream_test: the installed omnisfm runs: ${version}")

# Moved elsewhere, the prefix still serves its program its own shipped camera: made different
# from the source tree's here, the default camera must project as that file does.
set(moved "${work_dir}/moved-prefix")
file(RENAME "${prefix}" "${moved}")
set(moved_camera "${moved}/share/omnisfm/cameras/equiangular.ini")
file(READ "${moved_camera}" camera_text)
string(REGEX REPLACE "\ncx = [^\n]*" "\ncx = 400" camera_text "${camera_text}")
file(WRITE "${moved_camera}" "${camera_text}")
foreach(camera_args IN ITEMS "" "--camera;${moved_camera}")
  execute_process(COMMAND "${moved}/bin/omnisfm" project ${camera_args}
                  INPUT_FILE "${work_dir}/points.vnl" RESULT_VARIABLE status
                  OUTPUT_VARIABLE output ERROR_VARIABLE error)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "downstream_test: the moved prefix's omnisfm project failed: ${error}")
  endif()
  list(APPEND moved_projections "${output}")
endforeach()
list(GET moved_projections 0 by_default)
list(GET moved_projections 1 by_file)
if(NOT by_default STREQUAL by_file OR by_default STREQUAL projected)
  message(FATAL_ERROR "downstream_test: moved, the installed omnisfm did not take its prefix's "
                      "camera: ${by_default} (its file: ${by_file}; the source tree's: ${projected})")
endif()
file(RENAME "${moved}" "${prefix}")

set(configure_args -S "${DOWNSTREAM_SOURCE_DIR}" -B "${downstream_build_dir}"
                   "-DCMAKE_PREFIX_PATH=${prefix}")
if(GENERATOR)
  list(APPEND configure_args -G "${GENERATOR}")
endif()
if(CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
if(CONFIG)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
endif()
run_step("configuring the downstream project" "${CMAKE_COMMAND}" ${configure_args})

# The package must come from the fresh prefix, not from an omnisfm installed elsewhere.
file(STRINGS "${downstream_build_dir}/CMakeCache.txt" found_dir REGEX "^omnisfm_DIR:")
string(REGEX REPLACE "^omnisfm_DIR:[A-Z]*=" "" found_dir "${found_dir}")
get_filename_component(real_prefix "${prefix}" REALPATH)
get_filename_component(real_found_dir "${found_dir}" REALPATH)
string(FIND "${real_found_dir}" "${real_prefix}/" position)
if(NOT position EQUAL 0)
  message(FATAL_ERROR "downstream_test: omnisfm was found in ${found_dir}, not under ${prefix}")
endif()

run_step("building the downstream project"
  "${CMAKE_COMMAND}" --build "${downstream_build_dir}" ${config_args})

set(program "${downstream_build_dir}/omnisfm_downstream")
if(NOT EXISTS "${program}" AND CONFIG)
  set(program "${downstream_build_dir}/${CONFIG}/omnisfm_downstream")  # multi-config generators
endif()
run_step("running ${program}" "${program}")

set(slam_program "${downstream_build_dir}/omnisfm_downstream_slam")
if(NOT EXISTS "${slam_program}" AND CONFIG)
  set(slam_program "${downstream_build_dir}/${CONFIG}/omnisfm_downstream_slam")
endif()
if(EXISTS "${slam_program}")
  run_step("running ${slam_program}" "${slam_program}")
endif()
