#include "core/material.h"

#include <algorithm>
#include <utility>
#include <cmath>

namespace penumbra {

TextureRef TextureRef::of(const TextureSlot& slot, int index) {
    TextureRef r;
    if (index < 0) return r;
    r.texture = index;
    r.uvSet = static_cast<uint8_t>(slot.uvSet == 1 ? 1 : 0);
    r.channel = static_cast<uint8_t>(slot.channel >= 0 && slot.channel <= 3 ? slot.channel : 0);
    r.wrapS = slot.wrapS;
    r.wrapT = slot.wrapT;
    r.filter = slot.filter;
    // KHR_texture_transform: T * R * S, with R = [[cos, sin], [-sin, cos]].
    const float c = std::cos(slot.rotation), s = std::sin(slot.rotation);
    const float sx = slot.scale[0], sy = slot.scale[1];
    const float m[6] = {c * sx, s * sy, slot.offset[0], -s * sx, c * sy, slot.offset[1]};
    for (int i = 0; i < 6; ++i) r.m[i] = std::isfinite(m[i]) ? m[i] : (i == 0 || i == 4 ? 1.f : 0.f);
    return r;
}

bool Material::needsUv1() const {
    for (const TextureRef* r : {&baseColorMap, &metallicMap, &roughnessMap, &transmissionMap, &normalMap, &emissiveMap,
                                &opacityMap})
        if (r->used() && r->uvSet == 1) return true;
    return false;
}

void mapTransmissionOntoGlass(Material& m) {
    const float transmitted = m.transmission * (1.f - m.metallic);
    m.ka = m.ks = m.kr = Rgb(0.f);
    if (transmitted > 0.f) {
        // The non-metal, non-transmitted share of the base less the dielectric's 4% specular is
        // diffuse; the smooth dielectric's Fresnel gives the specular part.
        m.kd = (1.f - m.metallic) * (1.f - transmitted) * (1.f - 0.04f) * Rgb(m.baseColor);
        m.kt = transmitted * Rgb(m.baseColor);
    } else {
        m.kd = Rgb(m.baseColor);  // what the albedo AOV of a metal-roughness point shows too
        m.kt = Rgb(0.f);
    }
}

void bindTextures(Material& m, const std::function<int(std::string& path, TextureColorSpace)>& texture) {
    auto bind = [&](std::string& path, TextureColorSpace space) {
        if (path.empty()) return -1;
        const int index = texture(path, space);
        if (index < 0) path.clear();
        return index;
    };
    constexpr TextureColorSpace kColour = TextureColorSpace::FromFile, kData = TextureColorSpace::Linear;
    m.textureIndex = bind(m.diffuseTexture, kColour);
    auto slot = [&](TextureSlot& s, TextureColorSpace space) { return TextureRef::of(s, bind(s.path, space)); };
    m.baseColorMap = slot(m.baseColorTexture, kColour);
    m.emissiveMap = slot(m.emissiveTexture, kColour);
    m.metallicMap = slot(m.metallicTexture, kData);
    m.roughnessMap = slot(m.roughnessTexture, kData);
    m.transmissionMap = slot(m.transmissionTexture, kData);
    m.normalMap = slot(m.normalTexture, kData);
    m.opacityMap = slot(m.opacityTexture, kData);
}

std::optional<std::string> materialProblem(const pnb::Material& m) {
    auto unit = [](float v) { return std::isfinite(v) && v >= 0.f && v <= 1.f; };
    auto num = [](float v) { return std::to_string(v); };
    const Rgb base = m.baseColor;
    if (!base.isFinite() || base.r < 0.f || base.g < 0.f || base.b < 0.f) return "baseColor must be finite and >= 0";
    const std::pair<const char*, float> units[] = {{"metallic", m.metallic}, {"roughness", m.roughness},
                                                   {"transmission", m.transmission}, {"opacity", m.opacity}};
    for (const auto& [name, v] : units)
        if (!unit(v)) return std::string(name) + " must lie in [0, 1], got " + num(v);
    if (!std::isfinite(m.normalScale)) return "normalScale must be finite";
    if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0.f)
        return "alphaCutoff must be finite and >= 0, got " + num(m.alphaCutoff);
    const std::pair<const char*, const TextureSlot*> slots[] = {
        {"baseColorTexture", &m.baseColorTexture}, {"metallicTexture", &m.metallicTexture},
        {"roughnessTexture", &m.roughnessTexture}, {"transmissionTexture", &m.transmissionTexture},
        {"normalTexture", &m.normalTexture},       {"emissiveTexture", &m.emissiveTexture},
        {"opacityTexture", &m.opacityTexture}};
    for (const auto& [name, slot] : slots) {
        const std::string where = std::string(name) + ".";
        if (slot->uvSet != 0 && slot->uvSet != 1) return where + "uvSet must be 0 or 1";
        if (slot->channel < 0 || slot->channel > 3) return where + "channel must lie in 0..3";
        for (float v : {slot->offset[0], slot->offset[1], slot->rotation, slot->scale[0], slot->scale[1]})
            if (!std::isfinite(v)) return where + "offset, rotation and scale must be finite";
    }
    return std::nullopt;
}

}  // namespace penumbra
