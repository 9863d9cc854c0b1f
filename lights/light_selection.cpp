#include "lights/light_selection.h"

#include "lights/light_set.h"

namespace penumbra {

const LightPicker* lightPicker(const LightSet& lights, LightSelection selection) {
    switch (selection) {
        case LightSelection::All: return nullptr;
        case LightSelection::Power: return &lights.powerPicker();
        case LightSelection::Tree: return &lights.bvhPicker();
        case LightSelection::Auto: return lights.size() >= kAutoTreeMinLights ? &lights.bvhPicker() : nullptr;
    }
    return nullptr;
}

}  // namespace penumbra
