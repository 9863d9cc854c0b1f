# Warnings for Penumbra's own targets.
function(penumbra_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
endfunction()

# An object library of one module: its sources are every .cpp in the folder
# (not its sub-folders).
function(penumbra_module name)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(${name} OBJECT ${_sources})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR} ${PROJECT_SOURCE_DIR}/api/include)
  target_link_libraries(${name} PUBLIC ${ARG_DEPENDS})
  # Hidden by default: only what the public headers mark PENUMBRA_API / PNB_API
  # leaves libpenumbra.so (cmake/penumbra.map hides the rest, std templates included).
  set_target_properties(${name} PROPERTIES CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  penumbra_warnings(${name})
  # Calls between the library's own functions go direct (and may inline)
  # instead of through the PLT: no host interposes Penumbra's internals.
  target_compile_options(${name} PRIVATE -fno-semantic-interposition)
  # Nothing reads errno after a math call: without it a square root is one
  # instruction (no test and call for negative inputs) and loops of them
  # vectorise. Results are the same IEEE values.
  target_compile_options(${name} PRIVATE -fno-math-errno)
  # Nothing reads the floating-point exception flags or traps on them:
  # without it GCC keeps every comparison that could raise a flag behind a
  # branch, and loops over the lanes of a ray packet (validity, planes,
  # selects) do not vectorise. Results are the same IEEE values.
  target_compile_options(${name} PRIVATE -fno-trapping-math)
  # a * b + c stays two roundings, never one fused multiply-add: the lane
  # loops are also compiled for CPUs with FMA (core/lane_clones.h), and every
  # copy must give the values of the baseline build, bit for bit.
  target_compile_options(${name} PRIVATE -ffp-contract=off)
endfunction()
