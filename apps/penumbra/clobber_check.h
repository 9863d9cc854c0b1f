// Refusing outputs that would overwrite an input: the render's files are
// compared by identity (device and inode), so links and different spellings
// of one path are caught, and different files with equal names are not.
#pragma once

#include <filesystem>
#include <string>

namespace penumbra::cli {

/// One file the command writes, and how the user named it ("-o", "--stats-json").
struct OutputFile {
    std::filesystem::path path;
    std::string option;
};

/// Throws pnb::Error(InvalidArgument) when `output` is the file `input`
/// (`inputRole` says what it is: "the scene file", "a file the scene reads").
/// Outputs that do not exist yet overwrite nothing.
void refuseOverwrite(const OutputFile& output, const std::filesystem::path& input, const std::string& inputRole);

/// Throws when two outputs name the same file (existing or to be created).
void refuseSameOutput(const OutputFile& a, const OutputFile& b);

}  // namespace penumbra::cli
