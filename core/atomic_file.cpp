#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "core/error.h"

namespace penumbra {
namespace fs = std::filesystem;
namespace {

// A unique hidden name beside the target: pid + clock tick + a counter keep
// concurrent writers (processes or threads) apart; O_EXCL catches the rest.
fs::path temporaryPathFor(const fs::path& target, int attempt) {
    const auto tick = std::chrono::steady_clock::now().time_since_epoch().count();
    std::string name(".");
    name += target.filename().string();
    name += ".tmp-";
    name += std::to_string(::getpid());
    name += '-';
    name += std::to_string(tick);
    name += '-';
    name += std::to_string(attempt);
    return target.parent_path() / name;
}

std::string errnoText(int e) { return std::strerror(e); }

}  // namespace

StagedFile::StagedFile(const fs::path& target, std::span<const unsigned char> bytes, const std::string& what)
    : target_(target), what_(what) {
    auto fail = [&](const std::string& why) -> void {
        throw Error(ErrorCode::IoError, target_.string() + ": cannot write " + what_ + ": " + why);
    };
    // Beyond RLIMIT_FSIZE the kernel sends SIGXFSZ, which ends the process
    // unless the host ignores it: refuse before writing instead.
    rlimit limit{};
    if (::getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
        rlim_t(bytes.size()) > limit.rlim_cur)
        fail(std::to_string(bytes.size()) + " bytes exceed the file size limit of " +
             std::to_string(uint64_t(limit.rlim_cur)) + " bytes (ulimit -f)");

    int fd = -1;
    for (int attempt = 0; fd < 0 && attempt < 16; ++attempt) {
        temp_ = temporaryPathFor(target_, attempt);
        fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) break;
    }
    if (fd < 0) {
        const int e = errno;
        temp_.clear();
        fail("cannot create a file in its folder (" + errnoText(e) + ")");
    }
    auto failAndRemove = [&](const std::string& why) {
        ::close(fd);
        ::unlink(temp_.c_str());
        temp_.clear();
        fail(why);
    };
    // Reserve the space first where the file system can: a full disk fails here, before any byte.
    if (!bytes.empty() && ::fallocate(fd, 0, 0, off_t(bytes.size())) != 0) {
        const int e = errno;
        if (e != EOPNOTSUPP && e != ENOSYS && e != EINVAL) failAndRemove(errnoText(e));
    }
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) failAndRemove(errnoText(errno));
        if (n == 0) failAndRemove(errnoText(ENOSPC));
        done += size_t(n);
    }
    // Data on disk before the name points at it; a file system without fsync (EINVAL) has nothing to flush.
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) failAndRemove(errnoText(errno));
    if (::close(fd) != 0 && errno != EINTR) {
        const int e = errno;
        ::unlink(temp_.c_str());
        temp_.clear();
        fail(errnoText(e));
    }
}

StagedFile::~StagedFile() {
    if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void StagedFile::commit() {
    if (committed_ || temp_.empty()) return;
    if (::rename(temp_.c_str(), target_.c_str()) != 0) {
        const int e = errno;
        ::unlink(temp_.c_str());
        temp_.clear();
        throw Error(ErrorCode::IoError, target_.string() + ": cannot write " + what_ + ": " + errnoText(e));
    }
    committed_ = true;
    // Make the rename itself durable; a folder that cannot be opened or synced changes nothing above.
    fs::path dir = target_.parent_path().empty() ? fs::path(".") : target_.parent_path();
    int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        (void)::fsync(dfd);
        ::close(dfd);
    }
}

void writeFileAtomically(const fs::path& target, std::span<const unsigned char> bytes, const std::string& what) {
    StagedFile staged(target, bytes, what);
    staged.commit();
}

}  // namespace penumbra
