// Hit to shading point, the one way every integrator builds it: both normals
// turned to the side the ray arrived from (shading is two-sided), the
// direction back along the ray, and the material after texturing, filtered
// over the pixel's footprint at the hit (a ray cone): the diffuse albedo; a
// normal map's shading normal; the metal-roughness model's base colour,
// metallic and roughness; and, asked apart, the emission (core/emission.h).
// Phong materials without a normal map take none of that work.
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
    /// mirrorRoughness: metal-roughness points at or below this roughness
    /// leave their specular lobe to a mirror bounce (ShadingPoint::mirrorSpecular);
    /// negative: none do.
    SurfaceShading(const Scene& scene, const TextureCache* textures, float pixelSpread, float mirrorRoughness = -1.f)
        : scene_(scene), textures_(textures), pixelSpread_(pixelSpread), mirrorRoughness_(mirrorRoughness),
          convexMeshes_(scene.convexMeshes()) {}

    /// Writes into sp the shading point of a hit reached along `ray` after
    /// pathLength, in place: a lane's shading point is read right after.
    void shade(const Hit& hit, const Ray& ray, float pathLength, ShadingPoint& sp) const;

    /// The radiance the emitter at `hit` sends towards the viewer (where
    /// sp.emits()): ke, textured (core/emission.h).
    Rgb emission(const Hit& hit, const ShadingPoint& sp) const;

private:
    /// The texture filter's width in uv units at a hit (0: the finest level).
    float footprint(const Hit& hit, float pathLength, const Vec3f& wo) const;
    Rgb diffuseAlbedo(const Material& m, const Hit& hit, float pathLength, const Vec3f& wo) const;
    /// The normal map and the metal-roughness parameters, where the material has them.
    void shadeMaps(const Material& m, const Hit& hit, float pathLength, ShadingPoint& sp) const;

    const Scene& scene_;
    const TextureCache* textures_;
    float pixelSpread_;
    float mirrorRoughness_;
    const int32_t* convexMeshes_;  // Scene::convexMeshes: null where no mesh is convex
};

}  // namespace penumbra
