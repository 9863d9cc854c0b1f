#include "core/io/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra {
namespace {

/// A member of a JSON object kept by tinygltf (extensions), or null.
const tinygltf::Value* member(const tinygltf::Value& v, const char* key) {
    return v.IsObject() && v.Has(key) ? &v.Get(key) : nullptr;
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& map, const char* name) {
    const auto it = map.find(name);
    return it == map.end() ? nullptr : &it->second;
}

/// A number member, or `fallback` when absent or not a finite number.
float numberOr(const tinygltf::Value* v, const char* key, float fallback) {
    const tinygltf::Value* m = v ? member(*v, key) : nullptr;
    if (!m || !m->IsNumber()) return fallback;
    const double d = m->GetNumberAsDouble();
    return std::isfinite(d) && std::fabs(d) < 1e30 ? float(d) : fallback;
}

/// A texture reference as glTF gives it: textureInfo's index, texCoord and extensions.
struct TextureUse {
    int index = -1;
    int texCoord = 0;
    const tinygltf::ExtensionMap* extensions = nullptr;
    const tinygltf::Value* json = nullptr;  // the textureInfo inside an extension (transmissionTexture)
};

TextureWrap wrapOf(int mode) {
    return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? TextureWrap::ClampToEdge
           : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? TextureWrap::MirroredRepeat
                                                          : TextureWrap::Repeat;
}

class MaterialReader {
public:
    MaterialReader(const GltfFile& file, Scene& scene, const Logger& log) : file_(file), scene_(scene), log_(log) {}

    Material read(const tinygltf::Material& g, const std::string& where);

private:
    /// The slot for `use`, its image registered in `space`; `channel` for one-value slots.
    TextureRef slot(const TextureUse& use, TextureColorSpace space, int channel, TextureSlot& out, const std::string& where);
    void warn(const std::string& where, const std::string& what) const { log_.warn(file_.where(where) + ": " + what); }

    const GltfFile& file_;
    Scene& scene_;
    const Logger& log_;
};

TextureRef MaterialReader::slot(const TextureUse& use, TextureColorSpace space, int channel, TextureSlot& out,
                                const std::string& where) {
    if (use.index < 0) return {};
    const auto& textures = file_.model.textures;
    if (size_t(use.index) >= textures.size()) {
        warn(where, "textures[" + std::to_string(use.index) + "] does not exist; the channel is left without a texture");
        return {};
    }
    const tinygltf::Texture& t = textures[size_t(use.index)];
    if (t.source < 0 || size_t(t.source) >= file_.images.size()) {
        warn(where, "textures[" + std::to_string(use.index) + "] has no image Penumbra reads (only PNG and JPEG sources)");
        return {};
    }
    const TextureSource& image = file_.images[size_t(t.source)];
    if (image.name.empty()) return {};  // warned about when the file was read
    out.channel = channel;
    out.uvSet = use.texCoord;
    if (t.sampler >= 0 && size_t(t.sampler) < file_.model.samplers.size()) {
        const tinygltf::Sampler& s = file_.model.samplers[size_t(t.sampler)];
        out.wrapS = wrapOf(s.wrapS);
        out.wrapT = wrapOf(s.wrapT);
        if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) out.filter = TextureFilter::Nearest;
    }
    const tinygltf::Value* transform = nullptr;
    if (use.extensions) transform = extension(*use.extensions, "KHR_texture_transform");
    if (use.json) transform = member(*use.json, "extensions") ? member(*member(*use.json, "extensions"), "KHR_texture_transform") : nullptr;
    if (transform) {
        for (int k = 0; k < 2; ++k) {
            const tinygltf::Value* o = member(*transform, "offset");
            const tinygltf::Value* s = member(*transform, "scale");
            if (o && o->ArrayLen() == 2 && o->Get(k).IsNumber()) out.offset[k] = float(o->Get(k).GetNumberAsDouble());
            if (s && s->ArrayLen() == 2 && s->Get(k).IsNumber()) out.scale[k] = float(s->Get(k).GetNumberAsDouble());
        }
        out.rotation = numberOr(transform, "rotation", 0.f);
        out.uvSet = int(numberOr(transform, "texCoord", float(out.uvSet)));
    }
    if (out.uvSet != 0 && out.uvSet != 1) {
        warn(where, "texture coordinates TEXCOORD_" + std::to_string(out.uvSet) + " (only sets 0 and 1 are read); using set 0");
        out.uvSet = 0;
    }
    TextureSource source = image;
    source.colorSpace = space;
    out.path = source.name;
    return TextureRef::of(out, scene_.addTexture(std::move(source)));
}

Material MaterialReader::read(const tinygltf::Material& g, const std::string& where) {
    Material m;
    m.name = g.name.empty() ? where : g.name;
    m.kind = MaterialKind::MetalRoughness;
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    auto unit = [&](double v, float fallback, const char* name) {
        if (std::isfinite(v) && v >= 0.0 && v <= 1.0) return float(v);
        warn(where, std::string(name) + " " + std::to_string(v) + " is not in [0, 1]; using " + std::to_string(fallback));
        return fallback;
    };
    if (pbr.baseColorFactor.size() == 4) {
        m.baseColor = Rgb(unit(pbr.baseColorFactor[0], 1.f, "baseColorFactor"), unit(pbr.baseColorFactor[1], 1.f, "baseColorFactor"),
                          unit(pbr.baseColorFactor[2], 1.f, "baseColorFactor"));
        m.opacity = unit(pbr.baseColorFactor[3], 1.f, "baseColorFactor's alpha");
    }
    m.metallic = unit(pbr.metallicFactor, 1.f, "metallicFactor");
    m.roughness = unit(pbr.roughnessFactor, 1.f, "roughnessFactor");
    constexpr TextureColorSpace kSrgb = TextureColorSpace::Srgb, kLinear = TextureColorSpace::Linear;
    const TextureUse base{pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, &pbr.baseColorTexture.extensions};
    m.baseColorMap = slot(base, kSrgb, 0, m.baseColorTexture, where + " baseColorTexture");
    const TextureUse mr{pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                        &pbr.metallicRoughnessTexture.extensions};
    m.metallicMap = slot(mr, kLinear, 2, m.metallicTexture, where + " metallicRoughnessTexture");
    m.roughnessMap = slot(mr, kLinear, 1, m.roughnessTexture, where + " metallicRoughnessTexture");
    const TextureUse normal{g.normalTexture.index, g.normalTexture.texCoord, &g.normalTexture.extensions};
    m.normalMap = slot(normal, kLinear, 0, m.normalTexture, where + " normalTexture");
    m.normalScale = std::isfinite(g.normalTexture.scale) ? float(g.normalTexture.scale) : 1.f;
    const TextureUse emissive{g.emissiveTexture.index, g.emissiveTexture.texCoord, &g.emissiveTexture.extensions};
    m.emissiveMap = slot(emissive, kSrgb, 0, m.emissiveTexture, where + " emissiveTexture");

    // Emission: emissiveFactor times KHR_materials_emissive_strength.
    const float strength = numberOr(extension(g.extensions, "KHR_materials_emissive_strength"), "emissiveStrength", 1.f);
    if (!(strength >= 0.f)) warn(where, "emissiveStrength " + std::to_string(strength) + " is negative; using 1");
    if (g.emissiveFactor.size() == 3)
        m.ke = Rgb(unit(g.emissiveFactor[0], 0.f, "emissiveFactor"), unit(g.emissiveFactor[1], 0.f, "emissiveFactor"),
                   unit(g.emissiveFactor[2], 0.f, "emissiveFactor")) *
               (strength >= 0.f ? strength : 1.f);
    m.twoSidedEmission = g.doubleSided;

    if (const tinygltf::Value* t = extension(g.extensions, "KHR_materials_transmission")) {
        m.transmission = unit(numberOr(t, "transmissionFactor", 0.f), 0.f, "transmissionFactor");
        if (const tinygltf::Value* info = member(*t, "transmissionTexture")) {
            const TextureUse use{int(numberOr(info, "index", -1.f)), int(numberOr(info, "texCoord", 0.f)), nullptr, info};
            m.transmissionMap = slot(use, kLinear, 0, m.transmissionTexture, where + " transmissionTexture");
        }
    }
    const float ior = numberOr(extension(g.extensions, "KHR_materials_ior"), "ior", 1.5f);
    if (ior >= 1.f) m.ior = ior;
    else warn(where, "ior " + std::to_string(ior) + " is below 1; using 1.5");

    if (g.alphaMode == "MASK") m.alphaMode = AlphaMode::Mask;
    else if (g.alphaMode == "BLEND") m.alphaMode = AlphaMode::Blend;
    else if (g.alphaMode != "OPAQUE") warn(where, "alphaMode \"" + g.alphaMode.substr(0, 20) + "\" is not OPAQUE, MASK or BLEND; using OPAQUE");
    if (std::isfinite(g.alphaCutoff) && g.alphaCutoff >= 0.0 && g.alphaCutoff <= 1.0) m.alphaCutoff = float(g.alphaCutoff);
    else warn(where, "alphaCutoff " + std::to_string(g.alphaCutoff) + " is not in [0, 1]; using 0.5");

    mapTransmissionOntoGlass(m);
    m.textureIndex = m.baseColorMap.texture;
    m.diffuseTexture = m.baseColorTexture.path;
    return m;
}

}  // namespace

uint32_t appendGltfMaterials(const GltfFile& file, Scene& scene, const Logger& log) {
    const uint32_t base = static_cast<uint32_t>(scene.materials.size());
    MaterialReader reader(file, scene, log);
    const auto& all = file.model.materials;
    for (size_t i = 0; i < all.size(); ++i)
        scene.materials.push_back(reader.read(all[i], "materials[" + std::to_string(i) + "]" +
                                                          (all[i].name.empty() ? "" : " '" + all[i].name.substr(0, 60) + "'")));
    Material fallback = reader.read(tinygltf::Material{}, "default material");
    fallback.name = "default";
    scene.materials.push_back(fallback);
    return base;
}

}  // namespace penumbra
