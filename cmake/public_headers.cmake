# Writes the public header tree: each SOURCE_DIR/FOLDER/*.hpp of FOLDERS (comma-separated) as
# OUTPUT_DIR/splatcl/FOLDER/*.hpp, with its includes of those folders prefixed by splatcl/, so that a
# program outside the project sees one include root with every splatcl header under splatcl/ (the
# sources themselves include "runtime/runtime.hpp" against host/). The kernel headers that host and
# kernels share (KERNEL_DIR/*.h, included as "../../kernels/x.h") go to OUTPUT_DIR/splatcl/kernels/,
# and those includes become "../kernels/x.h". The same tree serves the build tree and, installed,
# the package (docs/library.md). Then touches STAMP.
cmake_minimum_required(VERSION 3.20)
string(REPLACE "," ";" folders "${FOLDERS}")
string(REPLACE "," "|" alternatives "${FOLDERS}")
set(wanted)
# Rewritten only when it changes, so that what includes an unchanged header is not recompiled.
function(write_if_changed out text)
  set(old "")
  if(EXISTS ${out})
    file(READ ${out} old)
  endif()
  if(NOT old STREQUAL text)
    file(WRITE ${out} "${text}")
  endif()
endfunction()
foreach(folder IN LISTS folders)
  file(GLOB headers RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/${folder}/*.hpp)
  foreach(header IN LISTS headers)
    file(READ ${SOURCE_DIR}/${header} text)
    # Only #include lines at the start of a line: prose that quotes an include stays as it is.
    string(REGEX REPLACE "\n#include \"(${alternatives})/" "\n#include \"splatcl/\\1/" text "\n${text}")
    string(REGEX REPLACE "\n#include \"\\.\\./\\.\\./kernels/" "\n#include \"../kernels/" text "${text}")
    string(SUBSTRING "${text}" 1 -1 text)
    list(APPEND wanted ${OUTPUT_DIR}/splatcl/${header})
    write_if_changed(${OUTPUT_DIR}/splatcl/${header} "${text}")
  endforeach()
endforeach()
file(GLOB kernel_headers RELATIVE ${KERNEL_DIR} ${KERNEL_DIR}/*.h)
foreach(header IN LISTS kernel_headers)
  file(READ ${KERNEL_DIR}/${header} text)
  list(APPEND wanted ${OUTPUT_DIR}/splatcl/kernels/${header})
  write_if_changed(${OUTPUT_DIR}/splatcl/kernels/${header} "${text}")
endforeach()
# A header removed from host/ or kernels/ leaves the tree too.
file(GLOB_RECURSE existing ${OUTPUT_DIR}/splatcl/*.hpp ${OUTPUT_DIR}/splatcl/kernels/*.h)
foreach(path IN LISTS existing)
  if(NOT path IN_LIST wanted)
    file(REMOVE ${path})
  endif()
endforeach()
if(STAMP)
  file(TOUCH ${STAMP})
endif()
