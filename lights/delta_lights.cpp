#include "lights/delta_lights.h"

#include "core/lane_clones.h"
#include "lights/light_lanes.h"

namespace penumbra {

std::optional<LightSample> PointLightSource::sample(const Vec3f& p, Vec2f) const {
    Vec3f d = light_.position - p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f)) return std::nullopt;
    float dist = std::sqrt(dist2);
    // Inverse-square falloff: irradiance I cos / d^2; the cosine is the integrator's.
    return LightSample{light_.intensity / dist2, d / dist, light_.position, dist, 1.f, true};
}

// sample()'s operations in its order (a Vec3f divided by a float multiplies by
// the reciprocal), so that every lane holds the very values sample() returns.
void PointLightSource::sampleLanes(const LanePoints& at, const float*, const float*, const int32_t* want, int n,
                                   LightLanes& out) const {
    pointLanes(at, want, n, out);
}

PENUMBRA_LANE_CLONES void PointLightSource::pointLanes(const LanePoints& at, const int32_t* want, int n,
                                                       LightLanes& out) const {
    out.delta = true;
    const Rgb I = light_.intensity;
    // The points copied first: the loop below, reading them where it writes
    // `out` (which the compiler could not tell apart), stayed scalar. Every
    // lane is set, those from n on one unit from the light and not wanted, so
    // that the loop runs the full width: a batch of fewer than 16 lanes took
    // its last ones one at a time.
    constexpr int W = LightLanes::kWidth;
    alignas(64) float px[W], py[W], pz[W];
    alignas(64) int32_t wanted[W];
    const Vec3f q = light_.position;
    for (int l = 0; l < W; ++l) {
        const bool in = l < n;
        px[l] = in ? at.px[l] : q.x + 1.f;
        py[l] = in ? at.py[l] : q.y;
        pz[l] = in ? at.pz[l] : q.z;
        wanted[l] = in ? want[l] : 0;
    }
    for (int l = 0; l < W; ++l) {
        const float dx = q.x - px[l], dy = q.y - py[l], dz = q.z - pz[l];
        const float dist2 = dx * dx + dy * dy + dz * dz;
        const float dist = std::sqrt(dist2);
        const float inv = 1.f / dist, invDist2 = 1.f / dist2;
        out.wx[l] = dx * inv;
        out.wy[l] = dy * inv;
        out.wz[l] = dz * inv;
        out.qx[l] = q.x;
        out.qy[l] = q.y;
        out.qz[l] = q.z;
        out.distance[l] = dist;
        out.pdf[l] = 1.f;
        out.Lr[l] = I.r * invDist2;
        out.Lg[l] = I.g * invDist2;
        out.Lb[l] = I.b * invDist2;
        out.ok[l] = int32_t(wanted[l] != 0) & int32_t(dist2 > 0.f);
    }
}

DirectionalLightSource::DirectionalLightSource(const DirectionalLight& l, float sceneRadius)
    : light_(l), toLight_(-normalize(l.direction)), radius_(sceneRadius) {}

std::optional<LightSample> DirectionalLightSource::sample(const Vec3f& p, Vec2f) const {
    if (!(lengthSquared(toLight_) > 0.f)) return std::nullopt;
    return LightSample{light_.irradiance, toLight_, p, kInfinity, 1.f, true};
}

}  // namespace penumbra
