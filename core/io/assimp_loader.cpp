// Assimp's side of the loaders, the one file that includes it. The model's
// bytes come from the descriptor opened after the path check and reach Assimp
// through ReadFileFromMemory; what the model references (a glTF .bin, ...) is
// opened through PolicyIOSystem, which asks the same path policy and opens
// each file once. Materials become MTL-like records for MaterialConverter, so
// textures are resolved and handed on by descriptor as for OBJ files.
#include "core/io/assimp_loader.h"

#include <assimp/BaseImporter.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/importerdesc.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>

#include "core/error.h"
#include "core/io/mesh_options.h"
#include "core/io/model_checks.h"
#include "core/io/mtl_materials.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

/// A file's bytes as an Assimp stream (read-only).
class MemoryStream final : public Assimp::IOStream {
public:
    explicit MemoryStream(std::string bytes) : bytes_(std::move(bytes)) {}
    size_t Read(void* buffer, size_t size, size_t count) override {
        if (size == 0 || pos_ >= bytes_.size()) return 0;
        const size_t n = std::min(count, (bytes_.size() - pos_) / size);
        std::memcpy(buffer, bytes_.data() + pos_, n * size);
        pos_ += n * size;
        return n;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : bytes_.size();
        if (origin != aiOrigin_SET && origin != aiOrigin_CUR && origin != aiOrigin_END) return aiReturn_FAILURE;
        if (offset > bytes_.size() - base) return aiReturn_FAILURE;
        pos_ = base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return pos_; }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

private:
    std::string bytes_;
    size_t pos_ = 0;
};

/// The files a model references, opened through the path policy (relative
/// names against the model's folder), each once; the first failure is kept
/// so that the error names the file instead of Assimp's summary.
class PolicyIOSystem final : public Assimp::IOSystem {
public:
    PolicyIOSystem(fs::path dir, const LoadOptions& options) : dir_(std::move(dir)), options_(options) {}

    bool Exists(const char* file) const override { return open(file) != nullptr; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (mode && (std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+'))) return nullptr;
        const InputFile* in = open(file);
        if (!in) {
            if (!error && failures_.count(resolve(file))) error = failures_.at(resolve(file));
            return nullptr;
        }
        try {
            return new MemoryStream(in->readAll());
        } catch (const Error& e) {
            if (!error) error = e;
            return nullptr;
        }
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    bool ComparePaths(const char* a, const char* b) const override { return resolve(a) == resolve(b); }

    std::optional<Error> error;  // the first referenced file that could not be opened or read

private:
    fs::path resolve(const char* file) const {
        fs::path p(file ? file : "");
        return (p.is_absolute() ? p : dir_ / p).lexically_normal();
    }
    const InputFile* open(const char* file) const {
        const fs::path p = resolve(file);
        if (auto it = opened_.find(p); it != opened_.end()) return it->second.get();
        if (failures_.count(p)) return nullptr;
        try {
            return opened_.emplace(p, openInputFile(p, options_)).first->second.get();
        } catch (const Error& e) {
            failures_.emplace(p, e);
            return nullptr;
        }
    }

    fs::path dir_;
    const LoadOptions& options_;
    mutable std::map<fs::path, std::unique_ptr<InputFile>> opened_;
    mutable std::map<fs::path, Error> failures_;
};

Transform toTransform(const aiMatrix4x4& m) {
    const float rows[3][4] = {{m.a1, m.a2, m.a3, m.a4}, {m.b1, m.b2, m.b3, m.b4}, {m.c1, m.c2, m.c3, m.c4}};
    return Transform(rows);
}

Vec3f vec(const aiVector3D& v) { return {v.x, v.y, v.z}; }

/// Non-finite or negative components read as 0.
float clean(float v) { return std::isfinite(v) && v > 0.f ? v : 0.f; }

/// A node's transform to the model's root (the product along its parents).
Transform globalOf(const aiNode* node) {
    Transform t;
    for (int depth = 0; node && depth < 4096; node = node->mParent, ++depth) t = toTransform(node->mTransformation) * t;
    return t;
}

/// The material as an MTL record (docs/mtl-mapping.md, "Assimp formats").
MtlMaterial phongOf(const aiMaterial& a, const fs::path& file, const Logger& log, const std::string& where) {
    MtlMaterial m;
    aiString name;
    m.name = a.Get(AI_MATKEY_NAME, name) == aiReturn_SUCCESS ? std::string(name.C_Str()) : std::string("material");
    m.file = file;
    m.illum = 2;
    auto set = [](float out[3], const aiColor3D& c, float scale = 1.f) {
        out[0] = clean(c.r) * scale;
        out[1] = clean(c.g) * scale;
        out[2] = clean(c.b) * scale;
    };

    aiColor4D base4;
    float metallic = 0.f, roughness = 1.f;
    const bool pbr = a.Get(AI_MATKEY_BASE_COLOR, base4) == aiReturn_SUCCESS ||
                     a.Get(AI_MATKEY_METALLIC_FACTOR, metallic) == aiReturn_SUCCESS;
    if (pbr) {
        // Metallic-roughness as Phong: the diffuse part is the non-metal share of
        // the base colour less the dielectric's 4% specular; F0 (4% for
        // dielectrics, the base colour for metals) becomes ks with the Phong
        // exponent of the same Beckmann-like width, or a mirror when polished.
        aiColor3D base(1.f, 1.f, 1.f);
        if (a.Get(AI_MATKEY_BASE_COLOR, base4) == aiReturn_SUCCESS) base = aiColor3D(base4.r, base4.g, base4.b);
        else a.Get(AI_MATKEY_COLOR_DIFFUSE, base);
        metallic = 1.f;  // glTF's defaults
        roughness = 1.f;
        a.Get(AI_MATKEY_METALLIC_FACTOR, metallic);
        a.Get(AI_MATKEY_ROUGHNESS_FACTOR, roughness);
        metallic = std::isfinite(metallic) ? std::clamp(metallic, 0.f, 1.f) : 1.f;
        roughness = std::isfinite(roughness) ? std::clamp(roughness, 0.f, 1.f) : 1.f;
        float f0[3];
        const float b[3] = {clean(base.r), clean(base.g), clean(base.b)};
        for (int i = 0; i < 3; ++i) {
            m.diffuse[i] = (1.f - metallic) * (1.f - 0.04f) * b[i];
            f0[i] = 0.04f * (1.f - metallic) + metallic * b[i];
        }
        if (roughness <= 0.05f) {
            m.illum = 3;  // the converter takes a reflecting material's Ks as its mirror colour
            std::copy(f0, f0 + 3, m.specular);
        } else {
            const float alpha = roughness * roughness;
            const float blinn = 2.f / (alpha * alpha) - 2.f;
            m.shininess = std::clamp(blinn / 4.f, 1.f, 10000.f);
            std::copy(f0, f0 + 3, m.specular);
        }
    } else {
        aiColor3D c(0.8f, 0.8f, 0.8f);
        a.Get(AI_MATKEY_COLOR_DIFFUSE, c);
        set(m.diffuse, c);
        c = aiColor3D(0.f, 0.f, 0.f);
        float strength = 1.f;
        if (a.Get(AI_MATKEY_COLOR_SPECULAR, c) == aiReturn_SUCCESS) {
            a.Get(AI_MATKEY_SHININESS_STRENGTH, strength);
            set(m.specular, c, clean(strength));
        }
        float shininess = 0.f;
        if (a.Get(AI_MATKEY_SHININESS, shininess) == aiReturn_SUCCESS && std::isfinite(shininess) && shininess >= 1.f)
            m.shininess = std::min(shininess, 10000.f);
        c = aiColor3D(0.f, 0.f, 0.f);
        if (a.Get(AI_MATKEY_COLOR_AMBIENT, c) == aiReturn_SUCCESS) set(m.ambient, c);
    }
    aiColor3D e(0.f, 0.f, 0.f);
    float intensity = 1.f;
    a.Get(AI_MATKEY_COLOR_EMISSIVE, e);
    a.Get(AI_MATKEY_EMISSIVE_INTENSITY, intensity);
    set(m.emission, e, clean(intensity));

    aiString tex;
    if (a.GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == aiReturn_SUCCESS ||
        a.GetTexture(aiTextureType_DIFFUSE, 0, &tex) == aiReturn_SUCCESS) {
        std::string t = tex.C_Str();
        if (!t.empty() && t[0] == '*')
            log.warn(where + " '" + m.name + "': embedded textures are not supported; using the base colour alone");
        else
            m.diffuseTexture = t;
    }
    return m;
}

/// Per-triangle colour from the first vertex-colour set, quantised to 8 bits
/// so that triangles of one colour share a material.
std::array<uint8_t, 3> triangleColour(const aiMesh& mesh, const uint32_t* corners) {
    float sum[3] = {0.f, 0.f, 0.f};
    for (unsigned k = 0; k < 3; ++k) {
        const aiColor4D& c = mesh.mColors[0][corners[k]];
        const float v[3] = {c.r, c.g, c.b};
        for (int i = 0; i < 3; ++i) sum[i] += std::isfinite(v[i]) ? std::clamp(v[i], 0.f, 1.f) : 1.f;
    }
    std::array<uint8_t, 3> q{};
    for (int i = 0; i < 3; ++i) q[i] = static_cast<uint8_t>(std::lround(sum[i] / 3.f * 255.f));
    return q;
}


/// Assimp picks the importer by the extension, but where several claim it
/// (glTF 1 and 2 both read .gltf and .glb; three read .xml) and none of them
/// accepts the file, it tries every importer's signature instead: a fuzzed
/// .gltf was read by the ASE importer, and a PLY header in a .gltf hangs the
/// PLY reader, past the checks above. So the claimants are asked first, as
/// Assimp asks them, and a file none of them accepts is refused.
std::optional<std::string> noClaimantAccepts(const Assimp::Importer& importer, Assimp::IOSystem& io,
                                             const std::string& format, const std::string& bytes) {
    std::vector<Assimp::BaseImporter*> claimants;
    std::string names;
    for (size_t i = 0; i < importer.GetImporterCount(); ++i) {
        const aiImporterDesc* d = importer.GetImporterInfo(i);
        std::istringstream in(d && d->mFileExtensions ? d->mFileExtensions : "");
        for (std::string e; in >> e;)
            if (lower(e) == format) {
                claimants.push_back(importer.GetImporter(i));
                names += std::string(names.empty() ? "" : ", ") + d->mName;
                break;
            }
    }
    if (claimants.size() < 2) return std::nullopt;  // Assimp uses the one without asking
    Assimp::MemoryIOSystem memory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), &io);
    const std::string name = std::string(AI_MEMORYIO_MAGIC_FILENAME) + "." + format;
    for (Assimp::BaseImporter* claimant : claimants) {
        try {
            if (claimant && claimant->CanRead(name, &memory, true)) return std::nullopt;
        } catch (const std::exception&) {
            // not this one
        }
    }
    return "none of Assimp's readers of ." + format + " files accepts it (" + names + ")";
}

std::string formatName(const fs::path& p) {
    std::string e = p.extension().string();
    return e.empty() ? std::string("a model") : lower(e.substr(1));
}

/// The formats whose Assimp 5.2.5 importer leaks what it has read when it
/// throws on a malformed file, in ways no check here can foresee (each found by
/// fuzz_model and reproduced with Importer::ReadFileFromMemory alone):
/// - dae: ColladaParser parses the whole file in its constructor, so when it
///   throws ("Unknown reference format" for an <instance_geometry> without a
///   url, and many more) its destructor never runs and the nodes and meshes it
///   read leak (1,456 bytes in 9 allocations for one input).
/// - ply: PLYImporter deletes its half-built mesh when the body parser returns
///   false but not when it throws (a value fast_atoreal_move cannot read in an
///   ASCII body, "File corrupted" where a binary body ends early): 1,432 bytes.
/// - x: XFileParser parses the whole file in its constructor, so when it throws
///   (a frame the file ends inside) its destructor never runs and the frames
///   read so far leak (18,800 bytes in 234 allocations for one input).
/// - fbx: the FBX Parser builds its scopes in its constructor and leaks those
///   built when it throws ("unexpected token" inside nested scopes: 225 bytes
///   in 6 allocations).
constexpr std::array<std::string_view, 4> kLeakingImporters = {"dae", "ply", "x", "fbx"};

/// Importer::ReadFileFromMemory for those formats, apart: the leak is Assimp's,
/// and tests/fuzz/lsan.supp names this function, so that fuzz_model reports the
/// leaks of everything else. Never inlined, so that it is on the stack.
[[gnu::noinline]] const aiScene* assimpReadLeakingOnError(Assimp::Importer& importer, const std::string& bytes,
                                                           unsigned flags, const std::string& format) {
    return importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, format.c_str());
}

/// Assimp's reason for refusing the model, naming the real file where Assimp
/// names its in-memory copy, on one line.
Error readFailure(const Assimp::Importer& importer, const PolicyIOSystem& io, const fs::path& path,
                  const std::string& format) {
    const std::string file = path.string();
    if (io.error) return Error(io.error->code(), file + ": " + io.error->what());
    std::string why = importer.GetErrorString();
    for (size_t at; (at = why.find("$$$___magic___$$$")) != std::string::npos;) {
        const size_t stop = why.find_first_of(" :,;'\"", at);
        why.replace(at, (stop == std::string::npos ? why.size() : stop) - at, path.filename().string());
    }
    for (char& c : why)
        if (c == '\n' || c == '\r') c = ' ';
    if (why.empty()) why = "the file is incomplete";
    return Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + why);
}

/// The model as Assimp reads it, after the checks of model_checks.h; the
/// importer owns the result. Throws Error naming the file.
const aiScene* readModel(Assimp::Importer& importer, const InputFile& model, const LoadOptions& options) {
    const fs::path& path = model.path();
    const std::string file = path.string();
    const std::string format = formatName(path);
    auto* io = new PolicyIOSystem(path.parent_path(), options);
    importer.SetIOHandler(io);  // the importer owns it
    const aiScene* s = nullptr;
    {
        const std::string bytes = model.readAll();
        if (bytes.empty()) throw Error(ErrorCode::ParseError, file + ": empty file");
        if (auto why = modelFileProblem(format, bytes)) throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + *why);
        if (auto why = noClaimantAccepts(importer, *io, format, bytes))
            throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + *why);
        try {
            // Validation only: Debian's Assimp aborts (ai_assert) in its triangulation
            // step on faces it does not expect, so polygons are split below, as OBJ's are.
            const unsigned flags = aiProcess_ValidateDataStructure;
            s = std::find(kLeakingImporters.begin(), kLeakingImporters.end(), format) != kLeakingImporters.end()
                    ? assimpReadLeakingOnError(importer, bytes, flags, format)
                    : importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, format.c_str());
        } catch (const std::bad_alloc&) {
            throw Error(ErrorCode::OutOfMemory, file + ": out of memory while reading the " + format + " file");
        } catch (const std::exception& e) {
            throw Error(ErrorCode::ParseError, file + ": cannot read as " + format + ": " + e.what());
        }
    }
    if (!s || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !s->mRootNode) throw readFailure(importer, *io, path, format);
    return s;
}

/// The model's materials, appended to the scene's, and the tinted copies that
/// vertex colours make of them, each made once.
class ModelMaterials {
public:
    ModelMaterials(Scene& scene, const aiScene& s, const fs::path& path, const LoadOptions& options, const Logger& log)
        : scene_(scene), converter_(scene, path, options, log), base_(static_cast<uint32_t>(scene.materials.size())) {
        for (unsigned i = 0; i < s.mNumMaterials; ++i)
            scene.materials.push_back(converter_.convert(phongOf(*s.mMaterials[i], path, log, path.string() + ": material")));
        converter_.flushWarnings();
        count_ = scene.materials.size() - base_;
    }
    /// The scene's material for the model's material `index`; the default one when there is none.
    uint32_t of(unsigned index) { return index < count_ ? base_ + index : converter_.defaultMaterial(); }
    /// Whether `id` is one of the model's own materials (vertex colours tint only those).
    bool own(uint32_t id) const { return id >= base_; }
    /// `id` tinted by an 8-bit colour (white: `id` itself).
    uint32_t tinted(uint32_t id, const std::array<uint8_t, 3>& q) {
        if (q == std::array<uint8_t, 3>{255, 255, 255}) return id;
        auto [it, fresh] = tinted_.try_emplace({id, q[0], q[1], q[2]}, 0);
        if (fresh) {
            Material tint = scene_.materials[id];
            tint.kd = Rgb(tint.kd) * Rgb(q[0] / 255.f, q[1] / 255.f, q[2] / 255.f);
            tint.name += "*vertex colour";
            it->second = static_cast<uint32_t>(scene_.materials.size());
            scene_.materials.push_back(tint);
        }
        return it->second;
    }
    uint32_t base() const { return base_; }

private:
    Scene& scene_;
    MaterialConverter converter_;
    uint32_t base_;
    size_t count_ = 0;
    std::map<std::tuple<uint32_t, uint8_t, uint8_t, uint8_t>, uint32_t> tinted_;  // (material, colour) -> material
};

/// Every node with its transform to the world, walked without recursion (a
/// file may nest deeply) and each once (a node graph is a tree; a broken file
/// must not loop).
std::vector<std::pair<const aiNode*, Transform>> placedNodes(const aiScene& s, const Transform& worldFromObject) {
    std::vector<std::pair<const aiNode*, Transform>> placed, stack{{s.mRootNode, worldFromObject}};
    std::set<const aiNode*> visited;
    while (!stack.empty()) {
        auto [node, parent] = stack.back();
        stack.pop_back();
        if (!visited.insert(node).second) continue;
        const Transform t = parent * toTransform(node->mTransformation);
        placed.emplace_back(node, t);
        for (unsigned c = node->mNumChildren; c-- > 0;)
            if (node->mChildren[c]) stack.emplace_back(node->mChildren[c], t);
    }
    return placed;
}

/// Every placement of a mesh after its first is a copy: counted, and refused
/// past CopyCount's limit, before any is made.
void checkCopies(const aiScene& s, const std::vector<std::pair<const aiNode*, Transform>>& nodes, const std::string& file) {
    std::vector<uint64_t> uses(s.mNumMeshes, 0);
    for (const auto& [node, t] : nodes)
        for (unsigned k = 0; k < node->mNumMeshes; ++k)
            if (node->mMeshes[k] < s.mNumMeshes) ++uses[node->mMeshes[k]];
    CopyCount copies;
    for (unsigned i = 0; i < s.mNumMeshes; ++i)
        if (uses[i] > 1) copies.add(uses[i] - 1, s.mMeshes[i]->mNumFaces, s.mMeshes[i]->mNumVertices);
    copies.check(file + ": meshes placed by several nodes");
}

/// The mesh's vertices placed by t: positions, normals and the first UV set.
void placedVertices(const aiMesh& am, const Transform& t, TriangleMesh& m) {
    m.positions.reserve(am.mNumVertices);
    for (unsigned v = 0; v < am.mNumVertices; ++v) m.positions.push_back(t.applyPoint(vec(am.mVertices[v])));
    if (am.mNormals) {
        m.normals.reserve(am.mNumVertices);
        for (unsigned v = 0; v < am.mNumVertices; ++v) m.normals.push_back(t.applyNormal(vec(am.mNormals[v])));
    }
    if (am.mTextureCoords[0]) {
        m.uvs.reserve(am.mNumVertices);
        for (unsigned v = 0; v < am.mNumVertices; ++v) m.uvs.push_back({am.mTextureCoords[0][v].x, am.mTextureCoords[0][v].y});
    }
}

/// One face's triangles as corner indices (polygons split as OBJ's are).
void faceTriangles(const aiMesh& am, const aiFace& face, std::vector<uint32_t>& triangles) {
    triangles.assign(face.mIndices, face.mIndices + 3);
    if (face.mNumIndices == 3) return;
    std::vector<Vec3f> polygon;
    for (unsigned c = 0; c < face.mNumIndices; ++c) polygon.push_back(vec(am.mVertices[face.mIndices[c]]));
    std::vector<std::array<uint32_t, 3>> split;
    triangulate(polygon, split);
    triangles.clear();
    for (const auto& tri : split)
        for (uint32_t c : tri) triangles.push_back(face.mIndices[c]);
}

/// The faces as triangles of `m` (whose vertices are placed), with vertex
/// colours as tinted materials. Faces on missing or non-finite positions (NaN
/// in the file, or beyond float range after the node's transform) are
/// counted in `dropped`.
void addFaces(const aiMesh& am, bool mirrored, ModelMaterials& materials, TriangleMesh& m, size_t& dropped) {
    const bool colours = am.mColors[0] != nullptr && materials.own(m.material);
    m.indices.reserve(size_t(am.mNumFaces) * 3);
    std::vector<uint32_t> triangles;
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
        const aiFace& face = am.mFaces[f];
        if (face.mNumIndices < 3 || !face.mIndices) continue;  // points and lines
        if (std::any_of(face.mIndices, face.mIndices + face.mNumIndices,
                        [&](unsigned i) { return i >= am.mNumVertices || !isFinite(m.positions[i]); })) {
            ++dropped;
            continue;
        }
        faceTriangles(am, face, triangles);
        for (size_t first = 0; first + 3 <= triangles.size(); first += 3) {
            const uint32_t* tri = triangles.data() + first;
            if (mirrored)  // keeps the front side the front side, as for OBJ
                m.indices.insert(m.indices.end(), {tri[0], tri[2], tri[1]});
            else
                m.indices.insert(m.indices.end(), tri, tri + 3);
            if (colours) m.faceMaterials.push_back(materials.tinted(m.material, triangleColour(am, tri)));
        }
    }
}

/// One mesh placed by one node, or nullopt when it has no triangle left.
std::optional<TriangleMesh> placedMesh(const aiMesh& am, const aiNode& node, const Transform& t, const fs::path& path,
                                       ModelMaterials& materials, size_t& dropped) {
    if (!am.mVertices || !am.mFaces) return std::nullopt;
    TriangleMesh m;
    m.name = am.mName.length ? std::string(am.mName.C_Str()) : path.stem().string();
    if (node.mName.length && m.name != node.mName.C_Str()) m.name = std::string(node.mName.C_Str()) + "/" + m.name;
    m.material = materials.of(am.mMaterialIndex);
    placedVertices(am, t, m);
    addFaces(am, t.determinant() < 0.f, materials, m, dropped);
    if (m.indices.empty()) return std::nullopt;
    if (!std::all_of(m.positions.begin(), m.positions.end(), [](const Vec3f& p) { return isFinite(p); }))
        keepUsedVertices(m);  // a loaded mesh holds finite positions only
    if (!m.faceMaterials.empty() &&
        std::all_of(m.faceMaterials.begin(), m.faceMaterials.end(), [&](uint32_t id) { return id == m.material; }))
        m.faceMaterials.clear();
    return m;
}

/// Faces dropped for their positions are a warning naming the file, as for
/// OBJ files, and an error in strict mode.
void reportDropped(size_t dropped, const std::string& file, const LoadOptions& options, const Logger& log) {
    if (dropped == 0) return;
    const std::string what = std::to_string(dropped) + " face(s) with non-finite (NaN or infinite) or missing vertex positions";
    if (options.strict) throw Error(ErrorCode::ParseError, file + ": " + what);
    log.warn(file + ": dropped " + what);
}

/// The first usable camera, through its node.
std::optional<CameraDesc> firstCamera(const aiScene& s, const Transform& worldFromObject) {
    for (unsigned i = 0; i < s.mNumCameras; ++i) {
        const aiCamera& c = *s.mCameras[i];
        const aiNode* node = s.mRootNode->FindNode(c.mName);
        const Transform t = worldFromObject * globalOf(node);
        // The position is relative to the node, but Assimp's glTF importer
        // also copies the node's translation into it: counted once.
        Vec3f local = vec(c.mPosition);
        if (node && local.x == node->mTransformation.a4 && local.y == node->mTransformation.b4 &&
            local.z == node->mTransformation.c4)
            local = Vec3f{};
        CameraDesc cam;
        cam.eye = t.applyPoint(local);
        const Vec3f dir = t.applyVector(vec(c.mLookAt)), up = t.applyVector(vec(c.mUp));
        const float l = length(dir);
        if (!(l > 0.f) || !std::isfinite(l) || !(length(up) > 0.f)) continue;
        cam.lookAt = cam.eye + dir / l;
        cam.up = up;
        // Assimp's horizontal angle (the full angle, as its glTF and COLLADA importers fill it) as a vertical one.
        const float aspect = c.mAspect > 0.f && std::isfinite(c.mAspect) ? c.mAspect : 1.f;
        if (c.mHorizontalFOV > 0.f && c.mHorizontalFOV < kPi) {
            const float vfov = 2.f * std::atan(std::tan(0.5f * c.mHorizontalFOV) / aspect) * 180.f / kPi;
            if (vfov > 0.f && vfov < 180.f) cam.vfovDegrees = vfov;
        }
        if (isFinite(cam.eye) && isFinite(cam.lookAt) && isFinite(cam.up)) return cam;
    }
    return std::nullopt;
}

/// Point, spot (as point) and directional lights, through their nodes.
void addLights(const aiScene& s, const Transform& worldFromObject, ModelExtras& extras, const std::string& file,
               const Logger& log) {
    size_t skipped = 0;
    for (unsigned i = 0; i < s.mNumLights; ++i) {
        const aiLight& l = *s.mLights[i];
        const Transform t = worldFromObject * globalOf(s.mRootNode->FindNode(l.mName));
        const Rgb colour(clean(l.mColorDiffuse.r), clean(l.mColorDiffuse.g), clean(l.mColorDiffuse.b));
        if (l.mType == aiLightSource_POINT || l.mType == aiLightSource_SPOT) {
            if (l.mType == aiLightSource_SPOT) ++skipped;
            const Vec3f p = t.applyPoint(vec(l.mPosition));
            if (isFinite(p)) extras.pointLights.push_back({p, colour});
        } else if (l.mType == aiLightSource_DIRECTIONAL) {
            const Vec3f d = t.applyVector(vec(l.mDirection));
            const float len = length(d);
            if (len > 0.f && std::isfinite(len)) extras.directionalLights.push_back({d / len, colour});
        } else {
            ++skipped;
        }
    }
    if (skipped)
        log.warn(file + ": " + std::to_string(skipped) +
                 " spot, ambient or area light(s): spot lights shine as point lights, the others are skipped");
}

}  // namespace

bool assimpReadsExtension(const std::string& extension) {
    const std::string e = lower(extension);
    if (e.size() < 2 || e[0] != '.') return false;
    return Assimp::Importer().IsExtensionSupported(e);
}

std::vector<std::string> assimpExtensions() {
    std::string list;
    Assimp::Importer().GetExtensionList(list);  // "*.3ds;*.dae;..."
    std::vector<std::string> out;
    std::istringstream in(list);
    std::string item;
    while (std::getline(in, item, ';')) {
        if (item.rfind("*.", 0) == 0) out.push_back(lower(item.substr(1)));
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

ObjStats appendAssimp(Scene& scene, const InputFile& model, const Transform& worldFromObject, const LoadOptions& options,
                      const Logger& log, ModelExtras& extras) {
    const fs::path& path = model.path();
    Assimp::Importer importer;
    const aiScene& s = *readModel(importer, model, options);
    const std::vector<std::pair<const aiNode*, Transform>> nodes = placedNodes(s, worldFromObject);
    checkCopies(s, nodes, path.string());

    ModelMaterials materials(scene, s, path, options, log);
    ObjStats stats;
    const size_t firstMesh = scene.meshes.size();
    for (const auto& [node, t] : nodes)
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            if (node->mMeshes[k] >= s.mNumMeshes) continue;
            std::optional<TriangleMesh> m = placedMesh(*s.mMeshes[node->mMeshes[k]], *node, t, path, materials, stats.droppedFaces);
            if (!m) continue;
            stats.triangles += m->triangleCount();
            for (size_t tri = 0; tri < m->triangleCount(); ++tri)
                stats.emissiveTriangles += scene.materials[m->materialOf(tri)].isEmissive();
            scene.meshes.push_back(std::move(*m));
        }
    reportDropped(stats.droppedFaces, path.string(), options, log);
    stats.materials = scene.materials.size() - materials.base();
    applyMeshOptions(scene, firstMesh, materials.base(), options);
    if (!extras.camera) extras.camera = firstCamera(s, worldFromObject);
    addLights(s, worldFromObject, extras, path.string(), log);
    return stats;
}

}  // namespace penumbra
