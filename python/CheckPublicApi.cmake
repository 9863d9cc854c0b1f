# The Python module binds only the public C++ API: its sources include
# <penumbra/penumbra.hpp>, pybind11, the standard library and each other;
# nothing of the renderer's internals (run by CTest as Python.PublicApiOnly).
# Usage: cmake -DSOURCE_DIR=<repo>/python/src -P CheckPublicApi.cmake
file(GLOB _files ${SOURCE_DIR}/*.h ${SOURCE_DIR}/*.cpp)
set(_errors "")
foreach(_f IN LISTS _files)
  get_filename_component(_name ${_f} NAME)
  file(STRINGS ${_f} _includes REGEX "^[ \t]*#[ \t]*include")
  foreach(_line IN LISTS _includes)
    if(_line MATCHES "<penumbra/penumbra\\.hpp>" OR _line MATCHES "<pybind11/[a-z0-9_/]+\\.h>"
       OR _line MATCHES "<[a-z_]+>" OR _line MATCHES "\"[a-z_]+\\.h\"")
      continue()
    endif()
    list(APPEND _errors "${_name}: includes more than the public API: ${_line}")
  endforeach()
endforeach()
if(_errors)
  list(JOIN _errors "\n" _msg)
  message(FATAL_ERROR "${_msg}")
endif()
list(LENGTH _files _count)
message(STATUS "python/src: ${_count} files include only the public API")
