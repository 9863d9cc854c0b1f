// Scene-file dispatch and automatic framing; the formats live in obj_loader.cpp,
// assimp_loader.cpp (through model_file.cpp) and json_loader.cpp, the path policy in path_policy.cpp.
#include "core/io/scene_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/error.h"
#include "core/io/model_file.h"

namespace penumbra {
namespace fs = std::filesystem;

LoadedScene loadScene(const fs::path& path, const LoadOptions& options, const Logger& log) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    if (ext == ".obj") return loadObjScene(path, options, log);
    if (ext == ".json") return loadJsonScene(path, options, log);
    if (isModelExtension(ext)) return loadModelScene(path, options, log);
    throw Error(ErrorCode::InvalidArgument, path.string() + ": unknown scene format " +
                                                (ext.empty() ? std::string("(no extension)") : "'" + ext + "'") +
                                                " (supported: .json, " + modelFormatsText() + ")");
}

namespace {

/// The camera along direction `toEye` (unit, from the centre towards the eye)
/// at the distance where every corner of the box fits the view with a 5% margin.
CameraDesc frameAlong(const Bounds3f& bounds, const Vec3f& toEye, float tanH, float tanV, CameraDesc cam) {
    const Vec3f center = bounds.center();
    const Vec3f w = toEye, u = normalize(cross(Vec3f{0.f, 1.f, 0.f}, w)), v = cross(w, u);
    float distance = 0.f;
    for (int k = 0; k < 8; ++k) {
        const Vec3f corner{k & 1 ? bounds.hi.x : bounds.lo.x, k & 2 ? bounds.hi.y : bounds.lo.y,
                           k & 4 ? bounds.hi.z : bounds.lo.z};
        const Vec3f r = corner - center;
        distance = std::max(distance, dot(r, w) + 1.05f * std::max(std::fabs(dot(r, u)) / tanH, std::fabs(dot(r, v)) / tanV));
    }
    if (!(distance > 0.f) || !std::isfinite(distance)) distance = 1.f;
    cam.lookAt = center;
    cam.eye = center + distance * w;
    cam.up = Vec3f{0.f, 1.f, 0.f};
    return cam;
}

}  // namespace

CameraDesc frameBounds(const Bounds3f& bounds, float vfovDegrees, float aspect) {
    CameraDesc cam;
    if (std::isfinite(vfovDegrees) && vfovDegrees > 0.f && vfovDegrees < 180.f) cam.vfovDegrees = vfovDegrees;
    if (bounds.empty() || !isFinite(bounds.lo) || !isFinite(bounds.hi)) return cam;

    const Vec3f center = bounds.center();
    const Vec3f half = bounds.diagonal() * 0.5f;
    const float halfV = 0.5f * cam.vfovDegrees * kPi / 180.f;
    const float a = std::isfinite(aspect) && aspect > 0.f ? aspect : 1.f;
    const float tanV = std::tan(halfV), tanH = a * tanV;
    // A model seen almost edge-on from the front (its box's face towards +z
    // under a quarter of its largest face: a plane lying flat, a thin slab
    // standing sideways) is seen from a raised three-quarter view instead:
    // 45 degrees round from +z towards +x, 30 degrees up. Everything else
    // keeps the front view, which rooms open towards +z (a Cornell box) need.
    const float front = half.x * half.y, largest = std::max({front, half.x * half.z, half.y * half.z});
    if (front < 0.25f * largest) {
        const float up = 30.f * kPi / 180.f, round = 45.f * kPi / 180.f;
        const Vec3f toEye{std::cos(up) * std::sin(round), std::sin(up), std::cos(up) * std::cos(round)};
        return frameAlong(bounds, toEye, tanH, tanV, cam);
    }
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
