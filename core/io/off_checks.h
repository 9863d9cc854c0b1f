// What an OFF file must satisfy before Assimp reads it: Assimp 5.2.5's OFF
// reader allocates what the header's counts claim, before it reads a vertex,
// and its number parser wraps around past 2^32 - 1 (a 110-byte file made it ask
// for 32 GiB: found by the fuzz target fuzz_model, reproduced with Assimp alone).
#pragma once

#include <optional>
#include <string>

namespace penumbra {

/// Why Assimp must not read these bytes as OFF, or nullopt: the header's vertex
/// or face count does not fit in 32 bits, or claims more lines than the file
/// has (every vertex and every face takes a line of its own). The header is
/// read as Assimp reads it: optional ST, C, N, 4 and n prefixes, the keyword
/// OFF (which may be missing), the dimension after an n, then the counts;
/// blank lines and lines starting with # are skipped.
std::optional<std::string> offHeaderProblem(const std::string& bytes);

}  // namespace penumbra
