#include "lights/delta_lights.h"

namespace penumbra {

std::optional<LightSample> PointLightSource::sample(const Vec3f& p, Vec2f) const {
    Vec3f d = light_.position - p;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f)) return std::nullopt;
    float dist = std::sqrt(dist2);
    // Inverse-square falloff: irradiance I cos / d^2; the cosine is the integrator's.
    return LightSample{light_.intensity / dist2, d / dist, light_.position, dist, 1.f, true};
}

DirectionalLightSource::DirectionalLightSource(const DirectionalLight& l, float sceneRadius)
    : light_(l), toLight_(-normalize(l.direction)), radius_(sceneRadius) {}

std::optional<LightSample> DirectionalLightSource::sample(const Vec3f& p, Vec2f) const {
    if (!(lengthSquared(toLight_) > 0.f)) return std::nullopt;
    return LightSample{light_.irradiance, toLight_, p, kInfinity, 1.f, true};
}

}  // namespace penumbra
