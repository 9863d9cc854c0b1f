// How deep a model file nests, measured before Assimp reads it. Assimp 5.2.5's
// readers recurse once per level of a file's nesting (FBX scopes and models,
// DirectX .x frames, AC3D child objects, COLLADA nodes and XML elements;
// fbx_checks.h and xml_checks.h have those formats' own), and so do the node
// trees they build, so a file nested 100,000
// deep overflows the stack. Each scan here walks the file once with a loop and
// an explicit stack, reading it as Assimp's tokenizer does where that decides
// the depth, and counts a level wherever it cannot be sure Assimp does not.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra {

/// The deepest a model file may nest: far beyond what modelling tools write
/// (a few dozen levels), far below what overflows a 1 MiB stack in Assimp
/// (512 levels of every format read in 1 MiB).
inline constexpr size_t kMaxModelNesting = 256;

/// The message for a file that nests deeper than kMaxModelNesting: `what`
/// ("FBX scopes") and where the limit was passed ("line 300").
std::string nestingProblem(const std::string& what, const std::string& where);

/// A DirectX .x file whose braces nest deeper than kMaxModelNesting, or a
/// binary or compressed one (their frames cannot be counted without
/// decoding the whole file as Assimp does, so they are refused).
std::optional<std::string> xFileNestingProblem(std::string_view bytes);

/// An AC3D file whose objects' kids nest deeper than kMaxModelNesting, or
/// whose counts (kids, numvert, numsurf, refs) claim more lines than follow.
std::optional<std::string> ac3dNestingProblem(std::string_view bytes);

}  // namespace penumbra
