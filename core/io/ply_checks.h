// What a PLY file must satisfy before Assimp reads it (found by the fuzz
// target fuzz_model and reproduced with Assimp alone).
#pragma once

#include <optional>
#include <string>

namespace penumbra {

/// Assimp 5.2.5's PLY reader loops for ever on a header without a clean
/// `end_header` line (a truncated file, junk after the keyword), reads past
/// its buffer when a header line it does not know shifts properties to
/// another element, and reserves what an element count claims. So PLY
/// headers are checked here first: known lines only, `end_header` alone on
/// its line, and element counts the rest of the file can hold (at least 2
/// bytes per ASCII value, the fixed sizes in binary files).
std::optional<std::string> plyHeaderProblem(const std::string& bytes);

}  // namespace penumbra
