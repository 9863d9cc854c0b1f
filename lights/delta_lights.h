// Point and directional lights: no area, no pdf; always sampled exactly.
#pragma once

#include "core/scene.h"
#include "lights/light.h"

namespace penumbra {

class PointLightSource final : public Light {
public:
    explicit PointLightSource(const PointLight& l) : light_(l) {}
    std::optional<LightSample> sample(const Vec3f& p, Vec2f u) const override;
    /// sample() at every lane's point as one loop over the lanes (the same values).
    void sampleLanes(const LanePoints& at, const float* ux, const float* uy, const int32_t* want, int n,
                     LightLanes& out) const override;
    float pdf(const Vec3f&, const Hit&) const override { return 0.f; }
    double power() const override { return channelMean(light_.intensity) * 4.0 * kPi; }
    /// The point itself, shining every way.
    std::optional<LightBounds> bounds() const override {
        LightBounds b;
        b.box.extend(light_.position);
        return b;
    }
    bool isDelta() const override { return true; }

private:
    /// sampleLanes' loop, compiled for each lane width (core/lane_clones.h).
    void pointLanes(const LanePoints& at, const int32_t* want, int n, LightLanes& out) const;

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
