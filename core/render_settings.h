// What to render: image size, sample counts, depth, seed, threads, crop window.
#pragma once

#include <cstdint>
#include <optional>

#include <penumbra/types.hpp>

#include "core/color.h"

namespace penumbra {

// The settings are the public value types (api/include/penumbra/types.hpp),
// used inside under their old names.
using CropWindow = pnb::CropWindow;
using LightSelection = pnb::LightSelection;
using IntegratorKind = pnb::IntegratorKind;
using DirectLightSampling = pnb::DirectLightSampling;
using RenderSettings = pnb::RenderSettings;

/// Settings that no public API offers: the comparison baselines of the
/// benchmark tools (penumbra-estimators, scripts/bench_noise.py).
struct InternalSettings {
    /// Light samples uniform in area, without MIS: the direct-light estimator
    /// before solid-angle sampling (docs/rendering.md).
    bool areaLightSamples = false;
};

/// Throws Error(InvalidArgument) naming the offending setting.
void validateSettings(const RenderSettings& s);

/// Settings a scene file may carry; unset fields leave the defaults alone.
struct SettingsPatch {
    std::optional<int> width, height, spp, lightSamples, maxDepth, threads, tileSize;
    std::optional<uint64_t> seed;
    std::optional<LightSelection> lightSelection;
    std::optional<IntegratorKind> integrator;
    void applyTo(RenderSettings& s) const;
};

}  // namespace penumbra
