// Flush-to-zero / denormals-are-zero for a scope, as Embree recommends for
// its traversal; the previous mode is restored so host threads are unchanged.
#pragma once

#include <pmmintrin.h>
#include <xmmintrin.h>

namespace penumbra {

class DenormalGuard {
public:
    DenormalGuard() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ | DAZ
    ~DenormalGuard() { _mm_setcsr(saved_); }
    DenormalGuard(const DenormalGuard&) = delete;
    DenormalGuard& operator=(const DenormalGuard&) = delete;

private:
    unsigned saved_;
};

}  // namespace penumbra
