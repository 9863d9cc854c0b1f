#include "core/io/gltf_meshes.h"

#include <cmath>

namespace penumbra {
namespace {

int attribute(const tinygltf::Primitive& p, const char* name) {
    const auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

bool drawsTriangles(const tinygltf::Primitive& p) {
    return p.mode == -1 || p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           p.mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

/// Triangle corner lists from a list, strip or fan of vertex indices.
std::vector<uint32_t> triangles(const std::vector<uint32_t>& v, int mode) {
    std::vector<uint32_t> out;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < v.size(); ++i)  // every other triangle turned, so all face the same way
            out.insert(out.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (size_t i = 1; i + 1 < v.size(); ++i) out.insert(out.end(), {v[i], v[i + 1], v[0]});
    } else {
        out.assign(v.begin(), v.begin() + (v.size() / 3) * 3);
    }
    return out;
}

}  // namespace

size_t gltfPrimitiveSize(const GltfAccessors& accessors, const tinygltf::Primitive& p, const std::string& where) {
    const int position = attribute(p, "POSITION");
    if (!drawsTriangles(p) || position < 0) return 0;
    const size_t vertices = accessors.count(position, where + " POSITION");
    return vertices + (p.indices >= 0 ? accessors.count(p.indices, where + " indices") : vertices) / 3 + 1;
}

GltfPrimitive readGltfPrimitive(const GltfAccessors& accessors, const tinygltf::Primitive& p,
                                const Transform& worldFromObject, const std::string& where) {
    GltfPrimitive out;
    const int position = attribute(p, "POSITION");
    if (!drawsTriangles(p) || position < 0) return out;
    TriangleMesh& m = out.mesh;
    const Transform& t = worldFromObject;
    const bool mirrored = t.determinant() < 0.f;

    const std::vector<float> pos = accessors.floats(position, 3, where + " POSITION");
    const size_t nv = pos.size() / 3;
    m.positions.reserve(nv);
    for (size_t i = 0; i < nv; ++i) m.positions.push_back(t.applyPoint({pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]}));
    auto sameCount = [&](int accessor, const char* name) {
        if (accessor < 0) return false;
        if (accessors.count(accessor, where + " " + name) == nv) return true;
        accessors.fail(where + " " + name + " has " + std::to_string(accessors.count(accessor, name)) +
                       " elements where POSITION has " + std::to_string(nv));
    };
    const int normal = attribute(p, "NORMAL");
    if (sameCount(normal, "NORMAL")) {
        const std::vector<float> n = accessors.floats(normal, 3, where + " NORMAL");
        m.normals.reserve(nv);
        for (size_t i = 0; i < nv; ++i) m.normals.push_back(normalize(t.applyNormal({n[3 * i], n[3 * i + 1], n[3 * i + 2]})));
        // Tangents count only beside the file's normals (the specification's rule).
        const int tangent = attribute(p, "TANGENT");
        if (sameCount(tangent, "TANGENT")) {
            const std::vector<float> tg = accessors.floats(tangent, 4, where + " TANGENT");
            m.tangents.reserve(nv);
            for (size_t i = 0; i < nv; ++i)
                m.tangents.push_back({normalize(t.applyVector({tg[4 * i], tg[4 * i + 1], tg[4 * i + 2]})),
                                      (tg[4 * i + 3] < 0.f ? -1.f : 1.f) * (mirrored ? -1.f : 1.f)});
        }
    }
    for (int set = 0; set < 2; ++set) {
        const std::string name = "TEXCOORD_" + std::to_string(set);
        const int uv = attribute(p, name.c_str());
        if (!sameCount(uv, name.c_str())) continue;
        const std::vector<float> st = accessors.floats(uv, 2, where + " " + name);
        std::vector<Vec2f>& to = set == 0 ? m.uvs : m.uvs1;
        to.reserve(nv);
        for (size_t i = 0; i < nv; ++i) to.push_back({st[2 * i], 1.f - st[2 * i + 1]});  // glTF's v points down
    }
    const int colour = attribute(p, "COLOR_0");
    if (sameCount(colour, "COLOR_0")) {
        const int n = accessors.components(colour, where + " COLOR_0") == 4 ? 4 : 3;
        const std::vector<float> c = accessors.floats(colour, n, where + " COLOR_0");
        out.colours.reserve(nv);
        for (size_t i = 0; i < nv; ++i) out.colours.push_back({c[n * i], c[n * i + 1], c[n * i + 2]});
    }

    std::vector<uint32_t> corners;
    if (p.indices >= 0) {
        corners = accessors.indices(p.indices, where + " indices");
    } else {
        corners.resize(nv);
        for (size_t i = 0; i < nv; ++i) corners[i] = uint32_t(i);
    }
    corners = triangles(corners, p.mode);
    bool anyNonFinite = false;
    for (size_t c = 0; c + 3 <= corners.size(); c += 3) {
        const uint32_t* tri = &corners[c];
        if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv || !isFinite(m.positions[tri[0]]) ||
            !isFinite(m.positions[tri[1]]) || !isFinite(m.positions[tri[2]])) {
            ++out.droppedFaces;
            continue;
        }
        if (mirrored) m.indices.insert(m.indices.end(), {tri[0], tri[2], tri[1]});
        else m.indices.insert(m.indices.end(), tri, tri + 3);
    }
    for (const Vec3f& q : m.positions) anyNonFinite = anyNonFinite || !isFinite(q);
    if (anyNonFinite && !m.indices.empty()) {
        const std::vector<uint32_t> to = keepUsedVertices(m);  // a loaded mesh holds finite positions only
        if (!out.colours.empty()) {
            size_t kept = 0;
            for (size_t v = 0; v < to.size(); ++v)
                if (to[v] != UINT32_MAX) out.colours[kept++] = out.colours[v];
            out.colours.resize(kept);
        }
    }
    return out;
}

}  // namespace penumbra
