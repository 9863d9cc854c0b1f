#include "core/io/gltf_loader.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <tuple>

#include "core/error.h"
#include "core/io/gltf_accessors.h"
#include "core/io/gltf_materials.h"
#include "core/io/gltf_meshes.h"
#include "core/io/mesh_options.h"
#include "core/mesh_tangents.h"

namespace penumbra {
namespace {

/// A node's transform relative to its parent: its matrix (column-major), or T * R * S.
Transform localTransform(const tinygltf::Node& n) {
    float rows[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    if (n.matrix.size() == 16) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) rows[r][c] = float(n.matrix[size_t(c) * 4 + size_t(r)]);
        return Transform(rows);
    }
    double q[4] = {0, 0, 0, 1};
    if (n.rotation.size() == 4) {
        const double l = std::sqrt(n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                                   n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3]);
        if (l > 0.0 && std::isfinite(l))
            for (int k = 0; k < 4; ++k) q[k] = n.rotation[size_t(k)] / l;
    }
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; ++i) {
        for (int c = 0; c < 3; ++c) rows[i][c] = float(r[i][c] * (n.scale.size() == 3 ? n.scale[size_t(c)] : 1.0));
        rows[i][3] = n.translation.size() == 3 ? float(n.translation[size_t(i)]) : 0.f;
    }
    return Transform(rows);
}

/// A node drawn at a place in the world.
struct Placed {
    int node;
    Transform world;
};

/// The nodes of the file's scene (its default, else the first; without
/// scenes, the nodes no other node names as a child), depth first, each
/// with its world transform. A stack instead of recursion: a file may nest
/// nodes deeply. A node reached again (glTF gives every node one parent; a
/// broken file may loop) is skipped there, with one warning.
std::vector<Placed> placeNodes(const GltfFile& file, const Transform& worldFromObject, const Logger& log) {
    const tinygltf::Model& m = file.model;
    const int nn = int(m.nodes.size());
    std::vector<int> roots;
    const int scene = m.defaultScene >= 0 && size_t(m.defaultScene) < m.scenes.size() ? m.defaultScene : 0;
    if (!m.scenes.empty()) {
        roots = m.scenes[size_t(scene)].nodes;
    } else {
        std::vector<char> child(size_t(nn), 0);
        for (const tinygltf::Node& n : m.nodes)
            for (int c : n.children)
                if (c >= 0 && c < nn) child[size_t(c)] = 1;
        for (int i = 0; i < nn; ++i)
            if (!child[size_t(i)]) roots.push_back(i);
    }
    std::vector<Placed> out;
    std::vector<char> visited(size_t(nn), 0);
    size_t again = 0, missing = 0;
    std::vector<Placed> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, worldFromObject});
    while (!stack.empty()) {
        const Placed p = stack.back();
        stack.pop_back();
        if (p.node < 0 || p.node >= nn) {
            ++missing;
            continue;
        }
        if (visited[size_t(p.node)]++) {
            ++again;
            continue;
        }
        const tinygltf::Node& n = m.nodes[size_t(p.node)];
        const Transform world = p.world * localTransform(n);
        out.push_back({p.node, world});
        for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, world});
    }
    if (again)
        log.warn(file.where() + ": " + std::to_string(again) +
                 " node reference(s) reach a node a second time (a node has one parent in glTF); skipped there");
    if (missing) log.warn(file.where() + ": " + std::to_string(missing) + " reference(s) to nodes that do not exist; skipped");
    return out;
}

/// The first perspective camera of the placed nodes, in world space (glTF
/// cameras look along their node's -z with +y up).
std::optional<CameraDesc> firstCamera(const GltfFile& file, const std::vector<Placed>& placed, const Logger& log) {
    const tinygltf::Model& m = file.model;
    bool orthographic = false;
    for (const Placed& p : placed) {
        const int c = m.nodes[size_t(p.node)].camera;
        if (c < 0 || size_t(c) >= m.cameras.size()) continue;
        const tinygltf::Camera& cam = m.cameras[size_t(c)];
        if (cam.type != "perspective") {
            orthographic = true;
            continue;
        }
        CameraDesc d;
        d.eye = p.world.applyPoint({0.f, 0.f, 0.f});
        const Vec3f dir = p.world.applyVector({0.f, 0.f, -1.f}), up = p.world.applyVector({0.f, 1.f, 0.f});
        const float l = length(dir);
        if (!(l > 0.f) || !std::isfinite(l) || !(length(up) > 0.f)) continue;
        d.lookAt = d.eye + dir / l;
        d.up = up;
        const double vfov = cam.perspective.yfov * 180.0 / kPi;
        if (vfov > 0.0 && vfov < 180.0) d.vfovDegrees = float(vfov);
        if (isFinite(d.eye) && isFinite(d.lookAt) && isFinite(d.up)) return d;
    }
    if (orthographic) log.warn(file.where() + ": orthographic cameras are not supported; using another view");
    return std::nullopt;
}

/// KHR_lights_punctual lights of the placed nodes: point lights (spot
/// lights shine as point lights, with a warning) and directional lights.
void addLights(const GltfFile& file, const std::vector<Placed>& placed, ModelExtras& extras, const Logger& log) {
    const tinygltf::Model& m = file.model;
    size_t spots = 0;
    for (const Placed& p : placed) {
        const auto ext = m.nodes[size_t(p.node)].extensions.find("KHR_lights_punctual");
        if (ext == m.nodes[size_t(p.node)].extensions.end() || !ext->second.IsObject() || !ext->second.Has("light")) continue;
        const tinygltf::Value& index = ext->second.Get("light");
        if (!index.IsNumber() || index.GetNumberAsInt() < 0 || size_t(index.GetNumberAsInt()) >= m.lights.size()) continue;
        const tinygltf::Light& l = m.lights[size_t(index.GetNumberAsInt())];
        auto clean = [](double v) { return std::isfinite(v) && v > 0.0 ? float(v) : 0.f; };
        const float intensity = clean(l.intensity);
        const Rgb colour = l.color.size() == 3 ? Rgb(clean(l.color[0]), clean(l.color[1]), clean(l.color[2])) : Rgb(1.f);
        if (l.type == "point" || l.type == "spot") {
            spots += l.type == "spot";
            const Vec3f at = p.world.applyPoint({0.f, 0.f, 0.f});
            if (isFinite(at)) extras.pointLights.push_back({at, colour * intensity});
        } else if (l.type == "directional") {
            const Vec3f d = p.world.applyVector({0.f, 0.f, -1.f});
            const float len = length(d);
            if (len > 0.f && std::isfinite(len)) extras.directionalLights.push_back({d / len, colour * intensity});
        }
    }
    if (spots) log.warn(file.where() + ": " + std::to_string(spots) + " spot light(s) shine as point lights");
}

/// Vertex colours multiply the base colour: each triangle's mean colour,
/// quantised to 8 bits so that triangles of one colour share a material.
class Tints {
public:
    explicit Tints(Scene& scene) : scene_(scene) {}
    void apply(TriangleMesh& m, const std::vector<Vec3f>& colours) {
        if (colours.size() != m.positions.size()) return;
        m.faceMaterials.assign(m.triangleCount(), m.material);
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            float sum[3] = {0.f, 0.f, 0.f};
            for (int k = 0; k < 3; ++k) {
                const Vec3f& c = colours[m.indices[3 * t + size_t(k)]];
                const float v[3] = {c.x, c.y, c.z};
                for (int i = 0; i < 3; ++i) sum[i] += std::isfinite(v[i]) ? std::clamp(v[i], 0.f, 1.f) : 1.f;
            }
            std::array<uint8_t, 3> q{};
            for (int i = 0; i < 3; ++i) q[i] = static_cast<uint8_t>(std::lround(sum[i] / 3.f * 255.f));
            if (q != std::array<uint8_t, 3>{255, 255, 255}) m.faceMaterials[t] = tinted(m.material, q);
        }
        if (std::all_of(m.faceMaterials.begin(), m.faceMaterials.end(), [&](uint32_t id) { return id == m.material; }))
            m.faceMaterials.clear();
    }

private:
    uint32_t tinted(uint32_t material, const std::array<uint8_t, 3>& q) {
        auto [it, fresh] = made_.try_emplace({material, q[0], q[1], q[2]}, 0);
        if (fresh) {
            Material tint = scene_.materials[material];
            const Rgb c(q[0] / 255.f, q[1] / 255.f, q[2] / 255.f);
            tint.kd = Rgb(tint.kd) * c;
            tint.baseColor = Rgb(tint.baseColor) * c;
            tint.name += "*vertex colour";
            it->second = static_cast<uint32_t>(scene_.materials.size());
            scene_.materials.push_back(tint);
        }
        return it->second;
    }
    Scene& scene_;
    std::map<std::tuple<uint32_t, uint8_t, uint8_t, uint8_t>, uint32_t> made_;
};

/// Normal maps need a tangent frame: the file's, or one made from the uvs
/// the map reads. A mesh without those uvs keeps its material without the
/// normal map (a warning naming the file): a missing frame is not a failure.
void addTangentFrames(const GltfFile& file, Scene& scene, size_t firstMesh, const Logger& log) {
    std::map<uint32_t, uint32_t> withoutMap;  // material -> its copy without the normal map
    auto plain = [&](uint32_t id) {
        auto [it, fresh] = withoutMap.try_emplace(id, id);
        if (fresh && scene.materials[id].needsTangents()) {
            Material copy = scene.materials[id];
            copy.normalMap = TextureRef{};
            copy.normalTexture = TextureSlot{};
            it->second = static_cast<uint32_t>(scene.materials.size());
            scene.materials.push_back(copy);
        }
        return it->second;
    };
    size_t degenerate = 0;
    for (size_t i = firstMesh; i < scene.meshes.size(); ++i) {
        TriangleMesh& m = scene.meshes[i];
        const Material& mat = scene.materials[m.material];
        if (!mat.needsTangents() || !m.tangents.empty()) continue;
        const int set = mat.normalMap.uvSet;
        size_t bad = 0;
        if (generateTangents(m, set, &bad)) {
            degenerate += bad;
            continue;
        }
        log.warn(file.where() + ": mesh '" + m.name + "' has no TEXCOORD_" + std::to_string(set) + " for material '" +
                 mat.name + "''s normal map: no tangent frame, so the normal map is not used on it");
        m.material = plain(m.material);
        for (uint32_t& id : m.faceMaterials) id = plain(id);
    }
    // Common at a few uv seams of real models (DamagedHelmet has 12): information, not a warning.
    if (degenerate)
        log.info(file.where() + ": " + std::to_string(degenerate) +
                 " vertices of normal-mapped meshes have degenerate texture coordinates; their tangents are arbitrary");
}

}  // namespace

bool isGltfExtension(const std::string& extension) {
    std::string e = extension;
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e == ".gltf" || e == ".glb";
}

ObjStats appendGltf(Scene& scene, const InputFile& model, const Transform& worldFromObject, const LoadOptions& options,
                    const Logger& log, ModelExtras& extras) {
    const GltfFile file = readGltfFile(model, options, log);
    const GltfAccessors accessors(file);
    const tinygltf::Model& m = file.model;
    const std::vector<Placed> placed = placeNodes(file, worldFromObject, log);

    // Counted before anything is made: nodes that share a mesh multiply it.
    size_t planned = 0;
    for (const Placed& p : placed) {
        const int mesh = m.nodes[size_t(p.node)].mesh;
        if (mesh < 0 || size_t(mesh) >= m.meshes.size()) continue;
        for (size_t k = 0; k < m.meshes[size_t(mesh)].primitives.size(); ++k)
            planned += gltfPrimitiveSize(accessors, m.meshes[size_t(mesh)].primitives[k],
                                         "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(k) + "]");
        if (planned > kMaxGltfElements)
            throw Error(ErrorCode::InvalidScene, file.where() + ": its nodes place more than " +
                                                     std::to_string(kMaxGltfElements) +
                                                     " vertices and triangles (a mesh counts once per node that draws it)");
    }

    const uint32_t materialBase = appendGltfMaterials(file, scene, log);
    const uint32_t defaultMaterial = static_cast<uint32_t>(materialBase + m.materials.size());
    Tints tints(scene);
    ObjStats stats;
    size_t dropped = 0;
    const size_t firstMesh = scene.meshes.size();
    for (const Placed& p : placed) {
        const tinygltf::Node& node = m.nodes[size_t(p.node)];
        if (node.mesh < 0 || size_t(node.mesh) >= m.meshes.size()) continue;
        const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
        for (size_t k = 0; k < mesh.primitives.size(); ++k) {
            const tinygltf::Primitive& prim = mesh.primitives[k];
            GltfPrimitive read = readGltfPrimitive(
                accessors, prim, p.world, "meshes[" + std::to_string(node.mesh) + "].primitives[" + std::to_string(k) + "]");
            dropped += read.droppedFaces;
            TriangleMesh& tm = read.mesh;
            if (tm.indices.empty()) continue;
            tm.name = mesh.name.empty() ? file.path.stem().string() : mesh.name;
            if (!node.name.empty() && node.name != tm.name) tm.name = node.name + "/" + tm.name;
            tm.material = prim.material >= 0 && size_t(prim.material) < m.materials.size()
                              ? materialBase + uint32_t(prim.material)
                              : defaultMaterial;
            tints.apply(tm, read.colours);
            stats.triangles += tm.triangleCount();
            for (size_t t = 0; t < tm.triangleCount(); ++t)
                stats.emissiveTriangles += scene.materials[tm.materialOf(t)].isEmissive();
            scene.meshes.push_back(std::move(tm));
        }
    }
    stats.droppedFaces = dropped;
    if (dropped)
        log.warn(file.where() + ": dropped " + std::to_string(dropped) +
                 " triangle(s) on missing vertices or non-finite positions");
    stats.materials = scene.materials.size() - materialBase;
    applyMeshOptions(scene, firstMesh, materialBase, options);
    addTangentFrames(file, scene, firstMesh, log);

    extras.camera = firstCamera(file, placed, log);
    addLights(file, placed, extras, log);
    return stats;
}

}  // namespace penumbra
