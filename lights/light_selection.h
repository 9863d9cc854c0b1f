// Which LightPicker light samples use, for each --light-selection: the one
// rule, asked by every integrator. `all` picks nothing (every light takes
// every point's samples), `power` and `tree` name their pickers, and `auto`
// (the default) takes the tree from kAutoTreeMinLights lights on and `all`
// below, where sampling every light costs little and stratifies best
// (docs/rendering.md, "Many lights").
#pragma once

#include <cstddef>

#include "core/render_settings.h"
#include "lights/light_picker.h"

namespace penumbra {

class LightSet;

/// The fewest lights (of every kind, the environment included) for which
/// LightSelection::Auto picks lights by the tree.
inline constexpr size_t kAutoTreeMinLights = 8;

/// The picker for `selection` over `lights` (which it points into); nullptr
/// where every light takes every point's samples.
const LightPicker* lightPicker(const LightSet& lights, LightSelection selection);

}  // namespace penumbra
