#include "lights/light_lanes.h"

namespace penumbra {

void Light::mayReachLanes(const LanePoints& at, int n, int32_t* reach) const {
    for (int l = 0; l < n; ++l) reach[l] = mayReach(at.p(l), at.n(l)) ? 1 : 0;
}

void Light::sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                        LightLanes& out) const {
    out.delta = isDelta();
    for (int l = 0; l < n; ++l) out.set(l, want[l] ? sample(at.p(l), Vec2f{ux[l], uy[l]}) : std::nullopt);
}

void Light::sampleManyLanes(const Vec3f& p, const float* ux, const float* uy, int n, LightLanes& out) const {
    // Through sampleMany, so that a light's shared set-up (mesh lights' spherical triangles) is kept.
    Vec2f u[LightLanes::kWidth];
    std::optional<LightSample> samples[LightLanes::kWidth];
    for (int l = 0; l < n; ++l) u[l] = Vec2f{ux[l], uy[l]};
    sampleMany(p, std::span<const Vec2f>(u, size_t(n)), std::span<std::optional<LightSample>>(samples, size_t(n)));
    for (int l = 0; l < n; ++l) out.set(l, samples[l]);
}

}  // namespace penumbra
