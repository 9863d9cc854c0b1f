// The Lambertian BRDF kd/pi (a Phong material without a specular lobe)
// sampled by its cosine: pdf cos(theta)/pi, so that f cos / pdf is kd in
// closed form and a bounce needs no lobe evaluated.
#pragma once

#include <algorithm>

#include "core/color.h"
#include "core/math.h"
#include "core/sampling.h"
#include "shading/bsdf/bsdf_sample.h"

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

/// The solid-angle pdf of a direction at cosine cosTheta with the normal: cos/pi, 0 below.
inline float lambertPdf(float cosTheta) { return std::max(0.f, cosTheta) * kInvPi; }

/// f cos and pdf of wi for albedo kd (not black) about the unit shading
/// normal n: kd/pi cos and cos/pi, zero below. phongEvaluate's values, bit
/// for bit, for a material without a Phong lobe (its lobe's terms add exact
/// zeros there), without working out the lobes.
inline BsdfSample lambertEvaluate(const Rgb& kd, const Vec3f& n, const Vec3f& wi) {
    const float cosTheta = dot(n, wi);
    Rgb fCos;
    if (cosTheta > 0.f) fCos = kd * kInvPi * cosTheta;
    return BsdfSample{wi, fCos, lambertPdf(cosTheta)};
}

}  // namespace penumbra
