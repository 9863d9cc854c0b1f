#include "core/io/obj_faces.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/io/mtl_materials.h"

namespace penumbra {
namespace {

// Ear clipping is cubic in the worst case; bigger polygons are fanned.
constexpr size_t kMaxEarClipCorners = 512;

std::string lineNote(uint32_t line) { return line > 0 ? " (first at line " + std::to_string(line) + ")" : ""; }

}  // namespace

void triangulate(const std::vector<Vec3f>& p, std::vector<std::array<uint32_t, 3>>& out) {
    const size_t n = p.size();
    out.clear();
    if (n == 3) {
        out.push_back({0, 1, 2});
        return;
    }
    Vec3f normal{};  // Newell's method: robust for non-planar and concave polygons
    for (size_t i = 0; i < n; ++i) {
        const Vec3f &a = p[i], &b = p[(i + 1) % n];
        normal += Vec3f{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    auto fan = [&](const std::vector<uint32_t>& v) {
        for (size_t i = 1; i + 1 < v.size(); ++i) out.push_back({v[0], v[i], v[i + 1]});
    };
    if (n == 4) {
        auto faces = [&](uint32_t a, uint32_t b, uint32_t c) {
            return dot(cross(p[b] - p[a], p[c] - p[a]), normal) > 0.f;
        };
        bool splitA = faces(0, 1, 2) && faces(0, 2, 3);  // diagonal 0-2
        bool splitB = faces(0, 1, 3) && faces(1, 2, 3);  // diagonal 1-3
        bool useA = splitA && (!splitB || lengthSquared(p[2] - p[0]) <= lengthSquared(p[3] - p[1]));
        if (useA || !splitB) {
            out.push_back({0, 1, 2});
            out.push_back({0, 2, 3});
        } else {
            out.push_back({0, 1, 3});
            out.push_back({1, 2, 3});
        }
        return;
    }
    std::vector<uint32_t> rest(n);
    for (size_t i = 0; i < n; ++i) rest[i] = static_cast<uint32_t>(i);
    if (lengthSquared(normal) == 0.f || !isFinite(normal) || n > kMaxEarClipCorners) {
        fan(rest);
        return;
    }
    // Project onto the plane that drops the normal's dominant axis, oriented so the polygon is counter-clockwise.
    int k = maxDimension(abs(normal));
    int u = (k + 1) % 3, w = (k + 2) % 3;
    if (normal[k] < 0.f) std::swap(u, w);
    auto cross2 = [&](uint32_t a, uint32_t b, uint32_t c) {
        return (p[b][u] - p[a][u]) * (p[c][w] - p[a][w]) - (p[b][w] - p[a][w]) * (p[c][u] - p[a][u]);
    };
    while (rest.size() > 3) {
        const size_t m = rest.size();
        bool clipped = false;
        for (size_t i = 0; i < m && !clipped; ++i) {
            uint32_t a = rest[(i + m - 1) % m], b = rest[i], c = rest[(i + 1) % m];
            if (!(cross2(a, b, c) > 0.f)) continue;  // reflex or collinear corner
            bool inside = false;
            for (size_t j = 0; j < m && !inside; ++j) {
                uint32_t q = rest[j];
                if (q == a || q == b || q == c || p[q] == p[a] || p[q] == p[b] || p[q] == p[c]) continue;
                inside = cross2(a, b, q) >= 0.f && cross2(b, c, q) >= 0.f && cross2(c, a, q) >= 0.f;
            }
            if (inside) continue;
            out.push_back({a, b, c});
            rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
            clipped = true;
        }
        if (!clipped) {
            fan(rest);
            return;
        }
    }
    out.push_back({rest[0], rest[1], rest[2]});
}

size_t ObjMeshBuilder::VertexKeyHash::operator()(const VertexKey& k) const {
    uint64_t h = static_cast<uint32_t>(k.v);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.vt);
    h = h * 0x9E3779B97F4A7C15ull ^ static_cast<uint32_t>(k.vn);
    return static_cast<size_t>(h ^ (h >> 29));
}

ObjMeshBuilder::ObjMeshBuilder(Scene& scene, const PreparedObj& prep, const std::vector<float>& vertices,
                               const std::vector<float>& normals, const std::vector<float>& texcoords,
                               const Transform& worldFromObject, size_t totalFaces, MaterialConverter& materials,
                               uint32_t materialBase, size_t materialCount)
    : scene_(scene),
      prep_(prep),
      texcoords_(texcoords),
      materials_(materials),
      materialBase_(materialBase),
      materialCount_(materialCount),
      // A mirroring placement turns counter-clockwise into clockwise; swap to keep the front side.
      flipWinding_(worldFromObject.determinant() < 0.f),
      haveLines_(totalFaces == prep.faceLines.size()),
      badFaces_(prep.invalidFaces),
      firstBadLine_(prep.firstInvalidLine) {
    // Vertex data in world space, validated once.
    const size_t nv = vertices.size() / 3, nn = normals.size() / 3;
    pos_.resize(nv);
    posOk_.resize(nv);
    for (size_t i = 0; i < nv; ++i) {
        Vec3f p{vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]};
        bool good = isFinite(p) && !(i < prep.badVertex.size() && prep.badVertex[i]);
        pos_[i] = good ? worldFromObject.applyPoint(p) : Vec3f{};
        posOk_[i] = good && isFinite(pos_[i]);
    }
    nrm_.resize(nn);
    for (size_t i = 0; i < nn; ++i) {
        Vec3f n{normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]};
        n = normalize(worldFromObject.applyNormal(n));
        nrm_[i] = isFinite(n) ? n : Vec3f{};
    }
}

void ObjMeshBuilder::noteLine(uint32_t& first, size_t face) const {
    if (haveLines_ && (first == 0 || prep_.faceLines[face] < first)) first = prep_.faceLines[face];
}

void ObjMeshBuilder::beginShape(std::string name) {
    mesh_ = TriangleMesh();
    mesh_.name = std::move(name);
    vertexOf_.clear();
    anyNormals_ = anyUvs_ = false;
    faceMats_.clear();
}

bool ObjMeshBuilder::positionsValid(const ObjCorner* c, size_t n) const {
    bool good = n >= 3;
    for (size_t i = 0; i < n && good; ++i) {
        int vi = c[i].vertex_index;
        good = vi >= 0 && static_cast<size_t>(vi) < pos_.size() && posOk_[vi];
    }
    return good;
}

ObjMeshBuilder::AttributeUse ObjMeshBuilder::attributesOf(const ObjCorner* c, size_t n, size_t faceNo) {
    const size_t nn = nrm_.size(), nt = texcoords_.size() / 2;
    // Normals and UVs are all-or-nothing per face.
    bool useN = true, useUv = true, badN = false, badUv = false;
    for (size_t i = 0; i < n; ++i) {
        int vn = c[i].normal_index, vt = c[i].texcoord_index;
        if (vn < 0) useN = false;
        else if (static_cast<size_t>(vn) >= nn) badN = true;
        else if (lengthSquared(nrm_[vn]) == 0.f) useN = false;
        if (vt < 0) useUv = false;
        else if (static_cast<size_t>(vt) >= nt) badUv = true;
        else if (!std::isfinite(texcoords_[2 * vt]) || !std::isfinite(texcoords_[2 * vt + 1]))
            useUv = false;
    }
    if (badN) {
        ++badNormalFaces_;
        noteLine(firstBadNormalLine_, faceNo);
    }
    if (badUv) {
        ++badUvFaces_;
        noteLine(firstBadUvLine_, faceNo);
    }
    return {useN && !badN, useUv && !badUv};
}

void ObjMeshBuilder::addFace(const ObjCorner* c, size_t n, int mid) {
    const size_t faceNo = faceNo_++;
    if (haveLines_ && nextBig_ < prep_.bigFaces.size() && prep_.bigFaces[nextBig_].face == faceNo) {
        c = prep_.bigFaces[nextBig_].corners.data();
        n = prep_.bigFaces[nextBig_].corners.size();
        ++nextBig_;
    }
    if (!positionsValid(c, n)) {
        ++badFaces_;
        noteLine(firstBadLine_, faceNo);
        return;
    }
    const AttributeUse use = attributesOf(c, n, faceNo);
    const uint32_t material = mid >= 0 && static_cast<size_t>(mid) < materialCount_
                                  ? materialBase_ + static_cast<uint32_t>(mid)
                                  : materials_.defaultMaterial();
    addTriangles(c, n, use, material);
}

void ObjMeshBuilder::addTriangles(const ObjCorner* c, size_t n, AttributeUse use, uint32_t material) {
    poly_.resize(n);
    for (size_t i = 0; i < n; ++i) poly_[i] = pos_[c[i].vertex_index];
    triangulate(poly_, tris_);
    for (auto t : tris_) {
        const Vec3f &p0 = poly_[t[0]], &p1 = poly_[t[1]], &p2 = poly_[t[2]];
        if (!(lengthSquared(cross(p1 - p0, p2 - p0)) > 0.f)) {
            ++degenerate_;  // also keeps zero-area emitters out of the light set
            continue;
        }
        if (flipWinding_) std::swap(t[1], t[2]);
        for (uint32_t corner : t) {
            const ObjCorner& ix = c[corner];
            VertexKey key{ix.vertex_index, use.uvs ? ix.texcoord_index : -1, use.normals ? ix.normal_index : -1};
            auto [it, inserted] = vertexOf_.try_emplace(key, static_cast<uint32_t>(mesh_.positions.size()));
            if (inserted) {
                mesh_.positions.push_back(pos_[key.v]);
                mesh_.normals.push_back(key.vn >= 0 ? nrm_[key.vn] : Vec3f{});
                mesh_.uvs.push_back(key.vt >= 0 ? Vec2f{texcoords_[2 * key.vt], texcoords_[2 * key.vt + 1]} : Vec2f{});
                anyNormals_ = anyNormals_ || key.vn >= 0;
                anyUvs_ = anyUvs_ || key.vt >= 0;
            }
            mesh_.indices.push_back(it->second);
        }
        faceMats_.push_back(material);
        if (scene_.materials[material].isEmissive()) ++stats_.emissiveTriangles;
    }
}

void ObjMeshBuilder::endShape() {
    if (mesh_.indices.empty()) return;
    if (!anyNormals_) mesh_.normals.clear();
    if (!anyUvs_) mesh_.uvs.clear();
    mesh_.material = faceMats_[0];
    if (!std::all_of(faceMats_.begin(), faceMats_.end(), [&](uint32_t m) { return m == faceMats_[0]; }))
        mesh_.faceMaterials = std::move(faceMats_);
    stats_.triangles += mesh_.triangleCount();
    scene_.meshes.push_back(std::move(mesh_));
}

ObjStats ObjMeshBuilder::finish(const std::string& file, const LoadOptions& options, const Logger& log) {
    if (badFaces_ > 0) {
        std::string what = std::to_string(badFaces_) +
                           " face(s) with invalid vertex indices, fewer than 3 vertices or non-finite positions" +
                           lineNote(firstBadLine_);
        if (options.strict) throw Error(ErrorCode::ParseError, file + ": " + what);
        log.warn(file + ": dropped " + what);
    }
    if (badNormalFaces_ > 0)
        log.warn(file + ": " + std::to_string(badNormalFaces_) +
                 " face(s) with invalid normal indices use the geometric normal" +
                 lineNote(firstBadNormalLine_));
    if (badUvFaces_ > 0)
        log.warn(file + ": " + std::to_string(badUvFaces_) +
                 " face(s) with invalid texture coordinate indices have no UVs" +
                 lineNote(firstBadUvLine_));
    if (degenerate_ > 0)
        log.info(file + ": skipped " + std::to_string(degenerate_) + " degenerate (zero-area) triangle(s)");
    stats_.droppedFaces = badFaces_ + degenerate_;
    return stats_;
}

}  // namespace penumbra
