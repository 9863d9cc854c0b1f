// A perfect mirror (kr): the one rule for the direction it reflects.
#pragma once

#include "core/math.h"

namespace penumbra {

/// The mirror direction of wo (unit, away from the surface) about the shading
/// normal ns, or about the geometric normal ng where smooth normals would send
/// it below the surface (both normals on wo's side).
inline Vec3f mirrorDirection(const Vec3f& wo, const Vec3f& ns, const Vec3f& ng) {
    Vec3f r = reflect(-wo, ns);
    if (dot(r, ng) <= 0.f) r = reflect(-wo, ng);
    return normalize(r);
}

}  // namespace penumbra
