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

    m.diffuseTexture = t.diffuseTexture;
    const Rgb ke = m.ke;
    addMaps(t, m, where);
    bindTextures(m, [&](std::string& path, TextureColorSpace space) { return texture(path, space, mtl, where); });
    if (!m.emissiveMap.used()) m.ke = ke;  // an emission map that cannot be used does not make the surface glow
    return m;
}

namespace {

/// MTL's -imfchan as a slot channel: r, g, b; m (matte) and the default read
/// the alpha channel, which is channel 0 in an image without alpha.
int channelOf(char imfchan) { return imfchan == 'g' ? 1 : imfchan == 'b' ? 2 : imfchan == 'r' || imfchan == 'l' || imfchan == 'z' ? 0 : 3; }

/// A texture statement as a slot: MTL's -o and -s work on (u, v) with v up;
/// in image coordinates (s, t = 1 - v) they scale t by the same factor and
/// offset it by 1 - scale - offset.
TextureSlot slotOf(const MtlTexture& t, char defaultChannel) {
    TextureSlot s;
    s.path = t.name;
    s.channel = channelOf(t.channel ? t.channel : defaultChannel);
    s.scale[0] = t.scale[0];
    s.scale[1] = t.scale[1];
    s.offset[0] = t.offset[0];
    s.offset[1] = 1.f - t.scale[1] - t.offset[1];
    if (t.clamp) s.wrapS = s.wrapT = TextureWrap::ClampToEdge;
    return s;
}

}  // namespace

void MaterialConverter::addMaps(const MtlMaterial& t, Material& m, const std::string& where) {
    if (!t.emissiveMap.name.empty()) {
        m.emissiveTexture = slotOf(t.emissiveMap, 'm');
        // The map is the emission: Ke 0 (or none) with a map_Ke means Ke 1; -mm's gain scales it.
        if (Rgb(m.ke).isBlack()) m.ke = Rgb(1.f);
        if (std::isfinite(t.emissiveMap.gain) && t.emissiveMap.gain >= 0.f) m.ke = Rgb(m.ke) * t.emissiveMap.gain;
    }
    if (!t.alphaMap.name.empty()) m.opacityTexture = slotOf(t.alphaMap, 'm');
    // Alpha cuts out where map_d, or the alpha channel of map_Kd, is below one half.
    if (!t.alphaMap.name.empty() || !t.diffuseTexture.empty()) m.alphaMode = AlphaMode::Mask;
    const MtlTexture& normal = !t.normalMap.name.empty() ? t.normalMap : t.bumpMap;
    if (!normal.name.empty()) {
        m.normalTexture = slotOf(normal, 'l');
        m.bumpMap = t.normalMap.name.empty();
        m.normalScale = std::isfinite(normal.bumpMultiplier) ? normal.bumpMultiplier : 1.f;
        if (!t.normalMap.name.empty() && !t.bumpMap.name.empty())
            log_.warn(where + ": both 'norm' and a bump map; using the normal map '" + printable(t.normalMap.name) + "'");
    }
    // The PBR extension keys make it a metal-roughness material: Kd and map_Kd
    // are its base colour; a map without its factor has the factor 1; the
    // Phong terms stay as the MTL gives them (what renders until the
    // renderer shades metal-roughness).
    const bool pbr = t.roughness != 0.f || t.metallic != 0.f || !t.roughnessMap.name.empty() || !t.metallicMap.name.empty();
    if (!pbr) return;
    m.kind = MaterialKind::MetalRoughness;
    m.baseColor = m.kd;
    if (!t.diffuseTexture.empty()) m.baseColorTexture.path = t.diffuseTexture;
    auto unit = [](float v) { return std::isfinite(v) ? std::clamp(v, 0.f, 1.f) : 0.f; };
    m.metallic = !t.metallicMap.name.empty() && t.metallic == 0.f ? 1.f : unit(t.metallic);
    // Without Pr, the roughness of the Phong exponent's lobe: alpha^2 = 2 / (Ns + 2), roughness = sqrt(alpha).
    m.roughness = !t.roughnessMap.name.empty() && t.roughness == 0.f ? 1.f
                  : t.roughness != 0.f                               ? unit(t.roughness)
                                                                     : std::sqrt(std::sqrt(2.f / (m.exponent + 2.f)));
    if (!t.metallicMap.name.empty()) m.metallicTexture = slotOf(t.metallicMap, 'm');
    if (!t.roughnessMap.name.empty()) m.roughnessTexture = slotOf(t.roughnessMap, 'm');
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

int MaterialConverter::texture(std::string& texName, TextureColorSpace space, const fs::path& mtl,
                               const std::string& where) {
    std::string rel = texName;
    std::replace(rel.begin(), rel.end(), '\\', '/');
    rel = std::string(trim(rel));
    fs::path dir = mtl.parent_path();
    fs::path relPath(rel);
    // Checked before probing the file system, and again (by the open) for the file matched.
    checkPathAllowed(relPath.is_absolute() ? relPath : dir / relPath, options_, /*willRead=*/false);
    std::optional<fs::path> file = resolveCaseInsensitive(dir, relPath);
    const std::string path = file ? file->string() : std::string();
    if (const TextureSource* known = file ? scene_.findTexture(path) : nullptr) {
        TextureSource again = *known;  // the file opened for another slot serves this one too
        again.colorSpace = space;
        texName = path;
        return scene_.addTexture(std::move(again));
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
                          "); rendering without it");
            else
                log_.warn(where + ": texture " + e.what() + "; rendering without it");
        }
        return -1;
    }
    texName = path;
    const int fd = in->fd();
    return scene_.addTexture(TextureSource{path, space, fd, std::move(in), nullptr});
}

}  // namespace penumbra
