// Up to 16 rays as arrays of their components (structure of arrays): the form
// in which the integrator's lane loops write shadow rays and Embree's 16-wide
// packets read them, so a ray is never built as a Ray and transposed on the way.
#pragma once

#include <cstdint>

#include "core/ray.h"

namespace penumbra {

struct RayLanes {
    static constexpr int kWidth = 16;
    alignas(64) float ox[kWidth], oy[kWidth], oz[kWidth];
    alignas(64) float dx[kWidth], dy[kWidth], dz[kWidth];
    alignas(64) float tnear[kWidth], tfar[kWidth];
    /// 1 where the lane holds a ray; 0 where it is idle: its components are
    /// then not read and no query answers or counts it.
    alignas(64) int32_t active[kWidth];

    Ray ray(int l) const { return Ray{Vec3f{ox[l], oy[l], oz[l]}, Vec3f{dx[l], dy[l], dz[l]}, tnear[l], tfar[l]}; }
    void set(int l, const Ray& r) {
        ox[l] = r.o.x;
        oy[l] = r.o.y;
        oz[l] = r.o.z;
        dx[l] = r.d.x;
        dy[l] = r.d.y;
        dz[l] = r.d.z;
        tnear[l] = r.tnear;
        tfar[l] = r.tfar;
    }
};

}  // namespace penumbra
