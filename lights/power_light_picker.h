// Light selection in proportion to power: a CDF over the lights' powers, the
// same at every shading point.
#pragma once

#include <vector>

#include "lights/light_picker.h"

namespace penumbra {

class PowerLightPicker final : public LightPicker {
public:
    /// powers: each light's power (negative and NaN ones count as 0); where
    /// their sum is not positive and finite, every light is equally likely.
    explicit PowerLightPicker(const std::vector<double>& powers);

    Pick pick(float u, const Vec3f& p, const Vec3f& n) const override;
    float probability(size_t j, const Vec3f& p, const Vec3f& n) const override;

private:
    std::vector<float> cdf_;  // normalised, last = 1
};

}  // namespace penumbra
