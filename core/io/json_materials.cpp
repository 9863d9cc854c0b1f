// JSON materials, their textures, and the materials shapes get (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <memory>

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

Material SceneReader::readMaterial(const Json& j, const std::string& ptr, const std::string& name, bool named, Scene& scene) {
    expectObject(j, ptr);
    if (named)
        checkKeys(j, ptr,
                  {"name", "ka", "kd", "ks", "n", "exponent", "kr", "ke", "two_sided", "model", "texture", "kt", "ior"});
    else
        checkKeys(j, ptr, {"ka", "kd", "ks", "n", "exponent", "kr", "ke", "two_sided", "model", "texture", "kt", "ior"});
    Material m;
    m.name = name;
    if (const Json* v = find(j, "ka")) m.ka = colour(*v, child(ptr, "ka"));
    if (const Json* v = find(j, "kd")) m.kd = colour(*v, child(ptr, "kd"));
    if (const Json* v = find(j, "ks")) m.ks = colour(*v, child(ptr, "ks"));
    if (const Json* v = find(j, "kr")) m.kr = colour(*v, child(ptr, "kr"));
    if (const Json* v = find(j, "ke")) m.ke = colour(*v, child(ptr, "ke"));
    if (const Json* v = find(j, "kt")) m.kt = colour(*v, child(ptr, "kt"));
    if (const Json* v = find(j, "ior")) {
        m.ior = nonNegative(*v, child(ptr, "ior"));
        if (!(m.ior > 0.f)) fail(ErrorCode::InvalidScene, child(ptr, "ior"), "must be > 0");
    }
    const Json* n = find(j, "n");
    const Json* e = find(j, "exponent");
    if (n && e) fail(ErrorCode::ParseError, child(ptr, "exponent"), "\"n\" and \"exponent\" are the same key; give one");
    if (n) m.exponent = nonNegative(*n, child(ptr, "n"));
    if (e) m.exponent = nonNegative(*e, child(ptr, "exponent"));
    if (const Json* v = find(j, "two_sided")) m.twoSidedEmission = boolean(*v, child(ptr, "two_sided"));
    if (const Json* v = find(j, "model")) {
        std::string mp = child(ptr, "model");
        std::string s = string(*v, mp);
        if (s == "normalized")
            m.model = PhongModel::Normalized;
        else if (s == "classic")
            m.model = PhongModel::Classic;
        else
            fail(ErrorCode::InvalidScene, mp, "must be \"normalized\" or \"classic\", got " + quotedValue(s));
    }
    if (const Json* v = find(j, "texture")) {
        m.textureIndex = texture(*v, child(ptr, "texture"), scene);
        if (m.textureIndex >= 0) m.diffuseTexture = scene.textures[size_t(m.textureIndex)];
    }
    return m;
}

int SceneReader::texture(const Json& j, const std::string& ptr, Scene& scene) const {
    fs::path p = resolvePath(j, ptr);
    std::string key = p.string();
    for (size_t i = 0; i < scene.textures.size(); ++i)
        if (scene.textures[i] == key) return static_cast<int>(i);
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
    scene.textures.push_back(key);
    scene.textureFiles.resize(scene.textures.size());
    scene.textureFiles.back() = std::move(file);
    return static_cast<int>(scene.textures.size() - 1);
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
