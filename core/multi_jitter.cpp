#include "core/multi_jitter.h"

#include <cmath>

#include "core/hash.h"

namespace penumbra {
namespace {

// A hash of (i, p) to [0, 1), for the jitter within a cell.
float jitter(uint32_t i, uint32_t p) { return toUnitFloat(mix64((uint64_t(p) << 32) ^ i ^ 0x5bd1e995ULL)); }

}  // namespace

uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t p) {
    if (n <= 1) return 0;
    uint32_t mask = n - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    // Each step is a bijection on [0, mask]: xor with a constant, multiply by
    // an odd number (mod 2^w), and xorshift-right (invertible). Cycle-walking
    // keeps the result inside [0, n) while preserving bijectivity.
    const uint32_t k0 = static_cast<uint32_t>(mix64(p));
    const uint32_t k1 = static_cast<uint32_t>(mix64(uint64_t(p) + 0x632be59bd9b4e019ULL)) | 1u;
    const uint32_t k2 = static_cast<uint32_t>(mix64(uint64_t(p) + 0x85157af5ULL));
    do {
        i ^= k0 & mask;
        i = (i * k1) & mask;
        i ^= (i & mask) >> 3;
        i = (i * 0x2c1b3c6dU) & mask;
        i ^= k2 & mask;
        i ^= (i & mask) >> 7;
        i = (i * 0x297a2d39U) & mask;
        i ^= (i & mask) >> 5;
    } while (i >= n);
    return i;
}

MjGrid mjGrid(uint32_t n) {
    uint32_t cols = static_cast<uint32_t>(std::sqrt(static_cast<double>(n)));
    if (cols == 0) cols = 1;
    uint32_t rows = (n + cols - 1) / cols;
    return {cols, rows};
}

Vec2f multiJitter2D(uint32_t s, uint32_t n, uint32_t p) {
    const MjGrid g = mjGrid(n);
    const uint32_t m = g.cols, k = g.rows;
    // For n that is not m*k, choose which n of the m*k cells are used.
    if (m * k != n) s = permuteIndex(s, m * k, p * 0x51633e2dU);
    const uint32_t col = s % m, row = s / m;
    // Shuffle the sub-cell offsets of a whole row (resp. column) with one
    // permutation: this is the "correlated" part that keeps the n-rooks
    // property while only needing permutations of length m and k.
    const uint32_t sx = permuteIndex(col, m, p * 0xa511e9b3U);
    const uint32_t sy = permuteIndex(row, k, p * 0x63d83595U);
    const float jx = jitter(s, p * 0xa399d265U);
    const float jy = jitter(s, p * 0x711ad6a5U);
    Vec2f r{(static_cast<float>(col) + (static_cast<float>(sy) + jx) / static_cast<float>(k)) / static_cast<float>(m),
            (static_cast<float>(row) + (static_cast<float>(sx) + jy) / static_cast<float>(m)) / static_cast<float>(k)};
    // Guard against rounding to exactly 1.
    r.x = std::min(r.x, 0x1.fffffep-1f);
    r.y = std::min(r.y, 0x1.fffffep-1f);
    return r;
}

uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension) {
    return static_cast<uint32_t>(hashValues({seed, pixel, set, dimension}));
}

}  // namespace penumbra
