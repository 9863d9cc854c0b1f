// All lights of a scene: explicit point/directional lights plus one area light
// per emissive rectangle, disk and sphere and per (mesh, emissive material).
#pragma once

#include <memory>
#include <vector>

#include "core/scene.h"
#include "lights/light.h"

namespace penumbra {

class LightSet {
public:
    /// Builds the lights of a finalized scene (which must outlive the set).
    explicit LightSet(const Scene& scene);

    size_t size() const { return lights_.size(); }
    const Light& operator[](size_t i) const { return *lights_[i]; }

    /// Power-proportional selection: light index for u in [0,1), with its probability.
    struct Pick {
        size_t index;
        float probability;
    };
    Pick pickByPower(float u) const;

    size_t areaLightCount() const { return areaLights_; }
    float totalEmitterArea() const { return totalArea_; }

private:
    std::vector<std::unique_ptr<Light>> lights_;
    std::vector<float> powerCdf_;  // normalised, last = 1
    size_t areaLights_ = 0;
    float totalArea_ = 0.f;
};

}  // namespace penumbra
