// Pinhole / thin-lens camera. Right-handed; `up` maps to the top of the image,
// row 0 is the top row, the vertical field of view is given in degrees.
#pragma once

#include "core/math.h"
#include "core/ray.h"

namespace penumbra {

struct CameraDesc {
    Vec3f eye{0.f, 1.f, 3.f};
    Vec3f lookAt{0.f, 1.f, 0.f};
    Vec3f up{0.f, 1.f, 0.f};
    float vfovDegrees = 45.f;
    float aperture = 0.f;       // lens radius; 0 = pinhole
    float focusDistance = 0.f;  // 0 = distance from eye to lookAt
};

/// Throws Error(InvalidArgument) naming the problem: eye == lookAt, up parallel
/// to the view direction, fov outside (0, 180), non-finite values, negative aperture.
void validateCamera(const CameraDesc& desc);

class Camera {
public:
    Camera(const CameraDesc& desc, int width, int height);

    /// Ray through film position (px, py) in pixels (continuous: pixel (x, y)
    /// covers [x, x+1) x [y, y+1)), with lens sample uLens in [0,1)^2.
    Ray generateRay(float px, float py, Vec2f uLens) const {
        // Film coordinates in [-1, 1]; y grows downwards on the film, up in the world.
        const float sx = (px * invWidth2_ - 1.f) * halfWidth_;
        const float sy = (1.f - py * invHeight2_) * halfHeight_;
        const Vec3f dir = sx * u_ + sy * v_ - w_;
        if (desc_.aperture <= 0.f) return Ray{desc_.eye, normalize(dir), 0.f, kInfinity};
        return lensRay(dir, uLens);
    }

    const CameraDesc& desc() const { return desc_; }

private:
    Ray lensRay(const Vec3f& dir, Vec2f uLens) const;

    CameraDesc desc_;
    Vec3f u_, v_, w_;  // camera frame: right, up, backwards
    float halfWidth_, halfHeight_;
    float focus_;
    int width_, height_;
    float invWidth2_, invHeight2_;  // 2 / width, 2 / height
};

}  // namespace penumbra
