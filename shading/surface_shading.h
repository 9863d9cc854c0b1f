// Hit to shading point, the one way every integrator builds it: both normals
// turned to the side the ray arrived from (shading is two-sided), the
// direction back along the ray, and the material's diffuse albedo after
// texturing, filtered over the pixel's footprint at the hit (a ray cone).
#pragma once

#include "core/hit.h"
#include "core/ray.h"
#include "core/scene.h"
#include "shading/shading_point.h"

namespace penumbra {

class TextureCache;

class SurfaceShading {
public:
    /// pixelSpread: the angle (radians) one pixel subtends at the camera; it
    /// sizes the texture filter footprint. 0 = the finest level.
    SurfaceShading(const Scene& scene, const TextureCache* textures, float pixelSpread)
        : scene_(scene), textures_(textures), pixelSpread_(pixelSpread) {}

    /// Writes into sp the shading point of a hit reached along `ray` after
    /// pathLength, in place: a lane's shading point is read right after.
    void shade(const Hit& hit, const Ray& ray, float pathLength, ShadingPoint& sp) const;

private:
    Rgb diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const;

    const Scene& scene_;
    const TextureCache* textures_;
    float pixelSpread_;
};

}  // namespace penumbra
