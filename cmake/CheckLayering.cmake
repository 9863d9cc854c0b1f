# Checks the include rules that keep the architecture visible (run by CTest):
#   Embree only in accel/, TBB only in core/parallel_tbb.cpp, OpenImageIO only
#   in core/oiio/oiio_module.cpp (the dlopen()ed image module), tinyobjloader only in
#   core/io/obj_loader.cpp, Assimp only in core/io/assimp_loader.cpp, tinygltf only in core/io/gltf_model.h
#   (the glTF reader's files include it from there), pugixml only in core/io/xml_checks.cpp, libdeflate only
#   in core/png_encoder.cpp
#   (the XML checks made before Assimp reads a file), nlohmann-json in the library only in
#   core/io/json_document.h (the JSON loader's files include it from there); the loaders' path policy
#   (core/io/path_policy, input_file, load_options) is their bottom and includes
#   no loader; the rest of core does not include the loaders; lights/ and accel/
#   do not include each other; the stack core <- accel, lights <- shading <- api
#   <- apps points one way. The public headers (api/include/penumbra/) include
#   only the standard library and each other; below api/ only
#   <penumbra/types.hpp> (the value types, std-only) and <penumbra/names.hpp>
#   (their names, std-only) may be included, never the facade; the penumbra CLI (apps/penumbra/, its preview in apps/penumbra/preview/)
#   and penumbra-mpi (apps/mpi/) include only public headers, like any other
#   host; CivetWeb only in apps/penumbra/preview/preview_server.cpp.
# Usage: cmake -DSOURCE_DIR=<repo> -P CheckLayering.cmake
file(GLOB_RECURSE _files RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/core/*.h ${SOURCE_DIR}/core/*.hpp ${SOURCE_DIR}/core/*.cpp
     ${SOURCE_DIR}/accel/*.h ${SOURCE_DIR}/accel/*.cpp
     ${SOURCE_DIR}/lights/*.h ${SOURCE_DIR}/lights/*.cpp
     ${SOURCE_DIR}/shading/*.h ${SOURCE_DIR}/shading/*.cpp
     ${SOURCE_DIR}/api/*.h ${SOURCE_DIR}/api/*.hpp ${SOURCE_DIR}/api/*.cpp
     ${SOURCE_DIR}/apps/penumbra/*.h ${SOURCE_DIR}/apps/penumbra/*.cpp
     ${SOURCE_DIR}/apps/penumbra/preview/*.h ${SOURCE_DIR}/apps/penumbra/preview/*.cpp
     ${SOURCE_DIR}/apps/mpi/*.h ${SOURCE_DIR}/apps/mpi/*.cpp)
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
    if(_line MATCHES "OpenImageIO/" AND NOT _f STREQUAL "core/oiio/oiio_module.cpp")
      list(APPEND _errors "${_f}: includes OpenImageIO outside core/oiio/oiio_module.cpp")
    endif()
    if(_line MATCHES "tiny_obj_loader" AND NOT _f STREQUAL "core/io/obj_loader.cpp")
      list(APPEND _errors "${_f}: includes tinyobjloader outside core/io/obj_loader.cpp")
    endif()
    if(_line MATCHES "[<\"]assimp/" AND NOT _f STREQUAL "core/io/assimp_loader.cpp")
      list(APPEND _errors "${_f}: includes Assimp outside core/io/assimp_loader.cpp")
    endif()
    if(_line MATCHES "tiny_gltf" AND NOT _f STREQUAL "core/io/gltf_model.h")
      list(APPEND _errors "${_f}: includes tinygltf outside core/io/gltf_model.h")
    endif()
    if(_line MATCHES "pugixml" AND NOT _f STREQUAL "core/io/xml_checks.cpp")
      list(APPEND _errors "${_f}: includes pugixml outside core/io/xml_checks.cpp")
    endif()
    if(_line MATCHES "<libdeflate\\.h>" AND NOT _f STREQUAL "core/png_encoder.cpp")
      list(APPEND _errors "${_f}: includes libdeflate outside core/png_encoder.cpp")
    endif()
    # Inside the library; the CLI writes its --stats-json with nlohmann-json too.
    if(_line MATCHES "nlohmann/" AND NOT _f STREQUAL "core/io/json_document.h" AND NOT _f MATCHES "^apps/")
      list(APPEND _errors "${_f}: includes nlohmann-json outside core/io/json_document.h")
    endif()
    if(_f MATCHES "^core/io/(path_policy|input_file|load_options)\\." AND _line MATCHES "\"core/io/"
       AND NOT _line MATCHES "\"core/io/(path_policy|input_file|load_options)\\.h\"")
      list(APPEND _errors "${_f}: the path policy includes a loader: ${_line}")
    endif()
    if(_f MATCHES "^core/" AND NOT _f MATCHES "^core/io/"
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
    if(_f MATCHES "^(core|accel|lights|shading)/" AND _line MATCHES "\"api/")
      list(APPEND _errors "${_f}: includes the API layer above it: ${_line}")
    endif()
    if(_f MATCHES "^(core|accel|lights|shading)/" AND _line MATCHES "[<\"]penumbra/" AND NOT _line MATCHES "<penumbra/(types|names)\\.hpp>")
      list(APPEND _errors "${_f}: below api/ only <penumbra/types.hpp> and <penumbra/names.hpp> may be included: ${_line}")
    endif()
    if(_f MATCHES "^api/include/penumbra/" AND _line MATCHES "\"")
      list(APPEND _errors "${_f}: public header includes a non-public header: ${_line}")
    endif()
    if(_f MATCHES "^api/include/penumbra/" AND _line MATCHES "<[^>]*/" AND NOT _line MATCHES "<penumbra/")
      list(APPEND _errors "${_f}: public header includes a third-party header: ${_line}")
    endif()
    if(_f STREQUAL "api/include/penumbra/types.hpp" AND _line MATCHES "<penumbra/")
      list(APPEND _errors "${_f}: the value types include only the standard library: ${_line}")
    endif()
    if(_f STREQUAL "api/include/penumbra/names.hpp" AND _line MATCHES "<penumbra/" AND NOT _line MATCHES "<penumbra/types\\.hpp>")
      list(APPEND _errors "${_f}: the values' names include only the standard library and types.hpp: ${_line}")
    endif()
    if(_line MATCHES "civetweb\\.h|CivetServer\\.h" AND NOT _f STREQUAL "apps/penumbra/preview/preview_server.cpp")
      list(APPEND _errors "${_f}: includes CivetWeb outside apps/penumbra/preview/preview_server.cpp")
    endif()
    if(_f MATCHES "^apps/(penumbra|mpi)/" AND _line MATCHES "\"(core|accel|lights|shading|api)/")
      list(APPEND _errors "${_f}: the CLI uses the public API only: ${_line}")
    endif()
  endforeach()
endforeach()
if(_errors)
  string(REPLACE ";" "\n" _msg "${_errors}")
  message(FATAL_ERROR "layering violations:\n${_msg}")
endif()
list(LENGTH _files _n)
message(STATUS "layering: ${_n} files follow the include rules")
