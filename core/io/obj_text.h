// Small text helpers shared by the OBJ and MTL readers (tokens, lines, numbers).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::obj_text {

inline bool isBlank(char c) { return c == ' ' || c == '\t'; }
std::string_view trim(std::string_view s);
std::vector<std::string_view> splitBlank(std::string_view s);
bool iequals(std::string_view a, std::string_view b);
void stripBom(std::string& s);
/// OBJ and MTL are text: a NUL byte means binary data (or UTF-16), which
/// tinyobjloader would read as garbage. Returns "<line>: ..." naming the first one.
std::optional<std::string> binaryDataProblem(std::string_view text);
/// A token from a file, made safe for a one-line message: printable ASCII
/// only, and at most 40 characters.
std::string printable(std::string_view tok);
/// Splits text into lines the way tinyobjloader does (\n, \r\n or a lone \r).
std::vector<std::string_view> splitLines(std::string_view text);
/// A coordinate token is usable when it is a complete, finite number as a float
/// (`nan`, `inf`, `1e39`, `1.#IND` and garbage are not).
bool finiteNumber(std::string_view tok);

}  // namespace penumbra::obj_text
