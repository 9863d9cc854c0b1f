# Checks that libpenumbra.so exports the embedding API and nothing else (run by
# CTest): every dynamic symbol it defines is C++ in namespace pnb (or the RTTI
# of a pnb type) or C named pnb_*, and the main entry points are there.
# Usage: cmake -DLIBRARY=<path to libpenumbra.so> -DNM=<nm> -P CheckExports.cmake
execute_process(COMMAND ${NM} -DC --defined-only ${LIBRARY}
                OUTPUT_VARIABLE _out ERROR_VARIABLE _err RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${LIBRARY}: ${_err}")
endif()
string(REPLACE "\n" ";" _lines "${_out}")
set(_bad "")
set(_count 0)
foreach(_line IN LISTS _lines)
  if(_line STREQUAL "")
    continue()
  endif()
  # "<address> <type> <name>"
  string(REGEX REPLACE "^[0-9a-fA-F]+ [A-Za-z] " "" _name "${_line}")
  string(REGEX REPLACE "^(typeinfo name for|typeinfo for|vtable for) " "" _bare "${_name}")
  math(EXPR _count "${_count} + 1")
  if(NOT _bare MATCHES "^pnb::" AND NOT _bare MATCHES "^pnb_")
    list(APPEND _bad "${_name}")
  endif()
endforeach()
if(_bad)
  list(LENGTH _bad _n)
  string(REPLACE ";" "\n  " _msg "${_bad}")
  message(FATAL_ERROR "${LIBRARY} exports ${_n} symbol(s) outside pnb:: and pnb_:\n  ${_msg}")
endif()
foreach(_needed "pnb_render_async" "pnb_renderer_create" "pnb::Renderer::prepare" "pnb::Scene::addMesh"
                "typeinfo for pnb::Error")
  string(FIND "${_out}" "${_needed}" _at)
  if(_at EQUAL -1)
    message(FATAL_ERROR "${LIBRARY} does not export ${_needed}")
  endif()
endforeach()
# Gone from the API: the image encoder helper process (images are encoded in the calling process).
foreach(_gone "pnb::ImageEncoder")
  string(FIND "${_out}" "${_gone}" _at)
  if(NOT _at EQUAL -1)
    message(FATAL_ERROR "${LIBRARY} still exports ${_gone}")
  endif()
endforeach()
message(STATUS "exports: ${_count} symbols, all pnb:: or pnb_")
