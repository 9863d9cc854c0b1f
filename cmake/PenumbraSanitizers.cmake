# Sanitizer and fuzzing switches for Penumbra's own targets.
#
#   PENUMBRA_SANITIZE   a list of -fsanitize= checks, e.g. "address;undefined"
#                       (the asan preset), "thread", or "address;undefined;fuzzer-no-link"
#                       (the fuzz preset: coverage for libFuzzer without its main()).
#   PENUMBRA_FUZZ       build the libFuzzer targets in tests/fuzz (clang only).
#
# Included before the modules are added, so every target of the project gets
# the flags (directory scope). UBSan findings abort instead of printing and
# going on, so a test or fuzz run fails on them.
set(PENUMBRA_SANITIZE "" CACHE STRING "Sanitizers for Penumbra's targets, e.g. address;undefined")
option(PENUMBRA_FUZZ "Build the libFuzzer targets (clang only)" OFF)

if(PENUMBRA_SANITIZE)
  list(JOIN PENUMBRA_SANITIZE "," _penumbra_sanitizers)
  add_compile_options(-fsanitize=${_penumbra_sanitizers} -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${_penumbra_sanitizers})
  if("undefined" IN_LIST PENUMBRA_SANITIZE)
    add_compile_options(-fno-sanitize-recover=undefined)
  endif()
  message(STATUS "Penumbra: sanitizers ${_penumbra_sanitizers}")
endif()
