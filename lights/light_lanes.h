// Shading points and light samples of a batch's lanes as arrays (structure of
// arrays): what Light::mayReachLanes and Light::sampleLanes take and give. A
// step written as one loop over such arrays runs for all lanes at once (the
// compiler vectorises it), where the same step taken lane by lane through
// Light::sample waits on each lane's square root and divisions in turn.
#pragma once

#include <cstdint>
#include <optional>

#include "core/math.h"
#include "lights/light.h"

namespace penumbra {

struct LanePoints {
    static constexpr int kWidth = 16;
    alignas(64) float px[kWidth], py[kWidth], pz[kWidth];  // shading point
    alignas(64) float nx[kWidth], ny[kWidth], nz[kWidth];  // unit geometric normal on the side samples must reach

    Vec3f p(int l) const { return Vec3f{px[l], py[l], pz[l]}; }
    Vec3f n(int l) const { return Vec3f{nx[l], ny[l], nz[l]}; }
    void set(int l, const Vec3f& p, const Vec3f& n) {
        px[l] = p.x;
        py[l] = p.y;
        pz[l] = p.z;
        nx[l] = n.x;
        ny[l] = n.y;
        nz[l] = n.z;
    }
};

/// One light sample per lane; ok[l] = 0 where the lane has none (sample()
/// returned nothing, or none was asked for), and its other entries are then
/// not to be read.
struct LightLanes {
    static constexpr int kWidth = LanePoints::kWidth;
    alignas(64) float wx[kWidth], wy[kWidth], wz[kWidth];  // unit direction towards the light
    alignas(64) float qx[kWidth], qy[kWidth], qz[kWidth];  // the sampled point on the light
    alignas(64) float distance[kWidth], pdf[kWidth];
    alignas(64) float Lr[kWidth], Lg[kWidth], Lb[kWidth];
    alignas(64) int32_t ok[kWidth];
    bool delta = false;  // the samples are a point or directional light's (LightSample::delta)

    void set(int l, const std::optional<LightSample>& s) {
        ok[l] = s ? 1 : 0;
        if (!s) return;
        wx[l] = s->wi.x;
        wy[l] = s->wi.y;
        wz[l] = s->wi.z;
        qx[l] = s->point.x;
        qy[l] = s->point.y;
        qz[l] = s->point.z;
        distance[l] = s->distance;
        pdf[l] = s->pdf;
        Lr[l] = s->L.r;
        Lg[l] = s->L.g;
        Lb[l] = s->L.b;
    }
    /// The sample of lane l (ok[l] set).
    LightSample get(int l) const {
        return LightSample{Rgb{Lr[l], Lg[l], Lb[l]}, Vec3f{wx[l], wy[l], wz[l]}, Vec3f{qx[l], qy[l], qz[l]},
                           distance[l], pdf[l], delta};
    }
};

}  // namespace penumbra
