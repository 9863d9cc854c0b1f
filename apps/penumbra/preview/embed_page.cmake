# Writes OUTPUT, a C++ header holding the bytes of INPUT as
# `penumbra::preview::kPreviewPage` (a std::string_view), so that the page is
# part of the program and the server reads no file at run time.
# Usage: cmake -DINPUT=page.html -DOUTPUT=preview_page.h -P embed_page.cmake
file(READ "${INPUT}" _hex HEX)
# Every byte as a \xNN escape, 8 to a line: no character of the page can end the literal.
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "\\\\x\\1" _escaped "${_hex}")
string(REGEX REPLACE "((\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f])(\\\\x[0-9a-f][0-9a-f]))" "\\1\"\n    \"" _lines "${_escaped}")
string(LENGTH "${_hex}" _hexLength)
math(EXPR _size "${_hexLength} / 2")
get_filename_component(_name "${INPUT}" NAME)
file(WRITE "${OUTPUT}.tmp" "// Generated from ${_name} by embed_page.cmake: do not edit.
#pragma once

#include <string_view>

namespace penumbra::preview {

inline constexpr std::string_view kPreviewPage{
    \"${_lines}\", ${_size}};

}  // namespace penumbra::preview
")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
