// Inputs Assimp 5.2.5 is known to mishandle (hang on, crash on, read out of
// bounds on, leak, or exhaust memory on), refused before it sees them: one
// check per format, each in a file of its own, chosen here by extension.
// docs/mtl-mapping.md ("Checked before Assimp") lists them for users.
#pragma once

#include <optional>
#include <string>

namespace penumbra {

/// Why Assimp must not read `bytes` as a `format` file (the extension, lower
/// case, without the dot), or nullopt.
std::optional<std::string> modelFileProblem(const std::string& format, const std::string& bytes);

}  // namespace penumbra
