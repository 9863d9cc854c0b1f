// An input file opened once, by descriptor, right after the path check. Every
// loader reads scene files, OBJ, MTL and meshes through it, and hands textures
// on as open files (docs: /work/notes/texture-fd.md), so no file is checked by
// name and then reopened by name (a symlink swapped in between cannot redirect
// the read), and what is not a regular file (a FIFO, a device, a directory) is
// refused before anything blocks on it or reads it without end.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "core/error.h"
#include "core/io/load_options.h"

namespace penumbra {

class InputFile {
public:
    InputFile(int fd, std::filesystem::path path, std::uint64_t size) noexcept
        : fd_(fd), path_(std::move(path)), size_(size) {}
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    /// Read with pread (the descriptor may be shared; its offset is not used).
    int fd() const noexcept { return fd_; }
    /// The name the loader resolved, for messages (never to reopen the file).
    const std::filesystem::path& path() const noexcept { return path_; }
    /// st_size when the file was opened.
    std::uint64_t size() const noexcept { return size_; }
    /// The whole file; Error(IoError) naming path() when a read fails.
    std::string readAll() const;

private:
    int fd_;
    std::filesystem::path path_;
    std::uint64_t size_;
};

/// Checks `file` against options.allowedRoots, opens it (without blocking and
/// without becoming a controlling terminal), refuses what is not a regular file
/// ("<file>: is not a regular file (it is a FIFO)"), and checks the path of
/// the file actually opened against the allowed roots again. Errors name
/// `file`: FileNotFound for a missing file, InvalidArgument for a refused
/// path, `notRegular` for a directory, FIFO, device or socket, IoError for a
/// symlink loop and anything else that cannot be opened.
std::unique_ptr<InputFile> openInputFile(const std::filesystem::path& file, const LoadOptions& options,
                                         ErrorCode notRegular = ErrorCode::IoError);

}  // namespace penumbra
