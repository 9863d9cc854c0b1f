// Pinhole / thin-lens camera. Right-handed; `up` maps to the top of the image,
// row 0 is the top row, the vertical field of view is given in degrees.
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "core/ray_lanes.h"

namespace penumbra {

/// What places the camera: the API's value type (api/include/penumbra/types.hpp).
using CameraDesc = pnb::Camera;

/// What is wrong with the camera (eye == lookAt, up parallel to the view
/// direction, fov outside (0, 180), non-finite values, negative aperture), or
/// nullptr when nothing is.
const char* cameraProblem(const CameraDesc& desc);
/// Throws Error(InvalidArgument) with cameraProblem's message.
void validateCamera(const CameraDesc& desc);

class Camera {
public:
    /// `desc` must be valid: the API checks it (validateCamera), so this only asserts.
    Camera(const CameraDesc& desc, int width, int height);

    /// Ray through film position (px, py) in pixels (continuous: pixel (x, y)
    /// covers [x, x+1) x [y, y+1)), with lens sample uLens in [0,1)^2.
    Ray generateRay(float px, float py, Vec2f uLens) const {
        const Vec3f dir = filmDirection(px, py);
        if (desc_.aperture <= 0.f) return Ray{desc_.eye, normalize(dir), 0.f, kInfinity};
        return lensRay(dir, uLens);
    }

    /// generateRay for the film positions (filmX[l], filmY[l]) (pixels) and
    /// lens samples lens[l] of the first n lanes, the same rays, written as
    /// lanes (out.active: 1 for the first n, 0 after), the form the packet
    /// query reads. A pinhole camera's are made in a loop over the lanes that
    /// vectorises; lens may be null for a pinhole camera.
    void generateRayLanes(const float* filmX, const float* filmY, const Vec2f* lens, int n, RayLanes& out) const;

    const CameraDesc& desc() const { return desc_; }

private:
    /// The unnormalised direction through film position (px, py): film
    /// coordinates in [-1, 1]; y grows downwards on the film, up in the world.
    Vec3f filmDirection(float px, float py) const {
        const float sx = (px * invWidth2_ - 1.f) * halfWidth_;
        const float sy = (1.f - py * invHeight2_) * halfHeight_;
        return sx * u_ + sy * v_ - w_;
    }
    Ray lensRay(const Vec3f& dir, Vec2f uLens) const;

    CameraDesc desc_;
    Vec3f u_, v_, w_;  // camera frame: right, up, backwards
    float halfWidth_, halfHeight_;
    float focus_;
    int width_, height_;
    float invWidth2_, invHeight2_;  // 2 / width, 2 / height
};

}  // namespace penumbra
