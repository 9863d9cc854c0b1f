#include "accel/accelerator.h"

#include <cassert>

#include "core/error.h"

namespace penumbra {

void Accelerator::completeBatch(const Ray* rays, const std::optional<PrimIntersection>* thin, std::optional<Hit>* out,
                                size_t n) const {
    // The hits on the mesh of the batch's first mesh hit (instances aside), and the others one by one.
    constexpr size_t kMax = 16;
    // Fewer lanes than this on the mesh go one by one: the lanes' pass has a
    // fixed cost (16 lanes gathered and computed); at 2 or 4 Figure 24.6 timed the same.
    constexpr int kFewestLanes = 4;
    assert(n <= kMax);
    uint32_t tri[kMax], lane[kMax];
    float u[kMax], v[kMax];
    int k = 0;
    uint32_t mesh = 0;
    for (size_t i = 0; i < n; ++i) {
        const std::optional<PrimIntersection>& h = thin[i];
        if (h && h->ref.kind == ShapeKind::Mesh && (k == 0 || h->ref.object == mesh)) {
            mesh = h->ref.object;
            tri[k] = h->ref.prim;
            u[k] = h->u;
            v[k] = h->v;
            lane[k++] = uint32_t(i);
        } else {
            completeThin(rays[i], h, out[i]);
        }
    }
    if (k < kFewestLanes) {
        for (int j = 0; j < k; ++j) completeThin(rays[lane[j]], thin[lane[j]], out[lane[j]]);
        return;
    }
    Hit* hits[kMax];
    for (int j = 0; j < k; ++j) hits[j] = &out[lane[j]].emplace();
    completeTriangleHitLanes(scene_.meshes[mesh], k, tri, u, v, hits);
    for (int j = 0; j < k; ++j) {
        hits[j]->t = thin[lane[j]]->t;
        hits[j]->ref = thin[lane[j]]->ref;
    }
}

std::unique_ptr<Accelerator> makeAccelerator(AcceleratorKind kind, const Scene& scene, BuildQuality quality,
                                             std::shared_ptr<const TextureCache> textures) {
    switch (kind) {
        case AcceleratorKind::Embree: return makeEmbreeAccelerator(scene, quality, std::move(textures));
        case AcceleratorKind::Naive: return makeNaiveAccelerator(scene, std::move(textures));
    }
    throw Error(ErrorCode::InvalidArgument, "accelerator " + std::to_string(int(kind)) + " is not an AcceleratorKind");
}

}  // namespace penumbra
