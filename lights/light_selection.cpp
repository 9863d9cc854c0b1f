#include "lights/light_selection.h"

#include "core/error.h"
#include "lights/light_set.h"

namespace penumbra {

LightSelection resolvedLightSelection(const RenderSettings& settings, size_t lightCount) {
    if (settings.lightSelection != LightSelection::Auto) return settings.lightSelection;
    const size_t fewest =
        settings.integrator == IntegratorKind::Path ? kAutoTreeMinLightsPath : kAutoTreeMinLightsWhitted;
    return lightCount >= fewest ? LightSelection::Tree : LightSelection::All;
}

const LightPicker* lightPicker(const LightSet& lights, LightSelection resolved) {
    switch (resolved) {
        case LightSelection::All: return nullptr;
        case LightSelection::Power: return &lights.powerPicker();
        case LightSelection::Tree: return &lights.bvhPicker();
        case LightSelection::Auto: break;
    }
    throw Error(ErrorCode::InvalidArgument, "light selection: auto must be resolved for an integrator first");
}

const LightPicker* lightPicker(const LightSet& lights, const RenderSettings& settings) {
    return lightPicker(lights, resolvedLightSelection(settings, lights.size()));
}

}  // namespace penumbra
