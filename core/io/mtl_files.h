// Finding and reading the files an OBJ names: `mtllib` libraries (relative to
// the OBJ) and `map_Kd` textures (relative to their MTL), matching names
// case-insensitively where the exact name does not exist. Each file is checked
// against the path policy, opened once and read from that descriptor.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/io/load_options.h"

namespace penumbra {

/// Finds `rel` below `base`, matching each path component case-insensitively
/// when the exact name does not exist (OBJ files written on Windows often
/// disagree with the files' capitalisation). Returns whatever exists there
/// (a directory or FIFO too: opening it says what it is); nullopt when nothing does.
std::optional<std::filesystem::path> resolveCaseInsensitive(const std::filesystem::path& base,
                                                            const std::filesystem::path& rel);

/// One material library's text, BOM stripped, its numbers checked.
struct MtlText {
    std::filesystem::path file;
    std::string text;
};

/// Reads the `mtllib` files of one OBJ.
class MtlLibraries {
public:
    MtlLibraries(std::filesystem::path objDir, const LoadOptions& options)
        : dir_(std::move(objDir)), options_(options) {}

    /// The library named `matId`; nullopt with a line appended to `warn` when it
    /// cannot be used (missing, not a regular file, binary), or with `error` set
    /// when its path is refused (rethrown by the caller after parsing).
    std::optional<MtlText> read(const std::string& matId, std::string* warn);

    std::optional<Error> error;

private:
    std::filesystem::path dir_;
    const LoadOptions& options_;
};

}  // namespace penumbra
