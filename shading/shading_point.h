// What the integrator knows about the surface point it shades: the hit made
// two-sided (both normals on the side the ray arrived from), the direction
// back along the ray and the material with its (textured) diffuse albedo.
#pragma once

#include "core/color.h"
#include "core/material.h"
#include "core/math.h"

namespace penumbra {

struct ShadingPoint {
    Vec3f p;    // hit point
    Vec3f ng;   // unit geometric normal, facing wo
    Vec3f ns;   // unit shading normal, facing wo
    Vec3f wo;   // unit direction back along the ray
    Rgb kd;     // diffuse albedo after texturing
    const Material* material = nullptr;
    // The response is more than the Lambertian kd/pi (material->isGlossy():
    // a Phong lobe); set by SurfaceShading::shade, so that the per-lane
    // decisions (which lanes take light samples, MIS, ShadowLanes' rule) need
    // not load through `material`.
    bool glossy = false;
    bool front = true;  // the ray arrived on the side the surface's own geometric normal faces

    /// Whether any light can reach the viewer from here (a black or pure
    /// mirror material needs no light samples).
    bool reflectsLight() const { return glossy || !kd.isBlack(); }
    /// Whether the material's emission ke leaves towards the viewer: emission
    /// is one-sided, from the side the geometric normal faces, unless the
    /// material emits on both sides.
    bool emits() const { return material->isEmissive() && (front || material->twoSidedEmission); }
};

}  // namespace penumbra
