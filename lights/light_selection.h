// Which LightPicker light samples use, for each --light-selection: the one
// rule, asked by every integrator. `all` picks nothing (every light takes
// every point's samples), `power` and `tree` name their pickers, and `auto`
// (the default) takes the tree from a number of lights on and `all` below,
// where sampling every light costs little and stratifies best. The number
// depends on the integrator: under the path integrator the noise of indirect
// light hides much of what stratifying each light gains, under Whitted's
// direct light alone it does not (docs/rendering.md, "Many lights", has the
// measurements).
#pragma once

#include <cstddef>

#include "core/render_settings.h"
#include "lights/light_picker.h"

namespace penumbra {

class LightSet;

/// The fewest lights (of every kind, the environment included) for which
/// LightSelection::Auto picks lights by the tree, per integrator.
inline constexpr size_t kAutoTreeMinLightsPath = 8;
inline constexpr size_t kAutoTreeMinLightsWhitted = 256;

/// The selection settings.lightSelection stands for with `lightCount`
/// lights: Auto resolved by the integrator; the others as they are.
LightSelection resolvedLightSelection(const RenderSettings& settings, size_t lightCount);

/// The picker of a resolved selection over `lights` (which it points into);
/// nullptr for All, where every light takes every point's samples. Auto,
/// which depends on the integrator, is an InvalidArgument error.
const LightPicker* lightPicker(const LightSet& lights, LightSelection resolved);
/// The picker light samples use under `settings` over `lights`.
const LightPicker* lightPicker(const LightSet& lights, const RenderSettings& settings);

}  // namespace penumbra
