#include "core/camera.h"

#include "core/error.h"
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
}

Ray Camera::generateRay(float px, float py, Vec2f uLens) const {
    // Film coordinates in [-1, 1]; y grows downwards on the film, up in the world.
    float sx = (2.f * px / static_cast<float>(width_) - 1.f) * halfWidth_;
    float sy = (1.f - 2.f * py / static_cast<float>(height_)) * halfHeight_;
    Vec3f dir = sx * u_ + sy * v_ - w_;
    if (desc_.aperture <= 0.f) return Ray{desc_.eye, normalize(dir), 0.f, kInfinity};
    // Thin lens: all rays through a film point meet on the focus plane.
    Vec3f focusPoint = desc_.eye + dir * focus_;
    Vec2f lens = squareToConcentricDisk(uLens);
    Vec3f o = desc_.eye + desc_.aperture * (lens.x * u_ + lens.y * v_);
    return Ray{o, normalize(focusPoint - o), 0.f, kInfinity};
}

}  // namespace penumbra
