# What keeps the build short: precompiled headers and unity builds.
#
# Precompiled headers. The standard library, fmt, nlohmann/json, the OpenCL C++ bindings and
# GoogleTest are ~95% of the ~150,000 lines each translation unit of this project parses (a fifth of
# the Release build's compile time, more under the sanitizers' -O1). Two targets compile them once per
# build, one for the libraries and programs and one with GoogleTest for the test programs (its
# definitions differ), and every target of several sources reuses one (a target of one or two would
# not gain). A source must still include what it uses: a build with SPLATCL_PRECOMPILE_HEADERS=OFF
# and SPLATCL_UNITY_BUILD=OFF checks that. With ccache, set
# CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime, or ccache compiles
# every source again.
option(SPLATCL_PRECOMPILE_HEADERS
       "Precompile the standard and third-party headers once and reuse them in every target of several sources" ON)

# splatcl_precompiled_headers_target(NAME [LIBRARIES...]): the target NAME that compiles them, with
# what splatcl_runtime (and LIBRARIES) pass on to the targets that reuse them.
function(splatcl_precompiled_headers_target name)
  add_library(${name} OBJECT ${PROJECT_SOURCE_DIR}/cmake/build_time.cpp)
  target_compile_definitions(${name} PRIVATE ${SPLATCL_OPENCL_DEFINITIONS})
  target_link_libraries(${name} PRIVATE OpenCL::OpenCL fmt::fmt nlohmann_json::nlohmann_json ${ARGN})
  target_precompile_headers(${name} PRIVATE
    <algorithm> <array> <cmath> <cstdint> <cstring> <filesystem> <fstream> <functional> <map> <memory>
    <numeric> <optional> <random> <sstream> <string> <string_view> <vector>
    <fmt/format.h> <nlohmann/json.hpp> <glm/glm.hpp> ${PROJECT_SOURCE_DIR}/host/runtime/opencl.hpp)
endfunction()
if(SPLATCL_PRECOMPILE_HEADERS)
  splatcl_precompiled_headers_target(splatcl_precompiled)
  if(SPLATCL_BUILD_TESTS)
    splatcl_precompiled_headers_target(splatcl_precompiled_tests GTest::gtest)
    target_precompile_headers(splatcl_precompiled_tests PRIVATE <gtest/gtest.h>)
  endif()
endif()

# splatcl_precompile_headers(TARGET [TESTS]): TARGET, which links splatcl_runtime (and GoogleTest
# with TESTS), reuses the precompiled headers.
function(splatcl_precompile_headers target)
  if(SPLATCL_PRECOMPILE_HEADERS)
    if("TESTS" IN_LIST ARGN)
      target_precompile_headers(${target} REUSE_FROM splatcl_precompiled_tests)
    else()
      target_precompile_headers(${target} REUSE_FROM splatcl_precompiled)
    endif()
  endif()
endfunction()

# Unity builds: each source emitted the same inline code of the header-only libraries again (CLI11,
# JSON, fmt, OpenMesh: ~10 s of -O3 code generation in each of the CLI's sources, and the sanitizers
# instrument every copy); compiled in batches, a batch emits it once. Names inside a source's
# anonymous namespace must then differ across the sources of a target. -Wsubobject-linkage warns of
# such names used in a type defined in a header, which a batched source is to GCC.
option(SPLATCL_UNITY_BUILD "Compile each target of several sources in batches of sources" ON)
function(splatcl_unity_build target batch_size)
  if(SPLATCL_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${batch_size})
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
endfunction()
