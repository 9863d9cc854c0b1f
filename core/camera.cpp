#include "core/camera.h"

#include <algorithm>

#include "core/error.h"
#include "core/lane_clones.h"
#include "core/sampling.h"

namespace penumbra {

void validateCamera(const CameraDesc& d) {
    if (!isFinite(d.eye) || !isFinite(d.lookAt) || !isFinite(d.up))
        throw Error(ErrorCode::InvalidArgument, "camera: eye, look-at and up must be finite");
    Vec3f view = d.lookAt - d.eye;
    if (!(lengthSquared(view) > 0.f)) throw Error(ErrorCode::InvalidArgument, "camera: eye and look-at are the same point");
    if (!(lengthSquared(d.up) > 0.f)) throw Error(ErrorCode::InvalidArgument, "camera: up vector is zero");
    Vec3f vn = normalize(view), un = normalize(d.up);
    if (lengthSquared(cross(vn, un)) < 1e-10f)
        throw Error(ErrorCode::InvalidArgument, "camera: up vector is parallel to the view direction");
    if (!(d.vfovDegrees > 0.f && d.vfovDegrees < 180.f))
        throw Error(ErrorCode::InvalidArgument, "camera: fov must lie in (0, 180) degrees");
    if (!std::isfinite(d.aperture) || d.aperture < 0.f)
        throw Error(ErrorCode::InvalidArgument, "camera: aperture must be finite and >= 0");
    if (!std::isfinite(d.focusDistance) || d.focusDistance < 0.f)
        throw Error(ErrorCode::InvalidArgument, "camera: focus distance must be finite and >= 0");
}

Camera::Camera(const CameraDesc& desc, int width, int height) : desc_(desc), width_(width), height_(height) {
    validateCamera(desc);
    w_ = normalize(desc.eye - desc.lookAt);
    u_ = normalize(cross(desc.up, w_));
    v_ = cross(w_, u_);
    halfHeight_ = std::tan(0.5f * desc.vfovDegrees * kPi / 180.f);
    halfWidth_ = halfHeight_ * static_cast<float>(width) / static_cast<float>(height);
    focus_ = desc.focusDistance > 0.f ? desc.focusDistance : length(desc.lookAt - desc.eye);
    invWidth2_ = 2.f / static_cast<float>(width);
    invHeight2_ = 2.f / static_cast<float>(height);
}

PENUMBRA_LANE_CLONES void Camera::generateRays(std::span<const Vec2f> film, std::span<const Vec2f> lens, std::span<Ray> out) const {
    if (desc_.aperture > 0.f) {
        for (size_t i = 0; i < film.size(); ++i) out[i] = generateRay(film[i].x, film[i].y, lens[i]);
        return;
    }
    // Directions as arrays (a loop that vectorises), then the rays.
    constexpr size_t kChunk = 16;
    for (size_t b = 0; b < film.size(); b += kChunk) {
        const size_t n = std::min(kChunk, film.size() - b);
        float dx[kChunk], dy[kChunk], dz[kChunk];
        for (size_t i = 0; i < n; ++i) {
            const Vec3f d = normalize(filmDirection(film[b + i].x, film[b + i].y));
            dx[i] = d.x;
            dy[i] = d.y;
            dz[i] = d.z;
        }
        for (size_t i = 0; i < n; ++i) out[b + i] = Ray{desc_.eye, Vec3f{dx[i], dy[i], dz[i]}, 0.f, kInfinity};
    }
}

Ray Camera::lensRay(const Vec3f& dir, Vec2f uLens) const {
    // Thin lens: all rays through a film point meet on the focus plane.
    Vec3f focusPoint = desc_.eye + dir * focus_;
    Vec2f lens = squareToConcentricDisk(uLens);
    Vec3f o = desc_.eye + desc_.aperture * (lens.x * u_ + lens.y * v_);
    return Ray{o, normalize(focusPoint - o), 0.f, kInfinity};
}

}  // namespace penumbra
