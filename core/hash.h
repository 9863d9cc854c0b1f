// Stateless integer hashing: the source of every random number in Penumbra.
// Every sample is a pure function of (seed, pixel, sample index, dimension),
// so images do not depend on thread count or tile order.
#pragma once

#include <cstdint>
#include <initializer_list>

namespace penumbra {

/// 64-bit finaliser (a variant of the MurmurHash3 fmix64 avalanche step).
constexpr uint64_t mix64(uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}

/// Hash of a sequence of integers (order matters).
inline uint64_t hashValues(std::initializer_list<uint64_t> values) {
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (uint64_t v : values) h = mix64(h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
    return h;
}

/// Uniform float in [0, 1) from the top 24 bits of a hash.
constexpr float toUnitFloat(uint64_t h) { return static_cast<float>(h >> 40) * (1.f / 16777216.f); }

}  // namespace penumbra
