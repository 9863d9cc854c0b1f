// What every BSDF model gives for a direction: f cos and the solid-angle pdf
// with which its sampling draws that direction.
#pragma once

#include "core/color.h"
#include "core/math.h"

namespace penumbra {

struct BsdfSample {
    Vec3f wi;   // the direction (unit, pointing away from the surface)
    Rgb fCos;   // f_r(wo, wi) * cos(theta_i), cos taken with the shading normal
    float pdf;  // solid-angle pdf with which the model's sampling returns wi
};

}  // namespace penumbra
