// Path restriction: component-wise prefix tests on canonical paths.
#include "core/io/path_policy.h"

#include <algorithm>
#include <system_error>

#include "core/error.h"

namespace penumbra {
namespace fs = std::filesystem;

namespace {

// Symlinks resolved where the path exists; lexically normalised beyond that.
fs::path canonicalish(const fs::path& p) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(p, ec);
    if (ec) c = fs::absolute(p, ec).lexically_normal();
    return c;
}

// Component-wise prefix test, so "/data/scenes2" is not below "/data/scenes".
bool isBelow(const fs::path& file, const fs::path& root) {
    auto f = file.begin();
    for (auto r = root.begin(); r != root.end(); ++r) {
        if (r->empty()) continue;  // trailing separator
        if (f == file.end() || *f != *r) return false;
        ++f;
    }
    return true;
}

}  // namespace

void checkPathAllowed(const fs::path& file, const LoadOptions& options, bool willRead) {
    if (options.allowedRoots.empty()) {
        if (willRead && options.onReadOutside && !options.noticeRoots.empty()) {
            const fs::path f = canonicalish(file);
            const bool inside = std::any_of(options.noticeRoots.begin(), options.noticeRoots.end(),
                                            [&](const fs::path& r) { return isBelow(f, canonicalish(r)); });
            if (!inside) options.onReadOutside(f);
        }
        return;
    }
    fs::path f = canonicalish(file);
    for (const auto& root : options.allowedRoots)
        if (isBelow(f, canonicalish(root))) return;
    throw Error(ErrorCode::InvalidArgument, file.string() + ": outside the allowed directories");
}

}  // namespace penumbra
