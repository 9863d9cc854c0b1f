// JSON meshes: model files (OBJ and the Assimp formats) placed by a transform, and inline triangle lists (SceneReader, json_reader.h).
#include "core/io/json_reader.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <type_traits>

#include "core/io/input_file.h"
#include "core/io/model_file.h"
#include <penumbra/names.hpp>

namespace penumbra {
namespace fs = std::filesystem;
using namespace json_text;

void SceneReader::readObjMesh(const Json& j, const std::string& ptr, Scene& scene) {
    checkKeys(j, ptr, {"type", "name", "material", "emission", "file", "transform", "model", "smooth_angle"});
    std::string fp = child(ptr, "file");
    fs::path file = resolvePath(*find(j, "file"), fp);
    // The file's own options: "model" and "smooth_angle" override the caller's.
    LoadOptions options = options_;
    if (const Json* v = find(j, "model")) {
        const std::string mp = child(ptr, "model");
        const std::string model = string(*v, mp);
        if (const std::optional<PhongModel> m = pnb::enumFromName<PhongModel>(model))
            options.meshModel = *m;
        else
            fail(ErrorCode::ParseError, mp, "expected " + pnb::enumNameList<PhongModel>("\"") + ", got \"" + model + "\"");
    }
    if (const Json* v = find(j, "smooth_angle")) {
        const std::string sp = child(ptr, "smooth_angle");
        options.smoothAngleDegrees = nonNegative(*v, sp);
        if (options.smoothAngleDegrees > 180.f) fail(ErrorCode::ParseError, sp, "must lie in [0, 180] degrees");
    }
    if (!isModelExtension(file.extension().string()))
        fail(ErrorCode::InvalidArgument, fp,
             file.string() + ": unknown mesh format " +
                 (file.extension().empty() ? std::string("(no extension)") : "'" + file.extension().string() + "'") +
                 " (supported: " + modelFormatsText() + ")");
    // Opened once, right after the path check; appendObj reads this descriptor only.
    std::unique_ptr<InputFile> in;
    try {
        in = openInputFile(file, options_);
    } catch (const Error& e) {
        if (e.code() == ErrorCode::FileNotFound) fail(ErrorCode::FileNotFound, fp, "mesh file not found: " + file.string());
        fail(e.code(), fp, e.what());
    }
    Transform t;
    if (const Json* v = find(j, "transform")) t = readTransform(*v, child(ptr, "transform"));
    // Resolve the material before loading, so a bad name fails fast.
    std::optional<uint32_t> override;
    if (find(j, "material")) override = shapeMaterial(j, ptr, scene);

    const size_t firstMesh = scene.meshes.size();
    ObjStats stats;
    try {
        ModelFile model = appendModelFile(scene, *in, t, options, log_);
        stats = model.stats;
        // The file's camera and lights count when the JSON scene has none (SceneReader::read).
        if (model.extras.camera && !modelCamera_) modelCamera_ = model.extras.camera;
        modelPointLights_.insert(modelPointLights_.end(), model.extras.pointLights.begin(),
                                 model.extras.pointLights.end());
        modelDirectionalLights_.insert(modelDirectionalLights_.end(), model.extras.directionalLights.begin(),
                                       model.extras.directionalLights.end());
    } catch (const Error& e) {
        fail(e.code(), ptr, e.what());
    }
    if (stats.triangles == 0) warnOrFail(ErrorCode::InvalidScene, fp, "mesh file has no triangles: " + file.string());

    std::string name;
    if (const Json* v = find(j, "name")) name = string(*v, child(ptr, "name"));
    std::map<uint32_t, uint32_t> emissive;  // MTL material -> its emissive copy
    const Json* emission = override ? nullptr : find(j, "emission");
    Rgb ke = emission ? colour(*emission, child(ptr, "emission")) : Rgb();
    auto remap = [&](uint32_t& id) {
        if (id >= scene.materials.size()) return;  // finalize() repairs it
        auto [it, fresh] = emissive.try_emplace(id, 0);
        if (fresh) it->second = emissiveCopy(id, ke, ptr, scene);
        id = it->second;
    };
    for (size_t i = firstMesh; i < scene.meshes.size(); ++i) {
        TriangleMesh& m = scene.meshes[i];
        if (!name.empty()) m.name = name;
        if (override) {
            m.material = *override;
            m.faceMaterials.clear();
        } else if (emission) {
            remap(m.material);
            for (uint32_t& id : m.faceMaterials) remap(id);
        }
    }
}

template <class T>
std::vector<T> SceneReader::tuples(const Json& j, const std::string& ptr, size_t arity, const char* what) const {
    if (!j.is_array()) fail(ErrorCode::ParseError, ptr, std::string("expected an array of ") + what);
    std::vector<T> out;
    bool nested = !j.empty() && j[0].is_array();
    out.reserve(nested ? j.size() * arity : j.size());
    auto element = [&](const Json& e, size_t i, size_t k) {
        if constexpr (std::is_same_v<T, float>) {
            if (e.is_number()) {
                float v = static_cast<float>(e.get<double>());
                if (std::isfinite(v)) return out.push_back(v);
            }
            number(e, nested ? child(child(ptr, i), k) : child(ptr, i));  // throws the precise error
        } else {
            if (e.is_number_unsigned()) return out.push_back(static_cast<T>(std::min<uint64_t>(e.get<uint64_t>(), UINT32_MAX)));
            // Integral floats are accepted; anything else throws the precise error.
            out.push_back(static_cast<T>(integer(e, nested ? child(child(ptr, i), k) : child(ptr, i), 0, UINT32_MAX)));
        }
    };
    if (nested) {
        for (size_t i = 0; i < j.size(); ++i) {
            const Json& t = j[i];
            if (!t.is_array() || t.size() != arity)
                fail(ErrorCode::ParseError, child(ptr, i),
                     "expected an array of " + std::to_string(arity) + " numbers (all entries nested alike)");
            for (size_t k = 0; k < arity; ++k) element(t[k], i, k);
        }
    } else {
        if (j.size() % arity != 0)
            fail(ErrorCode::ParseError, ptr,
                 "a flat array needs a multiple of " + std::to_string(arity) + " numbers, got " + std::to_string(j.size()));
        for (size_t i = 0; i < j.size(); ++i) element(j[i], i, 0);
    }
    return out;
}

void SceneReader::readInlineMesh(const Json& j, const std::string& ptr, Scene& scene) {
    checkKeys(j, ptr, {"type", "name", "material", "emission", "vertices", "indices", "normals", "uvs", "transform"});
    TriangleMesh m;
    m.name = "mesh@" + ptr;
    if (const Json* v = find(j, "name")) m.name = string(*v, child(ptr, "name"));
    std::vector<float> p = tuples<float>(require(j, ptr, "vertices", "an inline mesh"), child(ptr, "vertices"), 3,
                                         "vertices [x, y, z]");
    std::vector<uint32_t> idx = tuples<uint32_t>(require(j, ptr, "indices", "an inline mesh"), child(ptr, "indices"),
                                                 3, "triangles [i, j, k]");
    const size_t nv = p.size() / 3;
    if (idx.empty()) fail(ErrorCode::InvalidScene, child(ptr, "indices"), "a mesh needs at least one triangle");
    for (size_t i = 0; i < idx.size(); ++i) {
        if (idx[i] >= nv) {
            const Json& ij = j["indices"];
            std::string ip = ij[0].is_array() ? child(child(child(ptr, "indices"), i / 3), i % 3)
                                              : child(child(ptr, "indices"), i);
            fail(ErrorCode::InvalidScene, ip,
                 "vertex index " + std::to_string(idx[i]) + " out of range (the mesh has " + std::to_string(nv) +
                     " vertices)");
        }
    }
    Transform t;
    if (const Json* v = find(j, "transform")) t = readTransform(*v, child(ptr, "transform"));
    m.positions.reserve(nv);
    for (size_t i = 0; i < nv; ++i) m.positions.push_back(t.applyPoint({p[3 * i], p[3 * i + 1], p[3 * i + 2]}));
    m.indices = std::move(idx);
    if (const Json* v = find(j, "normals")) {
        std::string np = child(ptr, "normals");
        std::vector<float> n = tuples<float>(*v, np, 3, "normals [x, y, z]");
        if (n.size() / 3 != nv)
            fail(ErrorCode::InvalidScene, np,
                 "has " + std::to_string(n.size() / 3) + " normals for " + std::to_string(nv) + " vertices");
        for (size_t i = 0; i < nv; ++i)
            m.normals.push_back(normalize(t.applyNormal({n[3 * i], n[3 * i + 1], n[3 * i + 2]})));
    }
    if (const Json* v = find(j, "uvs")) {
        std::string up = child(ptr, "uvs");
        std::vector<float> uv = tuples<float>(*v, up, 2, "texture coordinates [u, v]");
        if (uv.size() / 2 != nv)
            fail(ErrorCode::InvalidScene, up,
                 "has " + std::to_string(uv.size() / 2) + " texture coordinates for " + std::to_string(nv) + " vertices");
        for (size_t i = 0; i < nv; ++i) m.uvs.push_back({uv[2 * i], uv[2 * i + 1]});
    }
    Bounds3f b;
    for (const Vec3f& q : m.positions) b.extend(q);
    checkRange(b, child(ptr, "vertices"));
    m.material = shapeMaterial(j, ptr, scene);
    scene.meshes.push_back(std::move(m));
}
}  // namespace penumbra
