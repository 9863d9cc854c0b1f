// The Lambertian BRDF kd/pi (a Phong material without a specular lobe)
// sampled by its cosine: pdf cos(theta)/pi, so that f cos / pdf is kd in
// closed form and a bounce needs no lobe evaluated.
#pragma once

#include "core/math.h"
#include "core/sampling.h"

namespace penumbra {

/// A cosine-weighted direction about the unit normal n and its cosine with
/// n (the hemisphere map's z, exact for the direction the map means: the
/// pdf is cosTheta / pi).
struct LambertDirection {
    Vec3f wi;
    float cosTheta;
};
inline LambertDirection sampleLambert(const Vec3f& n, Vec2f u) {
    const Vec3f local = squareToCosineHemisphere(u);
    return {Frame::fromNormal(n).toWorld(local), local.z};
}

}  // namespace penumbra
