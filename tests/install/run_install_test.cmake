# ctest Install.FindPackageBuildsExample: installs the build into a temporary prefix, builds
# examples/pushbroom_rays.cpp against it with find_package(beamtrace) (tests/install/CMakeLists.txt)
# and checks that the program writes the same rays as the in-tree build of the example.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCXX_COMPILER=... [-DLAUNCHER=...]
#         -DREFERENCE=<in-tree beamtrace_pushbroom_rays> -P run_install_test.cmake
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
set(launcher "")
if(LAUNCHER)
  set(launcher "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
endif()
run("configuring tests/install" ${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install" -B "${WORK_DIR}/build"
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launcher}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DEXPECTED_PREFIX=${prefix} -DEXAMPLE=${SOURCE_DIR}/examples/pushbroom_rays.cpp)
run("building the example against the installed tree" ${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("the installed-tree example" "${WORK_DIR}/build/pushbroom_rays" "${WORK_DIR}/installed.csv" 8 150)
if(NOT output MATCHES "wrote 64 rays")
  message(FATAL_ERROR "unexpected output of the example: ${output}")
endif()
run("the in-tree example" "${REFERENCE}" "${WORK_DIR}/in_tree.csv" 8 150)
file(STRINGS "${WORK_DIR}/installed.csv" lines)
list(LENGTH lines count)
file(SHA256 "${WORK_DIR}/installed.csv" installed)
file(SHA256 "${WORK_DIR}/in_tree.csv" in_tree)
if(NOT count EQUAL 65 OR NOT installed STREQUAL in_tree)
  message(FATAL_ERROR "the installed-tree example wrote ${count} lines (expected 65: a header and"
                      " 64 rays), or not the same rays as the in-tree build")
endif()
message(STATUS "find_package(beamtrace) from ${prefix}: the example builds and writes the same 64 rays")
