// What the integrator knows about the surface point it shades: the hit made
// two-sided (both normals on the side the ray arrived from), the direction
// back along the ray and the material with its textured parameters.
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
    Rgb kd;     // diffuse albedo after texturing; metal-roughness: the base colour after texturing
    const Material* material = nullptr;
    // Metal-roughness (metalRoughness: material->kind, unless it is glass),
    // after texturing: shading/bsdf/metal_roughness.h.
    float metallic = 0.f, roughness = 1.f;
    bool metalRoughness = false;
    // The specular lobe is left to a mirror bounce (the Whitted integrator,
    // at low roughness): the BSDF is the diffuse base alone.
    bool mirrorSpecular = false;
    // The response is more than the Lambertian kd/pi (material->isGlossy():
    // a Phong lobe; every metal-roughness point); set by SurfaceShading::shade, so that the per-lane
    // decisions (which lanes take light samples, MIS, ShadowLanes' rule) need
    // not load through `material`.
    bool glossy = false;
    bool front = true;  // the ray arrived on the side the surface's own geometric normal faces
    // Scene::convexMeshOf where the ray arrived from outside (front), else -1:
    // a ray leaving here above ng cannot meet that mesh again (the
    // accelerators' `leaving` hints). Set only in a scene with a convex mesh
    // (SurfaceShading::shade), read only where the accelerator takes hints:
    // set at every shading point, Figure 18.4 (no mesh) rendered 2% slower.
    int32_t convexMesh = -1;

    /// Whether any light can reach the viewer from here (a black or pure
    /// mirror material needs no light samples).
    /// Without branches: it decides per lane which points take light samples.
    bool reflectsLight() const { return glossy | (kd.r != 0.f) | (kd.g != 0.f) | (kd.b != 0.f); }
    /// Whether the material's emission ke leaves towards the viewer: emission
    /// is one-sided, from the side the geometric normal faces, unless the
    /// material emits on both sides.
    /// Whether a mirror bounce leaves here: the material's kr, or a polished
    /// metal-roughness surface's specular lobe (mirrorSpecular).
    bool mirrors() const { return metalRoughness ? mirrorSpecular : material->isMirror(); }
    bool emits() const { return material->isEmissive() && (front || material->twoSidedEmission); }
};

}  // namespace penumbra
