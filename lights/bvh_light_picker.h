// Light selection by a light hierarchy (--light-selection tree): the lights
// with bounds (area lights, point lights) are picked by descending a LightBVH
// at the shading point; the lights at infinity (directional lights, the
// environment), which have no position to bound, are picked beside it. A
// sample first chooses between the two groups in proportion to their total
// power (the same at every point), then a light within its group: by the
// tree, or in proportion to power among the lights at infinity.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "lights/light_bvh.h"
#include "lights/light_picker.h"
#include "lights/power_light_picker.h"

namespace penumbra {

class BVHLightPicker final : public LightPicker {
public:
    /// bounds[j]: light j's (Light::bounds), nullopt for a light at infinity;
    /// powers[j]: its power (Light::power's average; NaN and non-positive
    /// ones are never picked, infinite ones count as the largest float).
    BVHLightPicker(std::span<const std::optional<LightBounds>> bounds, std::span<const double> powers);

    Pick pick(float u, const Vec3f& p, const Vec3f& n) const override;
    float probability(size_t j, const Vec3f& p, const Vec3f& n) const override;

    const LightBVH& tree() const { return tree_; }
    /// The probability that a sample goes to the tree's lights.
    float treeShare() const { return treeShare_; }

private:
    LightBVH tree_;
    std::vector<size_t> infinite_;              // the lights at infinity, in index order
    std::vector<int32_t> infiniteSlot_;         // per light: its place in infinite_, or -1
    std::optional<PowerLightPicker> infinitePicker_;  // over infinite_
    float treeShare_ = 1.f;
};

}  // namespace penumbra
