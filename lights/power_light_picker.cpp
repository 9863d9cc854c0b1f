#include "lights/power_light_picker.h"

#include <algorithm>

namespace penumbra {

PowerLightPicker::PowerLightPicker(const std::vector<double>& powers) {
    double acc = 0.0;
    for (const double power : powers) {
        acc += std::max(0.0, power);
        cdf_.push_back(static_cast<float>(acc));
    }
    if (acc > 0.0) {
        for (float& c : cdf_) c = static_cast<float>(c / acc);
    } else {
        // No power anywhere: fall back to uniform selection.
        for (size_t i = 0; i < cdf_.size(); ++i) cdf_[i] = float(i + 1) / float(cdf_.size());
    }
    if (!cdf_.empty()) cdf_.back() = 1.f;
}

LightPicker::Pick PowerLightPicker::pick(float u, const Vec3f&, const Vec3f&) const {
    size_t i = std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin();
    i = std::min(i, cdf_.size() - 1);
    const float lo = i ? cdf_[i - 1] : 0.f;
    const float probability = cdf_[i] - lo;
    const float rescaled = probability > 0.f ? std::min((u - lo) / probability, 0x1.fffffep-1f) : 0.f;
    return {i, probability, rescaled};
}

float PowerLightPicker::probability(size_t j, const Vec3f&, const Vec3f&) const {
    return cdf_[j] - (j ? cdf_[j - 1] : 0.f);
}

}  // namespace penumbra
