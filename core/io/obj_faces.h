// OBJ faces to triangle meshes: each face validated (indices, positions,
// normals, UVs all-or-nothing per face), triangulated (ear clipping keeps
// concave polygons), de-indexed into per-shape TriangleMeshes; what is dropped
// is counted and reported once per file with the first line.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/io/load_options.h"
#include "core/io/obj_prepass.h"
#include "core/log.h"
#include "core/mesh.h"
#include "core/scene.h"
#include "core/transform.h"

namespace penumbra {

class MaterialConverter;

/// What appendObj added, for callers that report it.
struct ObjStats {
    size_t triangles = 0;
    size_t emissiveTriangles = 0;
    size_t droppedFaces = 0;   // bad vertex indices / non-finite positions / degenerate
    size_t materials = 0;
};

/// Splits a polygon into triangles (corner indices), keeping its winding.
/// Quads take the shorter diagonal when both are valid (like tinyobjloader);
/// bigger polygons are ear-clipped in their best-fit plane, so concave ones
/// keep their shape; a polygon without ears (self-intersecting, degenerate) is fanned.
void triangulate(const std::vector<Vec3f>& p, std::vector<std::array<uint32_t, 3>>& out);

/// Turns the faces of one OBJ, shape by shape, into TriangleMeshes of `scene`.
class ObjMeshBuilder {
public:
    /// `vertices`, `normals`, `texcoords`: the file's flat arrays (3, 3 and 2 floats each).
    ObjMeshBuilder(Scene& scene, const PreparedObj& prep, const std::vector<float>& vertices,
                   const std::vector<float>& normals, const std::vector<float>& texcoords,
                   const Transform& worldFromObject, size_t totalFaces, MaterialConverter& materials,
                   uint32_t materialBase, size_t materialCount);

    void beginShape(std::string name);
    /// The next face of the file (a big face's corners come from the pre-pass);
    /// `mtl` is the face's index among the file's materials, -1 for none.
    void addFace(const ObjCorner* corners, size_t n, int mtl);
    void endShape();

    /// Logs what was dropped (an error in strict mode) and returns the counts.
    ObjStats finish(const std::string& file, const LoadOptions& options, const Logger& log);

private:
    struct VertexKey {
        int v, vt, vn;
        bool operator==(const VertexKey&) const = default;
    };
    struct VertexKeyHash {
        size_t operator()(const VertexKey& k) const;
    };

    struct AttributeUse {
        bool normals, uvs;
    };
    void noteLine(uint32_t& first, size_t face) const;
    /// At least 3 corners, each a valid index of a finite position.
    bool positionsValid(const ObjCorner* c, size_t n) const;
    /// Whether the face's normals and UVs are used (counting invalid indices).
    AttributeUse attributesOf(const ObjCorner* c, size_t n, size_t faceNo);
    /// Triangulates a valid face and de-indexes its corners into the mesh being built.
    void addTriangles(const ObjCorner* c, size_t n, AttributeUse use, uint32_t material);

    Scene& scene_;
    const PreparedObj& prep_;
    const std::vector<float>& texcoords_;
    MaterialConverter& materials_;
    uint32_t materialBase_;
    size_t materialCount_;
    std::vector<Vec3f> pos_;
    std::vector<uint8_t> posOk_;
    std::vector<Vec3f> nrm_;
    bool flipWinding_;
    bool haveLines_;

    // The shape being built.
    TriangleMesh mesh_;
    std::unordered_map<VertexKey, uint32_t, VertexKeyHash> vertexOf_;
    bool anyNormals_ = false, anyUvs_ = false;
    std::vector<uint32_t> faceMats_;

    size_t faceNo_ = 0, nextBig_ = 0;
    std::vector<Vec3f> poly_;
    std::vector<std::array<uint32_t, 3>> tris_;
    ObjStats stats_;
    size_t badFaces_, badNormalFaces_ = 0, badUvFaces_ = 0, degenerate_ = 0;
    uint32_t firstBadLine_, firstBadNormalLine_ = 0, firstBadUvLine_ = 0;
};

}  // namespace penumbra
