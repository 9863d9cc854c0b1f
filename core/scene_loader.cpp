// Scene-file dispatch, path restriction and automatic framing; the formats
// themselves live in obj_loader.cpp and scene_file.cpp.
#include "core/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
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

LoadedScene loadScene(const fs::path& path, const LoadOptions& options, const Logger& log) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".obj") return loadObjScene(path, options, log);
    if (ext == ".json") return loadJsonScene(path, options, log);
    throw Error(ErrorCode::InvalidArgument, path.string() + ": unknown scene format (expected .obj or .json)");
}

CameraDesc frameBounds(const Bounds3f& bounds, float vfovDegrees, float aspect) {
    CameraDesc cam;
    if (std::isfinite(vfovDegrees) && vfovDegrees > 0.f && vfovDegrees < 180.f) cam.vfovDegrees = vfovDegrees;
    if (bounds.empty() || !isFinite(bounds.lo) || !isFinite(bounds.hi)) return cam;

    const Vec3f center = bounds.center();
    const Vec3f half = bounds.diagonal() * 0.5f;
    const float halfV = 0.5f * cam.vfovDegrees * kPi / 180.f;
    const float a = std::isfinite(aspect) && aspect > 0.f ? aspect : 1.f;
    const float tanV = std::tan(halfV), tanH = a * tanV;
    // Fit the box's front face (the corners nearest the camera are the
    // hardest to fit), with a 5% margin: tighter than a bounding sphere.
    float distance = half.z + 1.05f * std::max(half.x / tanH, half.y / tanV);
    if (!(distance > 0.f) || !std::isfinite(distance)) distance = 1.f;  // a single point: any distance shows it
    cam.lookAt = center;
    cam.eye = center + Vec3f{0.f, 0.f, distance};
    cam.up = Vec3f{0.f, 1.f, 0.f};
    return cam;
}

}  // namespace penumbra
