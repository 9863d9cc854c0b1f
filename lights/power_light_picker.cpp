#include "lights/power_light_picker.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

PowerLightPicker::PowerLightPicker(const std::vector<double>& powers) {
    // The running sums stay in double until they are divided by the total:
    // lights may emit more than the largest float.
    std::vector<double> sums;
    double acc = 0.0;
    for (const double power : powers) {
        acc += std::max(0.0, power);
        sums.push_back(acc);
    }
    cdf_.resize(sums.size());
    for (size_t i = 0; i < sums.size(); ++i)
        // Without a finite total of power (none, or an infinite one), uniform selection.
        cdf_[i] = acc > 0.0 && std::isfinite(acc) ? float(sums[i] / acc) : float(i + 1) / float(sums.size());
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
