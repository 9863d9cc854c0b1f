#include "core/multi_jitter.h"

#include <cmath>

#include "core/hash.h"

namespace penumbra {
namespace {

// A hash of (i, p) to [0, 1), for the jitter within a cell.
float jitter(uint32_t i, uint32_t p) { return toUnitFloat(mix64((uint64_t(p) << 32) ^ i ^ 0x5bd1e995ULL)); }

}  // namespace

IndexPermutation::IndexPermutation(uint32_t n, uint32_t p) : n_(n) {
    uint32_t mask = n > 1 ? n - 1 : 0;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    mask_ = mask;
    k0_ = static_cast<uint32_t>(mix64(p));
    k1_ = static_cast<uint32_t>(mix64(uint64_t(p) + 0x632be59bd9b4e019ULL)) | 1u;
    k2_ = static_cast<uint32_t>(mix64(uint64_t(p) + 0x85157af5ULL));
}

uint32_t IndexPermutation::operator()(uint32_t i) const {
    if (n_ <= 1) return 0;
    // Each step is a bijection on [0, mask]: xor with a key, multiply by an
    // odd number (mod 2^w), and xorshift-right. Cycle-walking keeps the
    // result inside [0, n) while preserving bijectivity.
    const uint32_t mask = mask_;
    do {
        i ^= k0_ & mask;
        i = (i * k1_) & mask;
        i ^= i >> 3;
        i = (i * 0x2c1b3c6dU) & mask;
        i ^= k2_ & mask;
        i ^= i >> 7;
        i = (i * 0x297a2d39U) & mask;
        i ^= i >> 5;
    } while (i >= n_);
    return i;
}

MjGrid mjGrid(uint32_t n) {
    uint32_t cols = static_cast<uint32_t>(std::sqrt(static_cast<double>(n)));
    if (cols == 0) cols = 1;
    uint32_t rows = (n + cols - 1) / cols;
    return {cols, rows};
}

MultiJitterSet::MultiJitterSet(uint32_t n, uint32_t p) : n_(n), pattern_(p) {
    const MjGrid g = mjGrid(n);
    m_ = g.cols;
    k_ = g.rows;
    invM_ = 1.f / static_cast<float>(m_);
    invK_ = 1.f / static_cast<float>(k_);
    if (m_ * k_ != n) cells_ = IndexPermutation(m_ * k_, p * 0x51633e2dU);
    // Shuffle the sub-cell offsets of a whole row (resp. column) with one
    // permutation: this is the "correlated" part that keeps the n-rooks
    // property while only needing permutations of length m and k.
    cols_ = IndexPermutation(m_, p * 0xa511e9b3U);
    rows_ = IndexPermutation(k_, p * 0x63d83595U);
}

Vec2f MultiJitterSet::sample(uint32_t s) const {
    if (m_ * k_ != n_) s = cells_(s);
    const uint32_t col = s % m_, row = s / m_;
    const uint32_t sx = cols_(col);
    const uint32_t sy = rows_(row);
    const float jx = jitter(s, pattern_ * 0xa399d265U);
    const float jy = jitter(s, pattern_ * 0x711ad6a5U);
    Vec2f r{(static_cast<float>(col) + (static_cast<float>(sy) + jx) * invK_) * invM_,
            (static_cast<float>(row) + (static_cast<float>(sx) + jy) * invM_) * invK_};
    // Guard against rounding to exactly 1.
    r.x = std::min(r.x, 0x1.fffffep-1f);
    r.y = std::min(r.y, 0x1.fffffep-1f);
    return r;
}

uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension) {
    return static_cast<uint32_t>(hashValues({seed, pixel, set, dimension}));
}

}  // namespace penumbra
