// Indexed triangle mesh. Its position and index arrays are handed to Embree
// as shared buffers (no second copy), which is why positions are padded.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace penumbra {

/// Vertex positions with one hidden padding element after the last vertex:
/// Embree loads vertices 16 bytes at a time, so the 12-byte last vertex needs
/// 4 readable bytes after it. size() counts real vertices only.
class PositionBuffer {
public:
    PositionBuffer() : v_(1) {}
    size_t size() const { return v_.size() - 1; }
    bool empty() const { return size() == 0; }
    void reserve(size_t n) { v_.reserve(n + 1); }
    void resize(size_t n) { v_.resize(n + 1); v_.back() = Vec3f{}; }
    void push_back(const Vec3f& p) { v_.back() = p; v_.emplace_back(); }
    void clear() { v_.assign(1, Vec3f{}); }
    Vec3f& operator[](size_t i) { return v_[i]; }
    const Vec3f& operator[](size_t i) const { return v_[i]; }
    const Vec3f* data() const { return v_.data(); }
    Vec3f* data() { return v_.data(); }
    const Vec3f* begin() const { return v_.data(); }
    const Vec3f* end() const { return v_.data() + size(); }
    /// Bytes allocated (for memory statistics).
    size_t capacityBytes() const { return v_.capacity() * sizeof(Vec3f); }

private:
    std::vector<Vec3f> v_;
};

/// A vertex's tangent, beside its normal: `direction` follows +u of the uv
/// set the normal map reads, and the bitangent (following +v, up the image) is
/// sign * cross(normal, direction): glTF's TANGENT attribute (xyz, w).
struct Tangent {
    Vec3f direction;
    float sign = 1.f;
};

struct TriangleMesh {
    std::string name;
    PositionBuffer positions;
    std::vector<uint32_t> indices;        // 3 per triangle, counter-clockwise = front
    std::vector<Vec3f> normals;           // optional, one per vertex (smooth shading)
    std::vector<Vec2f> uvs;               // optional, one per vertex; v points up the image (OBJ's convention)
    std::vector<Vec2f> uvs1;              // optional second set (glTF TEXCOORD_1), the same convention
    std::vector<Tangent> tangents;        // optional, one per vertex (normal maps; core/mesh_tangents.h)
    std::vector<uint32_t> faceMaterials;  // optional, one per triangle; else `material`
    uint32_t material = 0;

    size_t triangleCount() const { return indices.size() / 3; }
    uint32_t materialOf(size_t tri) const { return faceMaterials.empty() ? material : faceMaterials[tri]; }
    void vertices(size_t tri, Vec3f& p0, Vec3f& p1, Vec3f& p2) const {
        p0 = positions[indices[3 * tri]];
        p1 = positions[indices[3 * tri + 1]];
        p2 = positions[indices[3 * tri + 2]];
    }
};

/// Keeps the vertices that triangles use (positions and every per-vertex
/// array), in their order, and renumbers the indices (every index must be
/// below positions.size()). Returns each old vertex's new index, UINT32_MAX
/// for those dropped, so a caller can compact arrays of its own alike.
std::vector<uint32_t> keepUsedVertices(TriangleMesh& m);

}  // namespace penumbra
