// Materials: the API's value type (api/include/penumbra/types.hpp: Phong with mirror and glass,
// and glTF's metal-roughness model) and what the scene resolved its textures to. The Phong BRDF
// is shading/bsdf/phong.h (docs/rendering.md).
#pragma once

#include <penumbra/types.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/color.h"
#include "core/math.h"
#include "core/texture_source.h"

namespace penumbra {

using PhongModel = pnb::PhongModel;  // api/include/penumbra/types.hpp
using MaterialKind = pnb::MaterialKind;
using AlphaMode = pnb::AlphaMode;
using TextureWrap = pnb::TextureWrap;
using TextureFilter = pnb::TextureFilter;
using TextureSlot = pnb::TextureSlot;

/// A texture slot resolved: which of Scene::textures it samples and how, with
/// the slot's transform as one affine map of image coordinates (s, t).
struct TextureRef {
    int texture = -1;  // index into Scene::textures; -1 = none
    uint8_t uvSet = 0;
    uint8_t channel = 0;
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Linear;
    /// (s', t') = (m[0] s + m[1] t + m[2], m[3] s + m[4] t + m[5]).
    float m[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};

    bool used() const { return texture >= 0; }
    /// The slot's sampling for texture `index` (-1: an unused ref).
    static TextureRef of(const TextureSlot& slot, int index);
    /// Image coordinates of texture coordinates `uv` (OBJ's convention, v up: the scene's), transformed.
    Vec2f imageCoordinates(Vec2f uv) const {
        const float s = uv.x, t = 1.f - uv.y;
        return {m[0] * s + m[1] * t + m[2], m[3] * s + m[4] * t + m[5]};
    }
};

/// The API's material (what a user or a scene file sets, textures as paths)
/// and the textures the scene resolved them to.
struct Material : pnb::Material {
    int textureIndex = -1;  // index into Scene::textures (diffuseTexture's image), multiplies kd; -1 = none
    TextureRef baseColorMap, metallicMap, roughnessMap, transmissionMap, normalMap, emissiveMap, opacityMap;

    bool isEmissive() const { return Rgb(ke).maxComponent() > 0.f; }
    bool isMirror() const { return Rgb(kr).maxComponent() > 0.f; }
    /// Has a Phong lobe (ks > 0): its response needs more than the diffuse term.
    bool isGlossy() const { return Rgb(ks).maxComponent() > 0.f; }
    /// Smooth glass: Fresnel reflection and refraction (shading/bsdf/dielectric.h); kr is not used then.
    bool isDielectric() const { return Rgb(kt).maxComponent() > 0.f; }
    /// Whether a hit on it needs texture coordinates (any texture), the
    /// second uv set, or a tangent frame (a normal or bump map).
    bool needsUv() const {
        return textureIndex >= 0 || baseColorMap.used() || metallicMap.used() || roughnessMap.used() ||
               transmissionMap.used() || normalMap.used() || emissiveMap.used() || opacityMap.used();
    }
    bool needsUv1() const;
    bool needsTangents() const { return normalMap.used(); }
    /// Shaded by the metal-roughness BSDF (shading/bsdf/metal_roughness.h):
    /// the model, unless transmission made it glass (mapTransmissionOntoGlass).
    bool shadedAsMetalRoughness() const { return kind == MaterialKind::MetalRoughness && !isDielectric(); }
};

/// A glTF-style metal-roughness material's transmission
/// (KHR_materials_transmission) as the renderer's smooth dielectric: where
/// transmission * (1 - metallic) > 0 the Phong terms become that glass (kt,
/// the transmitted share of the base colour, refracting with ior) over a
/// diffuse kd (the rest of the non-metal share less 4%), and the material is
/// shaded as those terms; otherwise they hold no ambient, glossy, mirror or
/// glass term (the metal-roughness BSDF shades it) and kd is the base colour.
/// Emission is left as it is.
void mapTransmissionOntoGlass(Material& m);

/// Resolves a material's texture paths (diffuseTexture and every slot's) to
/// Scene::textures indices through `texture`, which gets each non-empty path
/// with the colour space its slot reads (colour slots as the file says, the
/// others linear), may rewrite the path (to the file it resolved), and returns
/// the index or -1 (the path is then cleared). Sets textureIndex and the TextureRefs.
void bindTextures(Material& m, const std::function<int(std::string& path, TextureColorSpace)>& texture);

/// What is wrong with the fields of the metal-roughness model, the slots and
/// alpha ("roughness must lie in [0, 1], got 2"), or nullopt. (The Phong terms
/// are checked where they are read.)
std::optional<std::string> materialProblem(const pnb::Material& m);

}  // namespace penumbra
