#include "ray_sets.h"

#include <cmath>
#include <optional>

#include "core/hash.h"
#include "core/multi_jitter.h"
#include "core/parallel.h"
#include "core/sampling.h"
#include "shading/integrator.h"

namespace penumbra::bench {
namespace {

constexpr int kBlock = 4;  // camera rays come in kBlock x kBlock pixel blocks
constexpr size_t kChunk = 1024;

float unitHash(uint64_t seed, uint64_t a, uint64_t b) { return toUnitFloat(hashValues({seed, a, b})); }

}  // namespace

const char* rayKindName(RayKind k) {
    switch (k) {
        case RayKind::Camera: return "camera";
        case RayKind::Shadow: return "shadow";
        case RayKind::Incoherent: return "incoherent";
    }
    return "?";
}

std::vector<size_t> spreadSubset(size_t n, size_t count) {
    std::vector<size_t> idx;
    if (n == 0 || count == 0) return idx;
    const size_t stride = (n + count - 1) / count;
    for (size_t i = 0; i < n; i += stride) idx.push_back(i);
    return idx;
}

RaySets makeRaySets(const Accelerator& accel, const LightSet& lights, const CameraDesc& cameraDesc, size_t cameraRays,
                    uint64_t seed, int threads) {
    RaySets sets;
    int side = int(std::ceil(std::sqrt(double(cameraRays))));
    side = (side + kBlock - 1) / kBlock * kBlock;
    sets.imageSide = side;
    const Camera camera(cameraDesc, side, side);
    const int blocksX = side / kBlock;

    auto& cam = sets.rays[size_t(RayKind::Camera)];
    cam.reserve(cameraRays);
    std::vector<uint64_t> pixelOf;  // full-image pixel index of each camera ray
    pixelOf.reserve(cameraRays);
    for (size_t i = 0; i < cameraRays; ++i) {
        const size_t block = i / (kBlock * kBlock), lane = i % (kBlock * kBlock);
        const int x = int(block % size_t(blocksX)) * kBlock + int(lane % kBlock);
        const int y = int(block / size_t(blocksX)) * kBlock + int(lane / kBlock);
        const uint64_t pixel = uint64_t(y) * uint64_t(side) + uint64_t(x);
        cam.push_back(camera.generateRay(float(x) + unitHash(seed, pixel, 0), float(y) + unitHash(seed, pixel, 1),
                                         Vec2f{0.5f, 0.5f}));
        pixelOf.push_back(pixel);
    }

    std::vector<std::optional<Hit>> hits(cam.size());
    parallelFor((cam.size() + kChunk - 1) / kChunk, threads, [&](size_t c) {
        const size_t end = std::min(cam.size(), (c + 1) * kChunk);
        for (size_t i = c * kChunk; i < end; ++i) hits[i] = accel.intersect(cam[i]);
    });

    auto& shadow = sets.rays[size_t(RayKind::Shadow)];
    auto& incoherent = sets.rays[size_t(RayKind::Incoherent)];
    for (size_t i = 0; i < cam.size(); ++i) {
        if (!hits[i]) continue;
        const Hit& h = *hits[i];
        const Ray& ray = cam[i];
        ++sets.cameraHits;
        // Shade from the side the camera sees, as the integrator does.
        const bool front = dot(ray.d, h.ng) < 0.f;
        const Vec3f ng = front ? h.ng : -h.ng;
        const Vec3f ns = front ? h.ns : -h.ns;

        const size_t block = i / (kBlock * kBlock);
        const auto lane = static_cast<uint32_t>(i % (kBlock * kBlock));
        for (size_t j = 0; j < lights.size(); ++j) {
            const uint32_t pattern = mjPattern(seed, block, j, kFirstLightDimension);
            const auto ls = lights[j].sample(h.p, multiJitter2D(lane, kBlock * kBlock, pattern));
            if (!ls || dot(ls->wi, ng) <= 0.f) continue;
            shadow.push_back(std::isinf(ls->distance) ? spawnRay(h.p, ng, ls->wi) : spawnRayTo(h.p, ng, ls->point));
        }

        if (sets.cameraHits % 2 == 1) {
            Vec3f r = reflect(ray.d, ns);
            if (dot(r, ng) <= 0.f) r = reflect(ray.d, ng);
            incoherent.push_back(spawnRay(h.p, ng, normalize(r)));
            ++sets.mirrorRays;
        } else {
            Vec3f d = squareToUniformSphere(Vec2f{unitHash(seed, pixelOf[i], 2), unitHash(seed, pixelOf[i], 3)});
            if (dot(d, ng) < 0.f) d = -d;
            incoherent.push_back(spawnRay(h.p, ng, d));
            ++sets.randomRays;
        }
    }
    return sets;
}

}  // namespace penumbra::bench
