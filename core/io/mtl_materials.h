// MTL materials as Penumbra materials (docs/mtl-mapping.md): Phong terms,
// illum models, emission, diffuse textures (opened here, handed on by fd),
// and the warnings for what is not supported, each kind once per OBJ.
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
    /// Index in Scene::textures, or -1 (with one warning) when the file cannot be used.
    int texture(const std::string& texName, const std::filesystem::path& mtl, const std::string& where);

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
