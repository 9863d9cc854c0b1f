// Point and directional lights: no area, no pdf; always sampled exactly.
#pragma once

#include "core/scene.h"
#include "lights/light.h"

namespace penumbra {

class PointLightSource final : public Light {
public:
    explicit PointLightSource(const PointLight& l) : light_(l) {}
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    double power() const override { return channelMean(light_.intensity) * 4.0 * kPi; }
    bool isDelta() const override { return true; }

private:
    PointLight light_;
};

class DirectionalLightSource final : public Light {
public:
    /// sceneRadius: radius of the scene's bounding sphere, for power().
    DirectionalLightSource(const DirectionalLight& l, float sceneRadius);
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    double power() const override { return channelMean(light_.irradiance) * kPi * double(radius_) * double(radius_); }
    bool isDelta() const override { return true; }

private:
    DirectionalLight light_;
    Vec3f toLight_;
    float radius_;
};

}  // namespace penumbra
