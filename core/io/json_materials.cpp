// JSON materials, their textures, and the materials shapes get (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <algorithm>
#include <iterator>
#include <memory>
#include <string_view>
#include <vector>

#include "core/io/input_file.h"

namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

void SceneReader::readMaterials(const Json& j, const std::string& ptr, Scene& scene) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            std::string mp = child(ptr, it.key());
            if (it.key().empty()) fail(ErrorCode::InvalidScene, mp, "material name must not be empty");
            addMaterial(readMaterial(it.value(), mp, it.key(), false, scene), mp, scene);
        }
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) {
            std::string mp = child(ptr, i);
            expectObject(j[i], mp);
            std::string name = string(require(j[i], mp, "name", "a material in an array"), child(mp, "name"));
            if (name.empty()) fail(ErrorCode::InvalidScene, child(mp, "name"), "must not be empty");
            addMaterial(readMaterial(j[i], mp, name, true, scene), mp, scene);
        }
    } else {
        fail(ErrorCode::ParseError, ptr, "expected an object {name: material} or an array of named materials, got " +
                                             typeName(j));
    }
}

void SceneReader::addMaterial(Material m, const std::string& ptr, Scene& scene) {
    if (names_.count(m.name)) fail(ErrorCode::InvalidScene, ptr, "material " + quotedValue(m.name) + " is defined twice");
    names_[m.name] = static_cast<uint32_t>(scene.materials.size());
    scene.materials.push_back(std::move(m));
}

namespace {

// The keys of each model and of both (docs/scene-format.md, "Materials").
constexpr std::string_view kPhongKeys[] = {"ka", "kd", "ks", "n", "exponent", "kr", "kt", "texture"};
constexpr std::string_view kMetalRoughnessKeys[] = {"base_color",       "metallic",          "roughness",
                                                    "transmission",     "base_color_texture", "metallic_texture",
                                                    "roughness_texture", "transmission_texture"};
constexpr std::string_view kSharedKeys[] = {"ke",           "two_sided",       "model",          "ior",
                                            "normal_texture", "bump_texture",  "normal_scale",   "emissive_texture",
                                            "opacity",      "opacity_texture", "alpha_mode",     "alpha_cutoff"};

}  // namespace

Material SceneReader::readMaterial(const Json& j, const std::string& ptr, const std::string& name, bool named, Scene& scene) {
    expectObject(j, ptr);
    Material m;
    m.name = name;
    if (const Json* v = find(j, "model")) {
        std::string mp = child(ptr, "model");
        std::string s = string(*v, mp);
        if (s == "normalized")
            m.model = PhongModel::Normalized;
        else if (s == "classic")
            m.model = PhongModel::Classic;
        else if (s == "metal_roughness")
            m.kind = MaterialKind::MetalRoughness;
        else
            fail(ErrorCode::InvalidScene, mp, "must be \"normalized\", \"classic\" or \"metal_roughness\", got " + quotedValue(s));
    }
    const bool pbr = m.kind == MaterialKind::MetalRoughness;
    std::vector<std::string_view> keys(std::begin(kSharedKeys), std::end(kSharedKeys));
    if (pbr) keys.insert(keys.end(), std::begin(kMetalRoughnessKeys), std::end(kMetalRoughnessKeys));
    else keys.insert(keys.end(), std::begin(kPhongKeys), std::end(kPhongKeys));
    if (named) keys.push_back("name");
    const auto& other = pbr ? kPhongKeys : kMetalRoughnessKeys;
    for (auto it = j.begin(); it != j.end(); ++it)
        if (std::find(std::begin(other), std::end(other), it.key()) != std::end(other))
            fail(ErrorCode::InvalidScene, child(ptr, it.key()),
                 pbr ? "is a Phong key; a \"metal_roughness\" material takes base_color, metallic, roughness, ..."
                     : "is a key of \"model\": \"metal_roughness\" materials");
    checkKeys(j, ptr, keys);
    if (pbr) readMetalRoughness(j, ptr, m, scene);
    else readPhong(j, ptr, m, scene);
    if (const Json* v = find(j, "ke")) m.ke = colour(*v, child(ptr, "ke"));
    if (const Json* v = find(j, "ior")) {
        m.ior = nonNegative(*v, child(ptr, "ior"));
        if (!(m.ior > 0.f)) fail(ErrorCode::InvalidScene, child(ptr, "ior"), "must be > 0");
    }
    if (const Json* v = find(j, "two_sided")) m.twoSidedEmission = boolean(*v, child(ptr, "two_sided"));
    readSharedMaps(j, ptr, m, scene);
    // Transmission is the smooth dielectric's (core/material.h).
    if (pbr) mapTransmissionOntoGlass(m);
    return m;
}

void SceneReader::readPhong(const Json& j, const std::string& ptr, Material& m, Scene& scene) {
    if (const Json* v = find(j, "ka")) m.ka = colour(*v, child(ptr, "ka"));
    if (const Json* v = find(j, "kd")) m.kd = colour(*v, child(ptr, "kd"));
    if (const Json* v = find(j, "ks")) m.ks = colour(*v, child(ptr, "ks"));
    if (const Json* v = find(j, "kr")) m.kr = colour(*v, child(ptr, "kr"));
    if (const Json* v = find(j, "kt")) m.kt = colour(*v, child(ptr, "kt"));
    const Json* n = find(j, "n");
    const Json* e = find(j, "exponent");
    if (n && e) fail(ErrorCode::ParseError, child(ptr, "exponent"), "\"n\" and \"exponent\" are the same key; give one");
    if (n) m.exponent = nonNegative(*n, child(ptr, "n"));
    if (e) m.exponent = nonNegative(*e, child(ptr, "exponent"));
    if (const Json* v = find(j, "texture")) {
        m.textureIndex = texture(*v, child(ptr, "texture"), scene, TextureColorSpace::FromFile);
        if (m.textureIndex >= 0) m.diffuseTexture = scene.textures[size_t(m.textureIndex)].name;
        // Its alpha channel cuts the surface out where it is below one half.
        if (m.textureIndex >= 0) m.alphaMode = AlphaMode::Mask;
    }
}

void SceneReader::readMetalRoughness(const Json& j, const std::string& ptr, Material& m, Scene& scene) {
    if (const Json* v = find(j, "base_color")) m.baseColor = colour(*v, child(ptr, "base_color"));
    auto unit = [&](const char* key, float& out) {
        if (const Json* v = find(j, key)) {
            out = nonNegative(*v, child(ptr, key));
            if (out > 1.f) fail(ErrorCode::InvalidScene, child(ptr, key), "must lie in [0, 1]");
        }
    };
    unit("metallic", m.metallic);
    unit("roughness", m.roughness);
    unit("transmission", m.transmission);
    m.baseColorMap = textureSlot(j, ptr, "base_color_texture", TextureColorSpace::FromFile, 0, m.baseColorTexture, scene);
    m.metallicMap = textureSlot(j, ptr, "metallic_texture", TextureColorSpace::Linear, 2, m.metallicTexture, scene);
    m.roughnessMap = textureSlot(j, ptr, "roughness_texture", TextureColorSpace::Linear, 1, m.roughnessTexture, scene);
    m.transmissionMap =
        textureSlot(j, ptr, "transmission_texture", TextureColorSpace::Linear, 0, m.transmissionTexture, scene);
}

void SceneReader::readSharedMaps(const Json& j, const std::string& ptr, Material& m, Scene& scene) {
    if (find(j, "normal_texture") && find(j, "bump_texture"))
        fail(ErrorCode::InvalidScene, child(ptr, "bump_texture"), "give a normal_texture or a bump_texture, not both");
    const char* normalKey = find(j, "bump_texture") ? "bump_texture" : "normal_texture";
    m.bumpMap = find(j, "bump_texture") != nullptr;
    m.normalMap = textureSlot(j, ptr, normalKey, TextureColorSpace::Linear, 0, m.normalTexture, scene);
    if (const Json* v = find(j, "normal_scale")) m.normalScale = number(*v, child(ptr, "normal_scale"));
    m.emissiveMap = textureSlot(j, ptr, "emissive_texture", TextureColorSpace::FromFile, 0, m.emissiveTexture, scene);
    if (const Json* v = find(j, "opacity")) {
        m.opacity = nonNegative(*v, child(ptr, "opacity"));
        if (m.opacity > 1.f) fail(ErrorCode::InvalidScene, child(ptr, "opacity"), "must lie in [0, 1]");
    }
    m.opacityMap = textureSlot(j, ptr, "opacity_texture", TextureColorSpace::Linear, 3, m.opacityTexture, scene);
    // Without "alpha_mode": an opacity map (or a Phong texture's alpha) cuts out, an opacity below 1 blends.
    if (m.opacityMap.used()) m.alphaMode = AlphaMode::Mask;
    else if (m.opacity < 1.f) m.alphaMode = AlphaMode::Blend;
    if (const Json* v = find(j, "alpha_mode")) {
        const std::string mp = child(ptr, "alpha_mode"), s = string(*v, mp);
        if (s == "opaque") m.alphaMode = AlphaMode::Opaque;
        else if (s == "mask") m.alphaMode = AlphaMode::Mask;
        else if (s == "blend") m.alphaMode = AlphaMode::Blend;
        else fail(ErrorCode::InvalidScene, mp, "must be \"opaque\", \"mask\" or \"blend\", got " + quotedValue(s));
    }
    if (const Json* v = find(j, "alpha_cutoff")) m.alphaCutoff = nonNegative(*v, child(ptr, "alpha_cutoff"));
}

TextureRef SceneReader::textureSlot(const Json& material, const std::string& materialPtr, const char* key,
                                    TextureColorSpace space, int defaultChannel, TextureSlot& slot, Scene& scene) {
    const Json* j = find(material, key);
    if (!j) return {};
    const std::string ptr = child(materialPtr, key);
    slot.channel = defaultChannel;
    if (j->is_string()) return TextureRef::of(slot, slotFile(*j, ptr, space, slot, scene));
    expectObject(*j, ptr);
    checkKeys(*j, ptr, {"file", "uv_set", "channel", "offset", "rotation", "scale", "wrap", "filter"});
    if (const Json* v = find(*j, "uv_set")) slot.uvSet = static_cast<int>(integer(*v, child(ptr, "uv_set"), 0, 1));
    if (const Json* v = find(*j, "channel")) {
        const std::string cp = child(ptr, "channel"), c = string(*v, cp);
        const size_t at = std::string_view("rgba").find(c);
        if (c.size() != 1 || at == std::string_view::npos)
            fail(ErrorCode::InvalidScene, cp, "must be \"r\", \"g\", \"b\" or \"a\", got " + quotedValue(c));
        slot.channel = static_cast<int>(at);
    }
    auto pair = [&](const char* k, float out[2]) {
        if (const Json* v = find(*j, k)) {
            const std::string kp = child(ptr, k);
            if (!v->is_array() || v->size() != 2) fail(ErrorCode::ParseError, kp, "expected [s, t], got " + typeName(*v));
            out[0] = number((*v)[0], child(kp, 0));
            out[1] = number((*v)[1], child(kp, 1));
        }
    };
    pair("offset", slot.offset);
    pair("scale", slot.scale);
    if (const Json* v = find(*j, "rotation")) slot.rotation = number(*v, child(ptr, "rotation")) * kPi / 180.f;
    if (const Json* v = find(*j, "wrap")) {
        const std::string wp = child(ptr, "wrap");
        auto wrapOf = [&](const Json& w, const std::string& at) {
            const std::string s = string(w, at);
            if (s == "repeat") return TextureWrap::Repeat;
            if (s == "clamp") return TextureWrap::ClampToEdge;
            if (s == "mirror") return TextureWrap::MirroredRepeat;
            fail(ErrorCode::InvalidScene, at, "must be \"repeat\", \"clamp\" or \"mirror\", got " + quotedValue(s));
        };
        if (v->is_array() && v->size() == 2) {
            slot.wrapS = wrapOf((*v)[0], child(wp, 0));
            slot.wrapT = wrapOf((*v)[1], child(wp, 1));
        } else {
            slot.wrapS = slot.wrapT = wrapOf(*v, wp);
        }
    }
    if (const Json* v = find(*j, "filter")) {
        const std::string fp = child(ptr, "filter"), s = string(*v, fp);
        if (s != "linear" && s != "nearest") fail(ErrorCode::InvalidScene, fp, "must be \"linear\" or \"nearest\", got " + quotedValue(s));
        slot.filter = s == "nearest" ? TextureFilter::Nearest : TextureFilter::Linear;
    }
    return TextureRef::of(slot, slotFile(require(*j, ptr, "file", "a texture"), child(ptr, "file"), space, slot, scene));
}

int SceneReader::slotFile(const Json& j, const std::string& ptr, TextureColorSpace space, TextureSlot& slot,
                          Scene& scene) const {
    const int index = texture(j, ptr, scene, space);
    slot.path = index >= 0 ? scene.textures[size_t(index)].name : std::string();
    return index;
}

int SceneReader::texture(const Json& j, const std::string& ptr, Scene& scene, TextureColorSpace space) const {
    fs::path p = resolvePath(j, ptr);
    std::string key = p.string();
    if (const TextureSource* known = scene.findTexture(key)) {
        TextureSource again = *known;  // the file opened for another material or slot serves this one too
        again.colorSpace = space;
        return scene.addTexture(std::move(again));
    }
    // Opened here, once; the texture side reads this descriptor (texture-fd interface).
    std::shared_ptr<const InputFile> file;
    try {
        file = openInputFile(p, options_);
    } catch (const Error& e) {
        if (e.code() == ErrorCode::InvalidArgument) fail(e.code(), ptr, e.what());  // a refused path stays an error
        if (e.code() == ErrorCode::FileNotFound)
            warnOrFail(ErrorCode::FileNotFound, ptr, "texture file not found: " + key);
        else
            warnOrFail(e.code(), ptr, std::string("cannot use texture ") + e.what());
        return -1;
    }
    const int fd = file->fd();
    return scene.addTexture(TextureSource{key, space, fd, std::move(file), nullptr});
}

uint32_t SceneReader::defaultMaterial(Scene& scene) {
    if (auto it = names_.find("default"); it != names_.end()) return it->second;
    Material m;
    m.name = "default";
    names_[m.name] = static_cast<uint32_t>(scene.materials.size());
    scene.materials.push_back(m);
    return names_[m.name];
}

uint32_t SceneReader::emissiveCopy(uint32_t base, const Rgb& ke, const std::string& ptr, Scene& scene) const {
    Material m = scene.materials[base];
    m.name += "@" + ptr;
    m.ke = ke;
    scene.materials.push_back(std::move(m));
    return static_cast<uint32_t>(scene.materials.size() - 1);
}

uint32_t SceneReader::shapeMaterial(const Json& j, const std::string& ptr, Scene& scene) {
    uint32_t id;
    if (const Json* v = find(j, "material")) {
        std::string mp = child(ptr, "material");
        std::string name = string(*v, mp);
        auto it = names_.find(name);
        if (it == names_.end()) fail(ErrorCode::InvalidScene, mp, "unknown material " + quotedValue(name));
        id = it->second;
    } else {
        id = defaultMaterial(scene);
    }
    if (const Json* v = find(j, "emission")) id = emissiveCopy(id, colour(*v, child(ptr, "emission")), ptr, scene);
    return id;
}
}  // namespace penumbra
