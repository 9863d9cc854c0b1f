// What a batch of camera samples reports besides radiance: the rays it
// traced by kind, and the first hit of each sample for the AOVs.
#pragma once

#include <cstdint>

#include "core/color.h"
#include "core/math.h"

namespace penumbra {

/// Rays traced and samples dropped, counted per tile and summed.
struct RayCounts {
    uint64_t camera = 0, shadow = 0, reflection = 0;
    uint64_t nonFinite = 0;      // radiance samples that were NaN/Inf and dropped
    uint64_t transmission = 0;   // refracted rays (dielectrics)
    uint64_t indirect = 0;       // path: diffuse and glossy bounce rays
    uint64_t pathLengthSum = 0;  // rays along each camera sample's path (whitted: deepest branch)
    uint32_t pathLengthMax = 0;
    uint64_t brdf = 0;           // BSDF-sampled rays of direct light under MIS (whitted)
    uint64_t pixelsHit = 0;      // pixels whose first camera sample of the pass hit a surface
    RayCounts& operator+=(const RayCounts& o) {
        camera += o.camera;
        shadow += o.shadow;
        reflection += o.reflection;
        nonFinite += o.nonFinite;
        transmission += o.transmission;
        indirect += o.indirect;
        pathLengthSum += o.pathLengthSum;
        pathLengthMax = pathLengthMax > o.pathLengthMax ? pathLengthMax : o.pathLengthMax;
        brdf += o.brdf;
        pixelsHit += o.pixelsHit;
        return *this;
    }
    uint64_t total() const { return camera + shadow + reflection + transmission + indirect + brdf; }
};

/// First-hit data for the AOVs.
struct FirstHit {
    Rgb albedo;
    Vec3f normal;
    float depth = 0.f;
};

}  // namespace penumbra
