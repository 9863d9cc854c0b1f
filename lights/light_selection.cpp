#include "lights/light_selection.h"

#include "lights/light_set.h"

namespace penumbra {

LightSelection resolvedLightSelection(const RenderSettings& settings, size_t lightCount) {
    if (settings.lightSelection != LightSelection::Auto) return settings.lightSelection;
    const size_t fewest =
        settings.integrator == IntegratorKind::Path ? kAutoTreeMinLightsPath : kAutoTreeMinLightsWhitted;
    return lightCount >= fewest ? LightSelection::Tree : LightSelection::All;
}

const LightPicker* lightPicker(const LightSet& lights, const RenderSettings& settings) {
    switch (resolvedLightSelection(settings, lights.size())) {
        case LightSelection::Power: return &lights.powerPicker();
        case LightSelection::Tree: return &lights.bvhPicker();
        default: return nullptr;
    }
}

}  // namespace penumbra
