// glTF 2.0 files written by the tests: a JSON document and one binary
// buffer built up piece by piece, saved as .gltf (the buffer as a data: URI)
// or .glb. Header-only; used by the core and API tests.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace penumbra::test {

class GltfBuilder {
public:
    using Json = nlohmann::json;
    Json doc = Json{{"asset", {{"version", "2.0"}}}};

    /// Appends bytes to the buffer (4-aligned) as a new buffer view; returns its index.
    int view(const std::string& bytes) {
        while (bin_.size() % 4) bin_ += '\0';
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}});
        bin_ += bytes;
        return int(doc["bufferViews"].size() - 1);
    }
    /// A FLOAT accessor of `components` per element ("VEC3", ...) over a new view.
    int floats(const std::vector<float>& v, int components) {
        std::string bytes(v.size() * sizeof(float), '\0');
        std::memcpy(bytes.data(), v.data(), bytes.size());
        static const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
        doc["accessors"].push_back({{"bufferView", view(bytes)},
                                    {"componentType", 5126},
                                    {"count", v.size() / size_t(components)},
                                    {"type", kTypes[components]}});
        return int(doc["accessors"].size() - 1);
    }
    /// An UNSIGNED_INT index accessor.
    int indices(const std::vector<uint32_t>& v) {
        std::string bytes(v.size() * 4, '\0');
        std::memcpy(bytes.data(), v.data(), bytes.size());
        doc["accessors"].push_back({{"bufferView", view(bytes)}, {"componentType", 5125}, {"count", v.size()}, {"type", "SCALAR"}});
        return int(doc["accessors"].size() - 1);
    }
    /// The 2 x 2 quad x, y in [-1, 1] at z = 0 facing +z, with normals and
    /// TEXCOORD_0 (glTF's v down: the vertex at y = 1 has v = 0) and
    /// TEXCOORD_1 = 2 * TEXCOORD_0; returns the primitive (add "material").
    Json quad() {
        const int pos = floats({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, 3);
        const int nrm = floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 3);
        const int uv0 = floats({0, 1, 1, 1, 1, 0, 0, 0}, 2);
        const int uv1 = floats({0, 2, 2, 2, 2, 0, 0, 0}, 2);
        return Json{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}},
                    {"indices", indices({0, 1, 2, 0, 2, 3})}};
    }
    /// A mesh of the given primitives, drawn by a new node (added to scene 0); returns the node.
    int node(const Json& primitives, Json extra = Json::object()) {
        doc["meshes"].push_back({{"primitives", primitives}});
        extra["mesh"] = doc["meshes"].size() - 1;
        doc["nodes"].push_back(extra);
        const int n = int(doc["nodes"].size() - 1);
        doc["scenes"][0]["nodes"].push_back(n);
        doc["scene"] = 0;
        return n;
    }
    int material(const Json& m) {
        doc["materials"].push_back(m);
        return int(doc["materials"].size() - 1);
    }
    /// An image (a file name, or encoded bytes kept in the buffer) and a
    /// texture of it with sampler `sampler` (-1: none); returns the texture.
    int textureFile(const std::string& uri, int sampler = -1) {
        doc["images"].push_back({{"uri", uri}});
        return texture(sampler);
    }
    int textureBytes(const std::string& png, int sampler = -1) {
        doc["images"].push_back({{"bufferView", view(png)}, {"mimeType", "image/png"}});
        return texture(sampler);
    }
    int textureDataUri(const std::string& png, int sampler = -1) {
        doc["images"].push_back({{"uri", "data:image/png;base64," + base64(png)}});
        return texture(sampler);
    }

    /// The document with the buffer as a data: URI.
    std::string gltf() const {
        Json d = doc;
        if (!bin_.empty())
            d["buffers"] = Json::array({{{"byteLength", bin_.size()},
                                         {"uri", "data:application/octet-stream;base64," + base64(bin_)}}});
        return d.dump();
    }
    /// A binary glTF: the JSON chunk, then the buffer as the BIN chunk.
    std::string glb() const {
        Json d = doc;
        std::string bin = bin_;
        while (bin.size() % 4) bin += '\0';
        if (!bin.empty()) d["buffers"] = Json::array({{{"byteLength", bin_.size()}}});
        std::string json = d.dump();
        while (json.size() % 4) json += ' ';
        std::string out = "glTF";
        auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
        u32(2);
        u32(uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
        u32(uint32_t(json.size()));
        u32(0x4E4F534A);
        out += json;
        if (!bin.empty()) {
            u32(uint32_t(bin.size()));
            u32(0x004E4942);
            out += bin;
        }
        return out;
    }

private:
    int texture(int sampler) {
        Json t{{"source", doc["images"].size() - 1}};
        if (sampler >= 0) t["sampler"] = sampler;
        doc["textures"].push_back(t);
        return int(doc["textures"].size() - 1);
    }
    std::string bin_;
};

}  // namespace penumbra::test
