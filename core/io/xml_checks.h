// What an XML model file (COLLADA, and the other XML formats Assimp reads)
// must satisfy before Assimp reads it. Assimp 5.2.5 parses XML with pugixml,
// without recursion, but then walks the elements recursively (XmlNodeIterator,
// its COLLADA reader's nodes), expands COLLADA's <instance_node> references
// into copies without looking for cycles, and trusts COLLADA's counts and
// indices; each problem below crashed, hung or exhausted memory in Assimp
// alone. The file is parsed here with pugixml too (the one file that includes
// it) and walked with loops.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace penumbra {

/// The most nodes a COLLADA node tree may hold with its <instance_node>
/// references expanded (Assimp copies the instanced nodes, over 1 KiB each).
inline constexpr size_t kMaxModelNodes = 1'000'000;

/// Why Assimp must not read these bytes as an XML model, or nullopt: not
/// well-formed XML, or elements nested deeper than kMaxModelNesting. With
/// `collada` also: a node that instances itself or an ancestor, a node tree
/// deeper than kMaxModelNesting or larger than kMaxModelNodes once instances
/// are expanded, a controller chain that loops, a data array whose count is
/// more than the values it holds, an accessor that reads past its array, a
/// primitive without a VERTEX input, or indices that are not integers.
std::optional<std::string> xmlModelProblem(const std::string& bytes, bool collada);

}  // namespace penumbra
