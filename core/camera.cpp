#include "core/camera.h"

#include <algorithm>
#include <cassert>

#include "core/error.h"
#include "core/lane_clones.h"
#include "core/sampling.h"

namespace penumbra {

const char* cameraProblem(const CameraDesc& d) {
    if (!isFinite(d.eye) || !isFinite(d.lookAt) || !isFinite(d.up)) return "camera: eye, look-at and up must be finite";
    Vec3f view = d.lookAt - d.eye;
    if (!(lengthSquared(view) > 0.f)) return "camera: eye and look-at are the same point";
    if (!(lengthSquared(d.up) > 0.f)) return "camera: up vector is zero";
    Vec3f vn = normalize(view), un = normalize(d.up);
    if (lengthSquared(cross(vn, un)) < 1e-10f) return "camera: up vector is parallel to the view direction";
    if (!(d.vfovDegrees > 0.f && d.vfovDegrees < 180.f)) return "camera: fov must lie in (0, 180) degrees";
    if (!std::isfinite(d.aperture) || d.aperture < 0.f) return "camera: aperture must be finite and >= 0";
    if (!std::isfinite(d.focusDistance) || d.focusDistance < 0.f) return "camera: focus distance must be finite and >= 0";
    return nullptr;
}

void validateCamera(const CameraDesc& d) {
    if (const char* problem = cameraProblem(d)) throw Error(ErrorCode::InvalidArgument, problem);
}

Camera::Camera(const CameraDesc& desc, int width, int height) : desc_(desc), width_(width), height_(height) {
    assert(!cameraProblem(desc));
    w_ = normalize(desc.eye - desc.lookAt);
    u_ = normalize(cross(desc.up, w_));
    v_ = cross(w_, u_);
    halfHeight_ = std::tan(0.5f * desc.vfovDegrees * kPi / 180.f);
    halfWidth_ = halfHeight_ * static_cast<float>(width) / static_cast<float>(height);
    focus_ = desc.focusDistance > 0.f ? desc.focusDistance : length(desc.lookAt - desc.eye);
    invWidth2_ = 2.f / static_cast<float>(width);
    invHeight2_ = 2.f / static_cast<float>(height);
}

PENUMBRA_LANE_CLONES void Camera::generateRayLanes(const float* filmX, const float* filmY, const Vec2f* lens, int n,
                                                   RayLanes& out) const {
    for (int l = 0; l < RayLanes::kWidth; ++l) out.active[l] = l < n;
    if (desc_.aperture > 0.f) {
        for (int l = 0; l < n; ++l) out.set(l, generateRay(filmX[l], filmY[l], lens[l]));
        return;
    }
    const Vec3f eye = desc_.eye;
    for (int l = 0; l < n; ++l) {
        const Vec3f d = normalize(filmDirection(filmX[l], filmY[l]));
        out.ox[l] = eye.x;
        out.oy[l] = eye.y;
        out.oz[l] = eye.z;
        out.dx[l] = d.x;
        out.dy[l] = d.y;
        out.dz[l] = d.z;
        out.tnear[l] = 0.f;
        out.tfar[l] = kInfinity;
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
