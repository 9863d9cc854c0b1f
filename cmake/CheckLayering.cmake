# Checks the include rules that keep the architecture visible (run by CTest):
#   Embree only in accel/, TBB only in core/parallel_tbb.cpp, OpenImageIO only
#   in core/image_io.cpp and core/texture_cache.cpp, tinyobjloader only in
#   core/io/obj_loader.cpp, nlohmann-json only in core/io/json_document.h (the
#   JSON loader's files include it from there); the loaders' path policy
#   (core/io/path_policy, input_file, load_options) is their bottom and includes
#   no loader; the rest of core does not include the loaders; the public headers
#   include only the standard library and each other; lights/ and accel/ do not
#   include each other.
# Usage: cmake -DSOURCE_DIR=<repo> -P CheckLayering.cmake
file(GLOB_RECURSE _files RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/core/*.h ${SOURCE_DIR}/core/*.hpp ${SOURCE_DIR}/core/*.cpp
     ${SOURCE_DIR}/accel/*.h ${SOURCE_DIR}/accel/*.cpp
     ${SOURCE_DIR}/lights/*.h ${SOURCE_DIR}/lights/*.cpp
     ${SOURCE_DIR}/shading/*.h ${SOURCE_DIR}/shading/*.cpp)
set(_errors "")
foreach(_f IN LISTS _files)
  file(STRINGS ${SOURCE_DIR}/${_f} _includes REGEX "^[ \t]*#[ \t]*include")
  foreach(_line IN LISTS _includes)
    if(_line MATCHES "embree3/" AND NOT _f MATCHES "^accel/")
      list(APPEND _errors "${_f}: includes Embree outside accel/")
    endif()
    if(_line MATCHES "<tbb/" AND NOT _f STREQUAL "core/parallel_tbb.cpp")
      list(APPEND _errors "${_f}: includes TBB outside core/parallel_tbb.cpp")
    endif()
    if(_line MATCHES "OpenImageIO/" AND NOT _f MATCHES "^core/(image_io|texture_cache)\\.cpp$")
      list(APPEND _errors "${_f}: includes OpenImageIO outside core/image_io.cpp and core/texture_cache.cpp")
    endif()
    if(_line MATCHES "tiny_obj_loader" AND NOT _f STREQUAL "core/io/obj_loader.cpp")
      list(APPEND _errors "${_f}: includes tinyobjloader outside core/io/obj_loader.cpp")
    endif()
    if(_line MATCHES "nlohmann/" AND NOT _f STREQUAL "core/io/json_document.h")
      list(APPEND _errors "${_f}: includes nlohmann-json outside core/io/json_document.h")
    endif()
    if(_f MATCHES "^core/io/(path_policy|input_file|load_options)\\." AND _line MATCHES "\"core/io/"
       AND NOT _line MATCHES "\"core/io/(path_policy|input_file|load_options)\\.h\"")
      list(APPEND _errors "${_f}: the path policy includes a loader: ${_line}")
    endif()
    if(_f MATCHES "^core/" AND NOT _f MATCHES "^core/io/" AND NOT _f STREQUAL "core/scene_loader.h"
       AND _line MATCHES "\"core/io/")
      list(APPEND _errors "${_f}: core outside io/ includes a loader: ${_line}")
    endif()
    if(_f MATCHES "^core/" AND _line MATCHES "\"(accel|lights|shading)/")
      list(APPEND _errors "${_f}: core includes a higher layer: ${_line}")
    endif()
    if(_f MATCHES "^lights/" AND _line MATCHES "\"(accel|shading)/")
      list(APPEND _errors "${_f}: lights includes ${_line}")
    endif()
    if(_f MATCHES "^accel/" AND _line MATCHES "\"(lights|shading)/")
      list(APPEND _errors "${_f}: accel includes ${_line}")
    endif()
    if(_f MATCHES "^core/include/penumbra/" AND _line MATCHES "\"" AND NOT _line MATCHES "\"penumbra/")
      list(APPEND _errors "${_f}: public header includes a non-public header: ${_line}")
    endif()
  endforeach()
endforeach()
if(_errors)
  string(REPLACE ";" "\n" _msg "${_errors}")
  message(FATAL_ERROR "layering violations:\n${_msg}")
endif()
list(LENGTH _files _n)
message(STATUS "layering: ${_n} files follow the include rules")
