// What an ASCII STL file must satisfy before Assimp reads it (found by the
// fuzz target fuzz_model and reproduced with Assimp alone).
#pragma once

#include <optional>
#include <string>

namespace penumbra {

/// Assimp 5.2.5's ASCII STL reader keeps each solid's aiMesh and aiNode in
/// local vectors until the file is read, so when it throws inside a solid they
/// leak (2,464 bytes; LeakSanitizer in fuzz_model, reproduced with
/// Importer::ReadFileFromMemory alone): a facet of other than three vertices, a
/// number it cannot parse ("1e", "abc"), a line break inside a vertex, a file
/// that ends in a facet, a name of 1024 bytes. So a file it would read as ASCII
/// (text starting with "solid", after a UTF-8 byte-order mark, whose size is not
/// a binary STL's for the count at byte 80, as its IsBinarySTL decides) must be
/// well formed here first: solids of facets of three vertices, one statement a
/// line, numbers as C writes them, no control characters. UTF-16 and UTF-32
/// text, which it converts first, is refused.
std::optional<std::string> stlTextProblem(const std::string& bytes);

}  // namespace penumbra
