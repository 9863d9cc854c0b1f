// Up to 16 rays as arrays of their components (structure of arrays): the form
// in which the integrator's lane loops write shadow rays and Embree's 16-wide
// packets read them, so a ray is never built as a Ray and transposed on the way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

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
    /// out[l] = ray(l) for l < count: lanes eight at a time as an 8 x 8
    /// transposition, each Ray written by one 32-byte store. Lane by lane,
    /// the compiler gathered each Ray from eight scalar loads, and the
    /// completion that reads it next could not take the value from the
    /// eight narrow stores in flight (store forwarding fails).
    void rays(int count, Ray* out) const;
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

namespace detail {

// A Ray is its eight floats in RayLanes' component order, so that a
// transposed row is a Ray's bytes.
static_assert(sizeof(Ray) == 8 * sizeof(float) && std::is_trivially_copyable_v<Ray>);
static_assert(offsetof(Ray, d) == 3 * sizeof(float) && offsetof(Ray, tnear) == 6 * sizeof(float) &&
              offsetof(Ray, tfar) == 7 * sizeof(float));

using Float8 = float __attribute__((vector_size(32)));

}  // namespace detail

inline void RayLanes::rays(int count, Ray* out) const {
    using detail::Float8;
    int l0 = 0;
    // Each shuffle is one of AVX's unpcklps/unpckhps, shufps or perm2f128
    // (on SSE2, the same on two halves of 128 bits).
    for (; l0 + 8 <= count; l0 += 8) {
        const float* rows[8] = {ox + l0, oy + l0, oz + l0, dx + l0, dy + l0, dz + l0, tnear + l0, tfar + l0};
        Float8 r[8];
        for (int c = 0; c < 8; ++c) std::memcpy(&r[c], rows[c], sizeof(Float8));
        Float8 t[8], q[8];
        for (int k = 0; k < 8; k += 2) {  // pairs of components, interleaved
            t[k] = __builtin_shufflevector(r[k], r[k + 1], 0, 8, 1, 9, 4, 12, 5, 13);
            t[k + 1] = __builtin_shufflevector(r[k], r[k + 1], 2, 10, 3, 11, 6, 14, 7, 15);
        }
        for (int h = 0; h < 8; h += 4) {  // four components side by side, lanes (0, 4), (1, 5), ...
            q[h] = __builtin_shufflevector(t[h], t[h + 2], 0, 1, 8, 9, 4, 5, 12, 13);
            q[h + 1] = __builtin_shufflevector(t[h], t[h + 2], 2, 3, 10, 11, 6, 7, 14, 15);
            q[h + 2] = __builtin_shufflevector(t[h + 1], t[h + 3], 0, 1, 8, 9, 4, 5, 12, 13);
            q[h + 3] = __builtin_shufflevector(t[h + 1], t[h + 3], 2, 3, 10, 11, 6, 7, 14, 15);
        }
        for (int k = 0; k < 4; ++k) {  // all eight components of lanes k and k + 4
            const Float8 lo = __builtin_shufflevector(q[k], q[k + 4], 0, 1, 2, 3, 8, 9, 10, 11);
            const Float8 hi = __builtin_shufflevector(q[k], q[k + 4], 4, 5, 6, 7, 12, 13, 14, 15);
            std::memcpy(static_cast<void*>(out + l0 + k), &lo, sizeof(lo));
            std::memcpy(static_cast<void*>(out + l0 + k + 4), &hi, sizeof(hi));
        }
    }
    for (; l0 < count; ++l0) out[l0] = ray(l0);
}

}  // namespace penumbra
