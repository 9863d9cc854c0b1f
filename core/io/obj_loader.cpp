// OBJ/MTL loading on top of tinyobjloader, the one file that includes it.
//
// tinyobjloader is lenient in ways a renderer cannot be: it keeps out-of-range
// face indices, turns `nan` into 0, fails the whole file on a zero index, and
// reads `1.#IND` as 1. So the OBJ text goes through a small pre-pass first
// (obj_prepass.cpp), tinyobjloader parses the result without triangulating,
// and every face is validated before it is triangulated and de-indexed into
// TriangleMeshes (obj_faces.cpp). MTL files are found and read by
// mtl_files.cpp and mapped to materials by mtl_materials.cpp.
#include <tiny_obj_loader.h>

#include <map>
#include <new>
#include <set>
#include <sstream>
#include <string_view>
#include <type_traits>

#include "core/error.h"
#include "core/io/mtl_files.h"
#include "core/io/mesh_options.h"
#include "core/io/mtl_materials.h"
#include "core/io/obj_loader.h"
#include "core/io/obj_prepass.h"
#include "core/io/obj_text.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;
using namespace obj_text;

static_assert(std::is_same_v<tinyobj::real_t, float>, "the face builder reads tinyobjloader's arrays as floats");

std::string name(const fs::path& p) { return p.string(); }

/// tinyobjloader's side of `mtllib`: the files come from MtlLibraries (path
/// policy, one open, checks); material names are trimmed (`newmtl tallBox `
/// must match `usemtl tallBox`), and each material remembers its file.
class MtlReader : public tinyobj::MaterialReader {
public:
    MtlReader(fs::path objDir, const LoadOptions& options) : libraries(std::move(objDir), options) {}

    bool operator()(const std::string& matId, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* matMap, std::string* warn, std::string* err) override {
        std::optional<MtlText> mtl = libraries.read(matId, warn);
        if (!mtl) return false;
        std::istringstream in(mtl->text);
        std::map<std::string, int> local;
        size_t begin = materials->size();
        std::string w, e;
        tinyobj::LoadMtl(&local, materials, &in, &w, &e);
        for (size_t i = begin; i < materials->size(); ++i) {
            auto& m = (*materials)[i];
            m.name = std::string(trim(m.name));
            matMap->insert({m.name, static_cast<int>(i)});
        }
        files.resize(materials->size(), mtl->file);
        if (warn && !w.empty()) *warn += w;
        if (err && !e.empty()) *err += e;
        return true;
    }

    MtlLibraries libraries;
    std::vector<fs::path> files;  // per material, the MTL it came from
};

MtlMaterial copyOut(const tinyobj::material_t& t, const fs::path& file) {
    MtlMaterial m;
    m.name = t.name;
    m.file = file;
    for (int i = 0; i < 3; ++i) {
        m.ambient[i] = t.ambient[i];
        m.diffuse[i] = t.diffuse[i];
        m.specular[i] = t.specular[i];
        m.emission[i] = t.emission[i];
        m.transmittance[i] = t.transmittance[i];
    }
    m.ior = t.ior;
    m.shininess = t.shininess;
    m.illum = t.illum;
    for (const auto& kv : t.unknown_parameter) m.unknownKeys.push_back(kv.first);
    m.diffuseTexture = t.diffuse_texname;
    auto map = [](const std::string& name, const tinyobj::texture_option_t& o) {
        return MtlTexture{name,    {o.origin_offset[0], o.origin_offset[1]}, {o.scale[0], o.scale[1]}, o.clamp,
                          o.imfchan, o.contrast, o.brightness, o.bump_multiplier};
    };
    m.emissiveMap = map(t.emissive_texname, t.emissive_texopt);
    m.alphaMap = map(t.alpha_texname, t.alpha_texopt);
    m.bumpMap = map(t.bump_texname, t.bump_texopt);
    m.normalMap = map(t.normal_texname, t.normal_texopt);
    m.roughnessMap = map(t.roughness_texname, t.roughness_texopt);
    m.metallicMap = map(t.metallic_texname, t.metallic_texopt);
    m.roughness = t.roughness;
    m.metallic = t.metallic;
    return m;
}

/// Lines of tinyobjloader's warnings, without those this loader reports
/// itself more precisely or that concern ignored keys, each distinct line once.
std::vector<std::string> filterTinyObjWarnings(const std::string& warn) {
    static constexpr std::string_view kOwn[] = {"Vertex indices out of bounds", "Vertex normal indices out of bounds",
                                                "Vertex texcoord indices out of bounds", "Degenerated face found",
                                                "Face with invalid vertex index",
                                                // d and Tr (dissolve) are not used
                                                "Both `d` and `Tr`"};
    std::vector<std::string> out;
    std::set<std::string> seen;
    std::istringstream in(warn);
    std::string line;
    while (std::getline(in, line)) {
        std::string_view t = trim(line);
        if (t.empty() || t == ".") continue;
        bool own = false;
        for (auto k : kOwn) own = own || t.substr(0, k.size()) == k;
        if (!own && seen.insert(std::string(t)).second) out.emplace_back(t);
    }
    return out;
}

}  // namespace

ObjStats appendObj(Scene& scene, const InputFile& obj, const Transform& worldFromObject, const LoadOptions& options,
                   const Logger& log) {
    const fs::path& objPath = obj.path();
    const std::string file = name(objPath);
    PreparedObj prep;
    {
        std::string text = obj.readAll();
        stripBom(text);
        if (auto bad = binaryDataProblem(text)) throw Error(ErrorCode::ParseError, file + ":" + *bad);
        prep = prepareObj(text);
    }

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> mtls;
    std::string warn, err;
    MtlReader reader(objPath.parent_path(), options);
    bool ok;
    {
        std::istringstream in(std::move(prep.text));
        ok = tinyobj::LoadObj(&attrib, &shapes, &mtls, &warn, &err, &in, &reader, /*triangulate=*/false,
                              /*default_vcols_fallback=*/false);
    }
    if (reader.libraries.error) throw *reader.libraries.error;
    if (!ok) throw Error(ErrorCode::ParseError, file + ": " + std::string(trim(err.empty() ? "parse error" : err)));
    for (const auto& w : filterTinyObjWarnings(warn)) log.warn(file + ": " + w);
    for (const auto& e : filterTinyObjWarnings(err)) log.warn(file + ": " + e);

    // Materials: appended after the scene's own, in MTL order.
    const uint32_t materialBase = static_cast<uint32_t>(scene.materials.size());
    const size_t firstMesh = scene.meshes.size();
    MaterialConverter converter(scene, objPath, options, log);
    for (size_t i = 0; i < mtls.size(); ++i)
        scene.materials.push_back(converter.convert(copyOut(mtls[i], i < reader.files.size() ? reader.files[i] : fs::path())));
    converter.flushWarnings();

    size_t totalFaces = 0;
    for (const auto& s : shapes) totalFaces += s.mesh.num_face_vertices.size();
    ObjMeshBuilder builder(scene, prep, attrib.vertices, attrib.normals, attrib.texcoords, worldFromObject, totalFaces,
                           converter, materialBase, mtls.size());
    std::vector<ObjCorner> corners;
    for (size_t si = 0; si < shapes.size(); ++si) {
        const tinyobj::mesh_t& sm = shapes[si].mesh;
        std::string shapeName(trim(shapes[si].name));
        builder.beginShape(shapeName.empty() ? objPath.stem().string() : shapeName);
        size_t offset = 0;
        for (size_t f = 0; f < sm.num_face_vertices.size(); ++f) {
            const size_t n = sm.num_face_vertices[f];
            if (offset + n > sm.indices.size()) break;  // cannot happen with tinyobjloader; guards the reads
            corners.resize(n);
            for (size_t i = 0; i < n; ++i) {
                const tinyobj::index_t& ix = sm.indices[offset + i];
                corners[i] = {ix.vertex_index, ix.normal_index, ix.texcoord_index};
            }
            offset += n;
            builder.addFace(corners.data(), n, f < sm.material_ids.size() ? sm.material_ids[f] : -1);
        }
        builder.endShape();
    }
    ObjStats stats = builder.finish(file, options, log);
    stats.materials = scene.materials.size() - materialBase;
    applyMeshOptions(scene, firstMesh, materialBase, options);
    return stats;
}

ObjStats appendObj(Scene& scene, const fs::path& objPath, const Transform& worldFromObject, const LoadOptions& options,
                   const Logger& log) {
    return appendObj(scene, *openInputFile(objPath, options), worldFromObject, options, log);
}

LoadedScene loadObjScene(const fs::path& path, const LoadOptions& options, const Logger& log) {
    LoadedScene loaded;
    loaded.sourcePath = path;
    ObjStats stats;
    try {
        stats = appendObj(loaded.scene, path, Transform(), options, log);
    } catch (const std::bad_alloc&) {
        throw Error(ErrorCode::OutOfMemory, name(path) + ": out of memory while loading the scene");
    }
    if (stats.triangles == 0)
        throw Error(ErrorCode::InvalidScene,
                    name(path) + ": no faces to render" +
                        (stats.droppedFaces ? " (all " + std::to_string(stats.droppedFaces) +
                                                  " face(s) or triangle(s) were invalid or degenerate)"
                                            : std::string()));
    return loaded;
}

}  // namespace penumbra
