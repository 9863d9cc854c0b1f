// What an FBX file (ASCII or binary) must satisfy before Assimp reads it.
// Assimp 5.2.5 recurses once per nested scope while it parses the file, and
// once per level of the model hierarchy (the Connections between Model
// objects) while it converts it, without looking for cycles: scopes nested
// 100,000 deep, a model connected to itself and a chain of 100,000 models
// each overflowed the stack. The file is walked here with loops, its scopes
// read as Assimp's tokenizer reads them.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace penumbra {

/// Why Assimp must not read these bytes as FBX, or nullopt: scopes (ASCII) or
/// records (binary) nested deeper than kMaxModelNesting, ASCII that Assimp's
/// parser would throw on (it leaks the scopes it has built), Model objects
/// whose connections form a cycle, or a model hierarchy deeper than
/// kMaxModelNesting.
std::optional<std::string> fbxProblem(std::string_view bytes);

}  // namespace penumbra
