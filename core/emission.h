// The radiance an emissive material sends out at a point: ke times its
// emissive texture (Material::emissiveMap) where the point lies on a mesh
// triangle with texture coordinates, else ke. The one rule for what a ray
// that meets an emitter sees (shading/surface_shading.h) and what a light
// sample of it carries (lights/area_light.h), so the two always agree.
#pragma once

#include "core/color.h"
#include "core/hit.h"
#include "core/material.h"
#include "core/math.h"

namespace penumbra {

class Scene;
class TextureCache;

/// Whether m's emission varies over a mesh: it has an emissive texture that `textures` decoded.
bool texturedEmission(const Material& m, const TextureCache* textures);

/// m's emission at texture coordinates uv0 (the first set) and uv1 (the second).
Rgb emittedRadiance(const Material& m, const TextureCache* textures, Vec2f uv0, Vec2f uv1);

/// m's emission where `hit` lies (m is the hit's material).
Rgb emittedRadiance(const Scene& scene, const TextureCache* textures, const Material& m, const Hit& hit);

/// The mean of m's emission over its texture (ke where it has none): what
/// the light's power, which only steers light selection, is computed from.
Rgb meanEmittedRadiance(const Material& m, const TextureCache* textures);

}  // namespace penumbra
