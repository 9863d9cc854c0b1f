#include "lights/light_lanes.h"

namespace penumbra {

void Light::mayReachLanes(const LanePoints& at, int n, int32_t* reach) const {
    for (int l = 0; l < n; ++l) reach[l] = mayReach(at.p(l), at.n(l)) ? 1 : 0;
}

void Light::sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                        LightLanes& out) const {
    for (int l = 0; l < n; ++l) out.set(l, want[l] ? sample(at.p(l), Vec2f{ux[l], uy[l]}) : std::nullopt);
}

}  // namespace penumbra
