// MTL materials as Penumbra materials (docs/mtl-mapping.md): Phong terms,
// illum models, emission, the PBR extension keys, textures (opened here,
// handed on by fd) and the warnings for what is not supported, each kind once per OBJ.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/io/load_options.h"
#include "core/log.h"
#include "core/material.h"
#include "core/scene.h"

namespace penumbra {

/// A texture statement's file and the options of it Penumbra reads.
struct MtlTexture {
    std::string name;                          // as written; empty = none
    float offset[2] = {0.f, 0.f};              // -o u v
    float scale[2] = {1.f, 1.f};               // -s u v
    bool clamp = false;                        // -clamp on
    char channel = 0;                          // -imfchan r, g, b, m, l or z; 0: the statement's default
    float gain = 1.f, base = 0.f;              // -mm base gain
    float bumpMultiplier = 1.f;                // -bm
};

/// One `newmtl` block as read from its file (tinyobjloader's fields, copied out).
struct MtlMaterial {
    std::string name;
    std::filesystem::path file;  // the MTL it came from; empty when unknown (the OBJ is named instead)
    float ambient[3] = {0.f, 0.f, 0.f};
    float diffuse[3] = {0.f, 0.f, 0.f};
    float specular[3] = {0.f, 0.f, 0.f};
    float emission[3] = {0.f, 0.f, 0.f};
    float shininess = 1.f;
    float transmittance[3] = {0.f, 0.f, 0.f};  // Tf (or Kt)
    float ior = 1.f;                           // Ni
    int illum = 0;
    std::vector<std::string> unknownKeys;  // sorted, each once
    std::string diffuseTexture;            // map_Kd as written
    MtlTexture emissiveMap;                // map_Ke
    MtlTexture alphaMap;                   // map_d
    MtlTexture bumpMap;                    // bump, map_Bump (a height map)
    MtlTexture normalMap;                  // norm (a tangent-space normal map)
    MtlTexture roughnessMap, metallicMap;  // map_Pr, map_Pm
    float roughness = 0.f, metallic = 0.f; // Pr, Pm (0 when absent: tinyobjloader does not tell)
};

/// Converts the MTL materials and resolves their diffuse textures.
class MaterialConverter {
public:
    MaterialConverter(Scene& scene, const std::filesystem::path& objPath, const LoadOptions& options,
                      const Logger& log)
        : scene_(scene), obj_(objPath), options_(options), log_(log) {}

    Material convert(const MtlMaterial& t);

    /// The one grey material for faces without a (known) material; added on first use.
    uint32_t defaultMaterial();

    /// Once per OBJ: one warning for all materials with the same unsupported illum kind.
    void flushWarnings();

private:
    static void note(std::string& list, const std::string& where, int illum);
    /// Index in Scene::textures, or -1 (with one warning) when the file cannot be used;
    /// `texName` becomes the path of the file found.
    int texture(std::string& texName, TextureColorSpace space, const std::filesystem::path& mtl,
                const std::string& where);
    /// The texture statements other than map_Kd, as texture slots (paths as written).
    void addMaps(const MtlMaterial& t, Material& m, const std::string& where);

    Scene& scene_;
    std::filesystem::path obj_;
    const LoadOptions& options_;
    const Logger& log_;
    std::optional<uint32_t> default_;
    std::string transparentIllum_, unknownIllum_, opaqueGlass_;
    static constexpr size_t kMaxUnknownKeyWarnings = 5;
    std::set<std::pair<std::string, std::string>> unknownKeys_;
    std::map<std::string, size_t> unknownKeyCount_;
    std::set<std::string> missingTextures_;
};

}  // namespace penumbra
