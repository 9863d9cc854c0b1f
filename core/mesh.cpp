#include "core/mesh.h"

namespace penumbra {

std::vector<uint32_t> keepUsedVertices(TriangleMesh& m) {
    constexpr uint32_t kUnused = UINT32_MAX;
    std::vector<uint32_t> to(m.positions.size(), kUnused);
    for (uint32_t i : m.indices) to[i] = 0;
    uint32_t next = 0;
    for (uint32_t& t : to)
        if (t != kUnused) t = next++;
    auto keep = [&](auto& values) {
        if (values.size() != to.size()) return;
        for (size_t v = 0; v < to.size(); ++v)
            if (to[v] != kUnused) values[to[v]] = values[v];
        values.resize(next);
    };
    keep(m.positions);
    keep(m.normals);
    keep(m.uvs);
    keep(m.uvs1);
    keep(m.tangents);
    for (uint32_t& i : m.indices) i = to[i];
    return to;
}

}  // namespace penumbra
