// Correlated multi-jittered sampling (Kensler 2013), a table-free form of
// multi-jittered sampling (Chiu, Shirley & Wang 1994): n = m x k points that
// are jittered in an m x k grid and, at the same time, stratified into n
// strata in each 1D projection (n-rooks). Sample s of the set with pattern p
// is computed on its own, without generating the rest of the set.
#pragma once

#include <cstdint>

#include "core/hash.h"
#include "core/math.h"

namespace penumbra {

/// A pseudo-random permutation of [0, n) chosen by a pattern id: a bijection
/// on [0, 2^w) built from invertible steps, applied by cycle-walking until the
/// value falls below n. The keys are derived once, when it is constructed.
class IndexPermutation {
public:
    /// The keys a pattern id stands for (three hashes of it).
    struct Keys {
        uint32_t k0, k1, k2;
    };
    static Keys keysOf(uint32_t pattern) {
        return {static_cast<uint32_t>(mix64(pattern)),
                static_cast<uint32_t>(mix64(uint64_t(pattern) + 0x632be59bd9b4e019ULL)) | 1u,
                static_cast<uint32_t>(mix64(uint64_t(pattern) + 0x85157af5ULL))};
    }

    IndexPermutation() = default;
    IndexPermutation(uint32_t n, uint32_t pattern) : IndexPermutation(n, keysOf(pattern)) {}
    /// The permutation of pattern p given keysOf(p), worked out beforehand.
    IndexPermutation(uint32_t n, const Keys& keys);
    uint32_t operator()(uint32_t i) const;

    /// The smallest all-ones mask covering 0 .. n - 1: the walk's domain.
    static uint32_t maskOf(uint32_t n) {
        uint32_t mask = n > 1 ? n - 1 : 0;
        mask |= mask >> 1;
        mask |= mask >> 2;
        mask |= mask >> 4;
        mask |= mask >> 8;
        mask |= mask >> 16;
        return mask;
    }
    /// One step of the cycle walk: a bijection on [0, mask] chosen by the
    /// keys (operator() repeats it until the value falls inside [0, n)).
    static uint32_t step(uint32_t i, uint32_t mask, uint32_t k0, uint32_t k1, uint32_t k2) {
        // Xor with a key, multiply by an odd number (mod 2^w), xorshift-right.
        i ^= k0 & mask;
        i = (i * k1) & mask;
        i ^= i >> 3;
        i = (i * 0x2c1b3c6dU) & mask;
        i ^= k2 & mask;
        i ^= i >> 7;
        i = (i * 0x297a2d39U) & mask;
        i ^= i >> 5;
        return i;
    }

private:
    uint32_t n_ = 1, mask_ = 0, k0_ = 0, k1_ = 1, k2_ = 0;
};

// Inline: the renderer builds a pixel's permutations in every block, and the
// keys' hashes of several permutations then overlap.
inline IndexPermutation::IndexPermutation(uint32_t n, const Keys& keys)
    : n_(n), mask_(maskOf(n)), k0_(keys.k0), k1_(keys.k1), k2_(keys.k2) {}

inline uint32_t IndexPermutation::operator()(uint32_t i) const {
    if (n_ <= 1) return 0;
    // Cycle-walking keeps the result inside [0, n) while preserving bijectivity.
    do {
        i = step(i, mask_, k0_, k1_, k2_);
    } while (i >= n_);
    return i;
}

namespace detail {
// A hash of (i, p) to [0, 1), for the jitter within a cell.
inline float jitter(uint32_t i, uint32_t p) { return toUnitFloat(mix64((uint64_t(p) << 32) ^ i ^ 0x5bd1e995ULL)); }

// A set's pattern times these gives its permutations' and jitters' patterns
// (MultiJitterSet and MultiJitterLanes derive them alike).
inline constexpr uint32_t kCellSalt = 0x51633e2dU, kColSalt = 0xa511e9b3U, kRowSalt = 0x63d83595U;
inline constexpr uint32_t kJitterXSalt = 0xa399d265U, kJitterYSalt = 0x711ad6a5U;

}  // namespace detail

/// Element i of the permutation of [0, n) with pattern p.
inline uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t p) { return IndexPermutation(n, p)(i); }

/// Grid shape for a set of n samples: cols x rows >= n, as square as possible,
/// with cols * rows == n whenever n is a perfect square.
struct MjGrid {
    uint32_t cols, rows;
};
MjGrid mjGrid(uint32_t n);

/// One n-sample correlated multi-jittered set. Construct it once per set (per
/// pixel, per shading point and light); sample(s) is then cheap.
class MultiJitterSet {
public:
    /// tabulate: write the column and row permutations out as tables (m + k
    /// evaluations, for grids of at most kMaxTable columns and rows), for a
    /// set that will draw many samples: a permutation's cycle-walking loop
    /// takes a data-dependent number of rounds, a mispredicted branch on
    /// most samples, where a table lookup takes none. Same samples either way.
    MultiJitterSet(uint32_t n, uint32_t pattern, bool tabulate = false) : MultiJitterSet(n, mjGrid(n), pattern, tabulate) {}
    /// The same set with its grid given: grid must be mjGrid(n), worked out
    /// once for the many sets of one size (the renderer's pixels).
    MultiJitterSet(uint32_t n, const MjGrid& grid, uint32_t pattern, bool tabulate);
    /// Sample s (0 <= s < n) in [0,1)^2.
    Vec2f sample(uint32_t s) const;
    uint32_t size() const { return n_; }
    static constexpr uint32_t kMaxTable = 64;  // up to 4096 samples

private:
    uint32_t n_, m_, k_, pattern_;
    float invM_, invK_;
    IndexPermutation cells_;  // chooses which n of the m*k cells are used (n not m*k)
    IndexPermutation cols_, rows_;
    bool tabulated_ = false;
    uint8_t colTable_[kMaxTable], rowTable_[kMaxTable];  // cols_(c), rows_(r) when tabulated_
};

inline Vec2f MultiJitterSet::sample(uint32_t s) const {
    if (m_ * k_ != n_) s = cells_(s);
    const uint32_t col = s % m_, row = s / m_;
    const uint32_t sx = tabulated_ ? colTable_[col] : cols_(col);
    const uint32_t sy = tabulated_ ? rowTable_[row] : rows_(row);
    const float jx = detail::jitter(s, pattern_ * detail::kJitterXSalt);
    const float jy = detail::jitter(s, pattern_ * detail::kJitterYSalt);
    Vec2f r{(static_cast<float>(col) + (static_cast<float>(sy) + jx) * invK_) * invM_,
            (static_cast<float>(row) + (static_cast<float>(sx) + jy) * invM_) * invK_};
    // Guard against rounding to exactly 1.
    r.x = std::min(r.x, 0x1.fffffep-1f);
    r.y = std::min(r.y, 0x1.fffffep-1f);
    return r;
}

/// Sample s of the n-sample set with pattern p (builds the set; prefer
/// MultiJitterSet when drawing several samples of one set).
inline Vec2f multiJitter2D(uint32_t s, uint32_t n, uint32_t p) { return MultiJitterSet(n, p).sample(s); }

/// Pattern id for one set of samples: scrambles per (seed, pixel, set, dimension).
uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension);

/// The renderer's sample keys. A pixel's key is a hash of (seed, pixel),
/// computed once per pixel; every pattern and point of that pixel's camera
/// samples is then one mix64 of (key, camera sample index, dimension), so the
/// per-shading-point cost of a sample set is a hash, not a constructor.
inline uint64_t pixelSampleKey(uint64_t seed, uint64_t pixel) { return hashValues({seed, pixel, 0x5eedULL}); }

/// Pattern id of the set that camera sample `set` of the pixel with key
/// `pixelKey` uses in `dimension` (one mix64).
inline uint32_t setPattern(uint64_t pixelKey, uint32_t set, uint32_t dimension) {
    return static_cast<uint32_t>(mix64(pixelKey ^ ((uint64_t(set) << 32 | dimension) * 0x9e3779b97f4a7c15ULL)) >> 32);
}

/// The one-sample set of (pixelKey, set, dimension): a uniform point in
/// [0,1)^2 from a single mix64 (24 bits per coordinate). A one-point
/// multi-jittered set is exactly that, so no set is constructed for it.
inline Vec2f hashPoint2D(uint64_t pixelKey, uint32_t set, uint32_t dimension) {
    const uint64_t h = mix64(pixelKey ^ ((uint64_t(set) << 32 | dimension) * 0xd1b54a32d192ed03ULL));
    return {static_cast<float>(h >> 40) * (1.f / 16777216.f),
            static_cast<float>((h >> 8) & 0xffffffULL) * (1.f / 16777216.f)};
}

}  // namespace penumbra
