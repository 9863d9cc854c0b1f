// POSIX opening and reading; the path check of the opened file goes through
// /proc/self/fd, the kernel's own name for the file behind the descriptor.
#include "core/io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "core/io/path_policy.h"

namespace penumbra {
namespace fs = std::filesystem;

namespace {

const char* kindOf(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a file";
}

[[noreturn]] void throwOpenError(const fs::path& file, int err) {
    const std::string name = file.string();
    switch (err) {
        case ENOENT: throw Error(ErrorCode::FileNotFound, name + ": file not found");
        case ENOTDIR: throw Error(ErrorCode::FileNotFound, name + ": file not found (a folder on its path is a file)");
        case ELOOP: throw Error(ErrorCode::IoError, name + ": symlink loop (too many levels of symbolic links)");
        case EACCES:
        case EPERM: throw Error(ErrorCode::IoError, name + ": cannot open for reading (permission denied)");
        case ENXIO: throw Error(ErrorCode::IoError, name + ": is not a regular file (a device or socket without a reader)");
        default: throw Error(ErrorCode::IoError, name + ": cannot open for reading (" + std::strerror(err) + ")");
    }
}

/// Closes a descriptor unless released.
struct FdGuard {
    int fd;
    ~FdGuard() {
        if (fd >= 0) ::close(fd);
    }
};

/// The path of the file behind `fd` as the kernel knows it; empty when /proc is not there.
fs::path openedPath(int fd) {
    std::error_code ec;
    fs::path p = fs::read_symlink("/proc/self/fd/" + std::to_string(fd), ec);
    return ec ? fs::path() : p;
}

}  // namespace

InputFile::~InputFile() {
    if (fd_ >= 0) ::close(fd_);
}

std::string InputFile::readAll() const {
    auto readAt = [&](char* dst, size_t n, size_t offset) -> size_t {
        for (;;) {
            ssize_t r = ::pread(fd_, dst, n, static_cast<off_t>(offset));
            if (r >= 0) return static_cast<size_t>(r);
            if (errno != EINTR)
                throw Error(ErrorCode::IoError, path_.string() + ": read error (" + std::strerror(errno) + ")");
        }
    };
    std::string out(static_cast<size_t>(size_), '\0');
    size_t have = 0;
    while (have < out.size()) {
        const size_t n = readAt(out.data() + have, out.size() - have, have);
        if (n == 0) break;  // shrunk since fstat
        have += n;
    }
    out.resize(have);
    if (have == size_) {
        // Grown since fstat: read on to the end, in chunks.
        char chunk[65536];
        while (const size_t n = readAt(chunk, sizeof chunk, have)) {
            out.append(chunk, n);
            have += n;
        }
    }
    return out;
}

std::unique_ptr<InputFile> openInputFile(const fs::path& file, const LoadOptions& options, ErrorCode notRegular) {
    // By name first: a refused path is never opened (opening alone can have effects on devices).
    checkPathAllowed(file, options, /*willRead=*/false);
    int raw;
    do {
        raw = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    } while (raw < 0 && errno == EINTR);
    if (raw < 0) throwOpenError(file, errno);
    FdGuard fd{raw};

    struct stat st {};
    if (::fstat(fd.fd, &st) != 0) throwOpenError(file, errno);
    if (!S_ISREG(st.st_mode)) {
        const std::string kind = kindOf(st.st_mode);
        throw Error(notRegular, file.string() + ": is not a regular file (it is " + kind + ")");
    }
    // Regular files never block; clearing the flag keeps reads plain.
    if (int flags = ::fcntl(fd.fd, F_GETFL); flags >= 0) ::fcntl(fd.fd, F_SETFL, flags & ~O_NONBLOCK);

    // Then the file actually opened: a symlink that changed since the check by name cannot lead outside.
    const fs::path real = openedPath(fd.fd);
    if (real.empty()) {
        if (!options.allowedRoots.empty())
            throw Error(ErrorCode::InvalidArgument,
                        file.string() + ": cannot verify where the opened file lies (/proc/self/fd is not available)");
        checkPathAllowed(file, options);
    } else {
        try {
            checkPathAllowed(real, options);
        } catch (const Error& e) {
            throw Error(e.code(), file.string() + ": outside the allowed directories (opened " + real.string() + ")");
        }
    }
    auto out = std::make_unique<InputFile>(fd.fd, file, static_cast<std::uint64_t>(st.st_size));
    fd.fd = -1;
    return out;
}

}  // namespace penumbra
