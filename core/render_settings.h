// What to render: image size, sample counts, depth, seed, threads, crop window.
#pragma once

#include <cstdint>
#include <optional>

#include "core/color.h"

namespace penumbra {

/// Pixel window [x0, x1) x [y0, y1) of the full frame. Pixels keep their
/// full-frame coordinates (and so their samples), so crops tile into the
/// exact full-frame image.
struct CropWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool operator==(const CropWindow&) const = default;
};

enum class LightSelection {
    All,    // every light gets lightSamples samples at every shading point (default)
    Power,  // lightSamples samples in total, each picking one light in proportion to its power
};

struct RenderSettings {
    int width = 512;
    int height = 512;
    int spp = 16;           // camera samples per pixel (multi-jittered)
    int lightSamples = 4;   // area-light samples per light per shading point (multi-jittered)
    int maxDepth = 10;      // mirror bounces; 0 = no reflection rays
    uint64_t seed = 0;
    int threads = 0;        // 0 = all cores
    int tileSize = 16;
    std::optional<CropWindow> crop;
    LightSelection lightSelection = LightSelection::All;
    bool aovs = true;       // fill albedo, normal and depth of the first hit
};

/// Throws Error(InvalidArgument) naming the offending setting.
void validateSettings(const RenderSettings& s);

/// Settings a scene file may carry; unset fields leave the defaults alone.
struct SettingsPatch {
    std::optional<int> width, height, spp, lightSamples, maxDepth, threads, tileSize;
    std::optional<uint64_t> seed;
    std::optional<LightSelection> lightSelection;
    void applyTo(RenderSettings& s) const;
};

}  // namespace penumbra
