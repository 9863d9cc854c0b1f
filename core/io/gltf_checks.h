// What a glTF file (.gltf or .glb) must satisfy before Assimp reads it: Assimp
// 5.2.5 leaks, reads out of bounds or misreads on some malformed ones (each
// found by the fuzz target fuzz_model and reproduced with Assimp alone).
#pragma once

#include <optional>
#include <string>

namespace penumbra {

/// Why Assimp must not read these bytes as glTF, or nullopt: the JSON (the
/// whole file, or a binary glTF's JSON chunk) is not valid UTF-8 JSON, a data:
/// URI holds a character outside ASCII, a string starts with U+0010, or an
/// accessor or buffer view reaches past what it views.
std::optional<std::string> gltfProblem(const std::string& bytes);

}  // namespace penumbra
