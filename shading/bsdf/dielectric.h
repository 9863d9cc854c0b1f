// Smooth dielectric interfaces (glass, water): exact Fresnel reflectance for
// unpolarised light, Snell refraction, total internal reflection, and the
// split of a ray into its reflected and transmitted parts.
//
// Conventions: wo points away from the surface, n is the unit normal on wo's
// side, eta = n_t / n_i is the ratio of the index on the far side of the
// interface to the index on wo's side (ior when the ray arrives from the
// front, 1/ior from behind). Radiance crossing into a denser medium is
// scaled by eta^2 (L/n^2 is invariant), so a ray traced from the camera
// carries (1 - F) kt / eta^2 through the interface (pbrt's radiance mode);
// entering and leaving a closed object cancel out.
#pragma once

#include <optional>

#include "core/color.h"
#include "core/math.h"

namespace penumbra {

/// Fresnel reflectance of a smooth dielectric for unpolarised light; cosThetaI
/// is the cosine between the incident direction and the normal on its side
/// (>= 0). 1 under total internal reflection.
float fresnelDielectric(float cosThetaI, float eta);

/// Direction refracted from wo through the interface with normal n (on wo's
/// side); nullopt under total internal reflection.
std::optional<Vec3f> refract(const Vec3f& wo, const Vec3f& n, float eta);

/// Both continuations of a ray at a dielectric: Whitted's mirror and
/// transmitted rays with their Fresnel weights (multiply the throughput).
struct DielectricSplit {
    Vec3f reflected;                   // unit mirror direction
    Rgb reflectedWeight;               // F
    std::optional<Vec3f> transmitted;  // unit refracted direction; none under total internal reflection
    Rgb transmittedWeight;             // (1 - F) kt / eta^2
};

/// Splits the ray arriving along -wo at a surface with shading normal ns and
/// geometric normal ng (both on wo's side). kt is the transmission colour.
/// Directions that smooth normals would send to the wrong side of the
/// geometric surface are recomputed about ng.
DielectricSplit splitDielectric(const Vec3f& wo, const Vec3f& ns, const Vec3f& ng, float eta, const Rgb& kt);

/// One sampled continuation for the path integrator: reflection with
/// probability F, refraction with probability 1 - F (both discrete, so the
/// weight is the split's weight over that probability).
struct DielectricSample {
    Vec3f wi;
    Rgb weight;        // f cos / pdf: 1 for reflection, kt / eta^2 for refraction
    float probability; // of the chosen branch
    bool transmitted;
};

/// Chooses a branch of splitDielectric with u in [0, 1).
DielectricSample sampleDielectric(const Vec3f& wo, const Vec3f& ns, const Vec3f& ng, float eta, const Rgb& kt, float u);

}  // namespace penumbra
