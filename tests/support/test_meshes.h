// Closed meshes the accelerator and geometry tests build: an icosphere and a
// cube of triangles, both counter-clockwise seen from outside.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace penumbra::test {

// Icosahedron subdivided `levels` times, projected onto a sphere; closed,
// counter-clockwise seen from outside, every edge shared by two triangles.
inline TriangleMesh makeIcosphere(const Vec3f& center, float radius, int levels) {
    const float g = (1.f + std::sqrt(5.f)) / 2.f;
    std::vector<Vec3f> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    for (auto& p : v) p = normalize(p);
    std::vector<uint32_t> f = {0, 11, 5, 0, 5,  1,  0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11,
                               4, 11, 10, 2, 10, 7,  6, 7, 1, 8, 3, 9, 4,  3, 4,  2, 3, 2, 6, 3,
                               6, 8,  3, 8, 9,  4,  9, 5, 2, 4, 11, 6, 2, 10, 8,  6, 7, 9, 8, 1};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize(v[a] + v[b]));
            return mid[key] = static_cast<uint32_t>(v.size() - 1);
        };
        std::vector<uint32_t> nf;
        for (size_t t = 0; t < f.size(); t += 3) {
            uint32_t a = f[t], b = f[t + 1], c = f[t + 2];
            uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            nf.insert(nf.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = std::move(nf);
    }
    TriangleMesh m;
    m.name = "icosphere";
    for (const auto& p : v) m.positions.push_back(center + radius * p);
    // Orient every face outwards (the table above is not trusted blindly).
    for (size_t t = 0; t < f.size(); t += 3) {
        const Vec3f &a = v[f[t]], &b = v[f[t + 1]], &c = v[f[t + 2]];
        if (dot(cross(b - a, c - a), a + b + c) < 0.f) std::swap(f[t + 1], f[t + 2]);
    }
    m.indices = std::move(f);
    return m;
}

// Axis-aligned cube [lo, hi] as 12 triangles (each face split along a diagonal).
inline TriangleMesh makeTriangleCube(const Vec3f& lo, const Vec3f& hi) {
    TriangleMesh m;
    m.name = "cube";
    for (int i = 0; i < 8; ++i) m.positions.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    m.indices = {0, 2, 3, 0, 3, 1,  // -z
                 4, 5, 7, 4, 7, 6,  // +z
                 0, 4, 6, 0, 6, 2,  // -x
                 1, 3, 7, 1, 7, 5,  // +x
                 0, 1, 5, 0, 5, 4,  // -y
                 2, 6, 7, 2, 7, 3};  // +y
    return m;
}

}  // namespace penumbra::test
