// A surface material: Phong (docs/rendering.md; the BRDF is shading/bsdf/phong.h), mirror and glass.
#pragma once

#include <penumbra/types.hpp>

#include <string>

#include "core/color.h"

namespace penumbra {

using PhongModel = pnb::PhongModel;  // api/include/penumbra/types.hpp

/// The API's material (what a user or a scene file sets, the texture as a
/// path: api/include/penumbra/types.hpp) and what the scene resolved its
/// texture to.
struct Material : pnb::Material {
    int textureIndex = -1;  // index into Scene::textures (diffuseTexture's image), multiplies kd; -1 = none

    bool isEmissive() const { return Rgb(ke).maxComponent() > 0.f; }
    bool isMirror() const { return Rgb(kr).maxComponent() > 0.f; }
    /// Has a Phong lobe (ks > 0): its response needs more than the diffuse term.
    bool isGlossy() const { return Rgb(ks).maxComponent() > 0.f; }
    /// Smooth glass: Fresnel reflection and refraction (shading/bsdf/dielectric.h); kr is not used then.
    bool isDielectric() const { return Rgb(kt).maxComponent() > 0.f; }
};

}  // namespace penumbra
