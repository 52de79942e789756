# run_consumer.cmake: the consumer tests (registered by tests/CMakeLists.txt as test_consumer_*).
# Each builds a tiny project against envlight the way a user's project would, and runs it.
#
#   cmake -DMODE=installed|subproject -DSOURCE_DIR=<envlight> -DWORK_DIR=<scratch dir>
#         [-DGENERATOR=...] [-DC_COMPILER=...] [-DCXX_COMPILER=...] -P run_consumer.cmake
#
# installed:  configure envlight itself with its tests, examples and benchmarks off and with Embree,
#             OpenEXR, Imath, zlib, pkg-config and Threads made unfindable (a find_package(... REQUIRED)
#             of any of them fails the configure), `cmake --install` it into WORK_DIR/prefix, then
#             build installed_c (C only) and installed_cxx (C++ only) with find_package(envlight)
#             from that prefix and run them.
# subproject: build subproject_c, a C-only project that calls add_subdirectory(envlight); its
#             CMakeLists.txt fails if envlight enabled C++, defined its own targets or looked for a
#             package. Run it, then install the parent: only its own program may be installed.
cmake_minimum_required(VERSION 3.16)
foreach(v MODE SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_consumer.cmake: -D${v}=... is required")
  endif()
endforeach()
set(HERE ${CMAKE_CURRENT_LIST_DIR})
set(COMMON_ARGS)
if(GENERATOR)
  list(APPEND COMMON_ARGS -G ${GENERATOR})
endif()
if(C_COMPILER)
  list(APPEND COMMON_ARGS -DCMAKE_C_COMPILER=${C_COMPILER})
endif()
if(CXX_COMPILER)
  list(APPEND COMMON_ARGS -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()

# run(<what> <command...>): runs a command, fails the test with its output when it fails.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "FAIL: ${what} (exit ${rc})\n${out}\n${err}")
  endif()
  message(STATUS "ok: ${what}")
  set(LAST_OUTPUT "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

if(MODE STREQUAL "installed")
  set(prefix ${WORK_DIR}/prefix)
  set(hide)
  foreach(p embree OpenEXR Imath ZLIB PkgConfig Threads)
    list(APPEND hide -DCMAKE_DISABLE_FIND_PACKAGE_${p}=ON)
  endforeach()
  run("configure envlight with tests, examples and benchmarks off, no optional package findable"
      ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/envlight-build ${COMMON_ARGS} ${hide}
      -DEL_BUILD_TESTS=OFF -DEL_BUILD_EXAMPLES=OFF -DEL_BUILD_BENCH=OFF -DCMAKE_INSTALL_PREFIX=${prefix})
  run("cmake --install into ${prefix}" ${CMAKE_COMMAND} --install ${WORK_DIR}/envlight-build)
  foreach(lang c cxx)
    run("configure installed_${lang} with find_package(envlight)"
        ${CMAKE_COMMAND} -S ${HERE}/installed_${lang} -B ${WORK_DIR}/${lang}-build ${COMMON_ARGS}
        -DCMAKE_PREFIX_PATH=${prefix} -DEXPECTED_PREFIX=${prefix}
        -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
    run("build installed_${lang}" ${CMAKE_COMMAND} --build ${WORK_DIR}/${lang}-build)
    run("run installed_${lang}" ${WORK_DIR}/${lang}-build/sample_light)
    message(STATUS "${LAST_OUTPUT}")
  endforeach()
elseif(MODE STREQUAL "subproject")
  run("configure subproject_c (a C-only project calling add_subdirectory(envlight))"
      ${CMAKE_COMMAND} -S ${HERE}/subproject_c -B ${WORK_DIR}/build ${COMMON_ARGS}
      -DENVLIGHT_SOURCE_DIR=${SOURCE_DIR})
  run("build subproject_c" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
  run("run subproject_c" ${WORK_DIR}/build/sample_light)
  message(STATUS "${LAST_OUTPUT}")
  run("install subproject_c" ${CMAKE_COMMAND} --install ${WORK_DIR}/build --prefix ${WORK_DIR}/prefix)
  file(GLOB_RECURSE installed RELATIVE ${WORK_DIR}/prefix ${WORK_DIR}/prefix/*)
  if(NOT installed STREQUAL "bin/sample_light")
    message(FATAL_ERROR "FAIL: a subproject envlight installed files of its own: ${installed}")
  endif()
  message(STATUS "ok: the parent's install holds only its own program")
else()
  message(FATAL_ERROR "run_consumer.cmake: unknown MODE '${MODE}'")
endif()
