#include "lights/bvh_light_picker.h"

#include <algorithm>
#include <limits>

namespace penumbra {

BVHLightPicker::BVHLightPicker(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers)
    : tree_(bounds, powers), infiniteSlot_(bounds.size(), -1) {
    double treePower = 0.0, infinitePower = 0.0;
    std::vector<double> infinitePowers;
    for (size_t j = 0; j < bounds.size(); ++j) {
        const double power = j < powers.size() ? weighedPower(powers[j]) : 0.0;
        if (bounds[j]) {
            if (tree_.holds(j)) treePower += power;
            continue;
        }
        infiniteSlot_[j] = int32_t(infinite_.size());
        infinite_.push_back(j);
        infinitePowers.push_back(power);
        infinitePower += power;
    }
    if (!infinite_.empty()) infinitePicker_.emplace(infinitePowers);
    if (infinite_.empty())
        treeShare_ = 1.f;
    else if (tree_.empty())
        treeShare_ = 0.f;
    else
        treeShare_ = float(treePower / (treePower + infinitePower));  // both groups hold power here
}

LightPicker::Pick BVHLightPicker::pick(float u, const Vec3f& p, const Vec3f& n) const {
    if (u < treeShare_) {
        Pick pick = tree_.pick(std::min(u / treeShare_, 0x1.fffffep-1f), p, n);
        pick.probability *= treeShare_;
        return pick;
    }
    if (!infinitePicker_) return {0, 0.f, u};
    const float share = 1.f - treeShare_;
    Pick pick = infinitePicker_->pick(std::min((u - treeShare_) / share, 0x1.fffffep-1f), p, n);
    pick.index = infinite_[pick.index];
    pick.probability *= share;
    return pick;
}

float BVHLightPicker::probability(size_t j, const Vec3f& p, const Vec3f& n) const {
    if (j >= infiniteSlot_.size()) return 0.f;
    if (infiniteSlot_[j] < 0) return treeShare_ * tree_.probability(j, p, n);
    return (1.f - treeShare_) * infinitePicker_->probability(size_t(infiniteSlot_[j]), p, n);
}

}  // namespace penumbra
