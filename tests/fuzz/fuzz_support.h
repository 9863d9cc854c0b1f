// Shared by the libFuzzer targets: a private scratch directory that the
// loaders may read (and nothing else: LoadOptions::allowedRoots), writing the
// input there, and the invariants every successfully loaded scene must keep.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/log.h"
#include "core/scene.h"
#include "core/io/scene_loader.h"

namespace penumbra::fuzz {

/// A fresh directory in RAM when /dev/shm exists (the loaders take paths, so
/// every input is written to a file), removed when the fuzzer exits normally.
class ScratchDir {
public:
    ScratchDir() {
        std::error_code ec;
        std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                         ? std::filesystem::path("/dev/shm")
                                         : std::filesystem::temp_directory_path();
        std::string pattern = (base / "penumbra-fuzz-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) {
            std::perror("penumbra fuzz: mkdtemp");
            std::abort();
        }
        path_ = pattern;
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    const std::filesystem::path& path() const { return path_; }

    /// Writes `bytes` to <dir>/<name>; returns the path.
    std::filesystem::path write(const std::string& name, std::string_view bytes) const {
        std::filesystem::path p = path_ / name;
        std::ofstream out(p, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        if (!out) {
            std::fprintf(stderr, "penumbra fuzz: cannot write %s\n", p.string().c_str());
            std::abort();
        }
        return p;
    }

private:
    std::filesystem::path path_;
};

/// Loading confined to the scratch directory: "mtllib /dev/zero" and the like are refused.
inline LoadOptions confinedTo(const ScratchDir& dir, bool strict) {
    LoadOptions o;
    o.strict = strict;
    o.allowedRoots = {dir.path()};
    return o;
}

/// Messages are built (that code runs) but go nowhere.
inline Logger silentLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Debug); }

/// Stops the fuzzer with a report when a loaded scene breaks a promise of the loaders.
[[noreturn]] inline void violated(const char* what) {
    std::fprintf(stderr, "penumbra fuzz: invariant violated: %s\n", what);
    std::abort();
}

/// What every loaded and finalized scene guarantees to the accelerators and the integrator.
inline void checkScene(const Scene& scene) {
    if (scene.materials.empty()) violated("a finalized scene has no material");
    for (const TriangleMesh& m : scene.meshes) {
        if (m.indices.size() % 3 != 0) violated("mesh index count is not a multiple of 3");
        for (uint32_t i : m.indices)
            if (i >= m.positions.size()) violated("mesh index out of range");
        for (const Vec3f& p : m.positions)
            if (!isFinite(p)) violated("non-finite mesh position");
        if (!m.normals.empty() && m.normals.size() != m.positions.size()) violated("normal count != vertex count");
        if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) violated("uv count != vertex count");
        if (!m.faceMaterials.empty() && m.faceMaterials.size() != m.triangleCount())
            violated("face material count != triangle count");
        for (size_t t = 0; t < m.triangleCount(); ++t)
            if (m.materialOf(t) >= scene.materials.size()) violated("material id out of range");
    }
    for (const Material& mat : scene.materials) {
        if (!Rgb(mat.kd).isFinite() || !Rgb(mat.ke).isFinite() || !Rgb(mat.ks).isFinite() ||
            !Rgb(mat.kr).isFinite() || !Rgb(mat.ka).isFinite())
            violated("non-finite material colour");
        if (mat.textureIndex >= 0 && static_cast<size_t>(mat.textureIndex) >= scene.textures.size())
            violated("texture index out of range");
    }
}

}  // namespace penumbra::fuzz
