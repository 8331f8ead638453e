# ctest -P script: builds and runs tests/package/consumer the way MODE says, in WORK_DIR (emptied first).
#   install:      `cmake --install` of BUILD_DIR into WORK_DIR/prefix, then find_package against it
#   subdirectory: add_subdirectory of SOURCE_DIR, only the targets the consumer links, unoptimised
#                 (no build type: it compiles the libraries again, and -O0 compiles them fastest)
# CXX, LAUNCHER, BUILD_TYPE and FLAGS (a comma-separated list of -D settings for splatcl) are the
# suite's own build's, so the consumer is built like it.
cmake_minimum_required(VERSION 3.20)
string(REPLACE "," ";" flags "${FLAGS}")
file(REMOVE_RECURSE ${WORK_DIR})
cmake_host_system_information(RESULT jobs QUERY NUMBER_OF_LOGICAL_CORES)

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result})")
  endif()
endfunction()

if(MODE STREQUAL "subdirectory")
  set(BUILD_TYPE "")
endif()
set(configure ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/build
    -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_CXX_COMPILER=${CXX})
if(LAUNCHER)
  list(APPEND configure -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
if(MODE STREQUAL "install")
  set(prefix ${WORK_DIR}/prefix)
  run("installing" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
  # The package must stand alone: no file of it may name the source or the build tree.
  file(GLOB_RECURSE package_files ${prefix}/lib/cmake/* ${prefix}/include/*)
  foreach(file IN LISTS package_files)
    file(READ ${file} text)
    foreach(tree ${SOURCE_DIR} ${BUILD_DIR})
      string(FIND "${text}" "${tree}" at)
      if(NOT at EQUAL -1)
        message(FATAL_ERROR "${file} names ${tree}")
      endif()
    endforeach()
  endforeach()
  run("configuring the consumer" ${configure} -DCMAKE_PREFIX_PATH=${prefix})
elseif(MODE STREQUAL "subdirectory")
  run("configuring the consumer" ${configure} -DSPLATCL_SOURCE_DIR=${SOURCE_DIR} ${flags})
else()
  message(FATAL_ERROR "MODE must be install or subdirectory, not '${MODE}'")
endif()
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build --target splatcl_consumer -j ${jobs})
run("running the consumer" ${WORK_DIR}/build/splatcl_consumer)
