// All-or-nothing file output: bytes go to a temporary file in the target's
// folder with checked writes, fsync and close, and only a complete file is
// renamed over the target. A full disk, a file-size limit or an I/O error
// leaves the old target as it was and no temporary file behind.
#pragma once

#include <filesystem>
#include <span>
#include <string>

namespace penumbra {

/// A complete temporary copy of `target`'s new content, renamed into place by
/// commit(); removed by the destructor when not committed.
class StagedFile {
public:
    /// Writes `bytes` to a new temporary file beside `target`. Throws
    /// Error(IoError) "<target>: cannot write <what>: <reason>" (no space, over
    /// the file-size limit, folder not writable...); nothing is left behind.
    StagedFile(const std::filesystem::path& target, std::span<const unsigned char> bytes, const std::string& what);
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;

    /// Renames the temporary file over the target. Throws Error(IoError) (and
    /// removes the temporary file) if the rename fails.
    void commit();

private:
    std::filesystem::path target_, temp_;
    std::string what_;
    bool committed_ = false;
};

/// StagedFile + commit: writes `bytes` to `target` all or nothing.
void writeFileAtomically(const std::filesystem::path& target, std::span<const unsigned char> bytes,
                         const std::string& what);

}  // namespace penumbra
