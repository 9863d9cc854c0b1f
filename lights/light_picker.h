// How a shading point's light samples choose their lights when each sample
// picks one (--light-selection power): the interface the direct-light
// estimator asks, whatever the rule. Power-proportional selection is one
// implementation (lights/power_light_picker.h); a light hierarchy that picks
// by what a light gives the point would be another. Sampling every light
// (--light-selection all) picks nothing: the estimator samples each light in
// turn, each with probability 1.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>

#include "core/math.h"

namespace penumbra {

class LightPicker {
public:
    struct Pick {
        size_t index;       // the light
        float probability;  // of picking it at this point; 0: no light can be picked
        float u;            // the u given, rescaled to [0, 1) within the pick: a fresh number for reuse
    };

    virtual ~LightPicker() = default;
    /// The light one sample at p (geometric normal n) takes, chosen with u in [0, 1).
    virtual Pick pick(float u, const Vec3f& p, const Vec3f& n) const = 0;
    /// The probability that pick() at (p, n) returns light j: what the MIS
    /// weight of a BSDF sample that reaches j multiplies its light pdf by.
    virtual float probability(size_t j, const Vec3f& p, const Vec3f& n) const = 0;
};

/// A light's power as every picker weighs it: NaN and non-positive powers 0 (never
/// picked), infinite ones the largest float, so that sums stay finite.
inline double weighedPower(double power) {
    return power > 0.0 ? std::min(power, double(std::numeric_limits<float>::max())) : 0.0;
}

}  // namespace penumbra
