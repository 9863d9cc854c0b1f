#include "core/io/mtl_materials.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "core/io/input_file.h"
#include "core/io/mtl_files.h"
#include "core/io/obj_text.h"
#include "core/io/path_policy.h"

namespace penumbra {
namespace fs = std::filesystem;
using namespace obj_text;

namespace {

std::string name(const fs::path& p) { return p.string(); }

Rgb toRgb(const float c[3], bool& clamped) {
    Rgb r;
    float* out[3] = {&r.r, &r.g, &r.b};
    for (int i = 0; i < 3; ++i) {
        float v = c[i];
        if (!std::isfinite(v) || v < 0.f) {
            clamped = true;
            v = 0.f;
        }
        *out[i] = v;
    }
    return r;
}

std::string rgbText(const float c[3]) {
    std::ostringstream ss;
    ss << c[0] << ' ' << c[1] << ' ' << c[2];
    return ss.str();
}

}  // namespace

Material MaterialConverter::convert(const MtlMaterial& t) {
    fs::path mtl = t.file.empty() ? obj_ : t.file;
    std::string where = name(mtl) + ": material '" + t.name + "'";

    Material m;
    m.name = t.name;
    m.model = PhongModel::Normalized;
    bool clamped = false;
    m.ka = toRgb(t.ambient, clamped);
    m.kd = toRgb(t.diffuse, clamped);
    m.ks = toRgb(t.specular, clamped);
    m.ke = toRgb(t.emission, clamped);
    float ns = t.shininess;
    m.exponent = std::isfinite(ns) && ns >= 0.f ? ns : 1.f;
    clamped = clamped || m.exponent != ns;
    if (clamped) log_.warn(where + ": negative or non-finite values replaced by 0 (Ns by 1)");

    if (Rgb(m.ka).maxComponent() > 1.5f)
        log_.warn(where + ": Ka " + rgbText(t.ambient) +
                  " looks like a light source; Penumbra takes emission from Ke only (add 'Ke " +
                  rgbText(t.ambient) + "' to make it emit)");

    int illum = t.illum;
    const bool glassIllum = illum == 4 || illum == 6 || illum == 7;
    bool tfClamped = false;
    const Rgb tf = toRgb(t.transmittance, tfClamped);
    if (glassIllum && tf.maxComponent() > 0.f) {
        // Glass: Fresnel decides between reflection and refraction (shading/dielectric.h), so the
        // MTL's Ks (the spec's reflection weight) is not used; Tf filters the refracted light.
        m.kt = tf;
        m.ks = Rgb(0.f);
        if (tfClamped) log_.warn(where + ": negative or non-finite Tf values replaced by 0");
        if (std::isfinite(t.ior) && t.ior > 0.f) {
            m.ior = t.ior;
        } else {
            m.ior = 1.5f;
            log_.warn(where + ": Ni " + std::to_string(t.ior) + " is not a positive number; using 1.5");
        }
    } else if (illum >= 3 && illum <= 9) {
        // The Ks of a reflecting material is the mirror's colour, not a highlight.
        m.kr = m.ks;
        m.ks = Rgb(0.f);
        if (glassIllum) note(opaqueGlass_, where, illum);
        if (illum == 9) note(transparentIllum_, where, illum);
    } else if (illum < 0 || illum > 9) {
        note(unknownIllum_, where, illum);
    }

    for (const auto& key : t.unknownKeys) {
        if (!unknownKeys_.insert({name(mtl), key}).second) continue;
        // A few by name; past that (a binary or foreign file) one line counts the rest.
        if (++unknownKeyCount_[name(mtl)] <= kMaxUnknownKeyWarnings)
            log_.warn(name(mtl) + ": ignoring unknown MTL key '" + printable(key) + "'");
    }

    if (!t.diffuseTexture.empty()) {
        m.textureIndex = texture(t.diffuseTexture, mtl, where);
        if (m.textureIndex >= 0) m.diffuseTexture = scene_.textures[size_t(m.textureIndex)];
    }
    return m;
}

uint32_t MaterialConverter::defaultMaterial() {
    if (!default_) {
        Material d;
        d.name = "default";
        d.kd = Rgb(0.8f);
        default_ = static_cast<uint32_t>(scene_.materials.size());
        scene_.materials.push_back(d);
    }
    return *default_;
}

void MaterialConverter::flushWarnings() {
    if (!transparentIllum_.empty())
        log_.warn(name(obj_) + ": transparency/refraction is not supported (" + transparentIllum_ +
                  "); rendering the mirror part only");
    if (!opaqueGlass_.empty())
        log_.warn(name(obj_) + ": glass without a transmission colour (" + opaqueGlass_ +
                  ": Tf is missing or 0); rendering the mirror part only (add 'Tf 1 1 1' for clear glass)");
    if (!unknownIllum_.empty()) log_.warn(name(obj_) + ": unknown illum model (" + unknownIllum_ + "); using lit Phong");
    for (const auto& [file, count] : unknownKeyCount_)
        if (count > kMaxUnknownKeyWarnings)
            log_.warn(file + ": ignoring " + std::to_string(count - kMaxUnknownKeyWarnings) + " more unknown MTL key(s)");
}

void MaterialConverter::note(std::string& list, const std::string& where, int illum) {
    if (!list.empty()) list += ", ";
    list += where + " illum " + std::to_string(illum);
}

int MaterialConverter::texture(const std::string& texName, const fs::path& mtl, const std::string& where) {
    std::string rel = texName;
    std::replace(rel.begin(), rel.end(), '\\', '/');
    rel = std::string(trim(rel));
    fs::path dir = mtl.parent_path();
    fs::path relPath(rel);
    // Checked before probing the file system, and again (by the open) for the file matched.
    checkPathAllowed(relPath.is_absolute() ? relPath : dir / relPath, options_, /*willRead=*/false);
    std::optional<fs::path> file = resolveCaseInsensitive(dir, relPath);
    std::string path = file ? file->string() : std::string();
    if (file) {
        auto it = std::find(scene_.textures.begin(), scene_.textures.end(), path);
        if (it != scene_.textures.end()) return static_cast<int>(it - scene_.textures.begin());
    }
    // Opened here, once; the texture side reads this descriptor (texture-fd interface).
    std::shared_ptr<const InputFile> in;
    try {
        if (!file) throw Error(ErrorCode::FileNotFound, rel + ": file not found");
        in = openInputFile(*file, options_);
    } catch (const Error& e) {
        if (e.code() == ErrorCode::InvalidArgument) throw;  // a refused path stays an error
        if (missingTextures_.insert(name(mtl) + "\n" + rel).second) {
            if (e.code() == ErrorCode::FileNotFound)
                log_.warn(where + ": texture '" + rel + "' not found (looked in " + name(dir.empty() ? "." : dir) +
                          "); using Kd without texture");
            else
                log_.warn(where + ": texture " + e.what() + "; using Kd without texture");
        }
        return -1;
    }
    scene_.textures.push_back(path);
    scene_.textureFiles.resize(scene_.textures.size());
    scene_.textureFiles.back() = std::move(in);
    return static_cast<int>(scene_.textures.size() - 1);
}

}  // namespace penumbra
