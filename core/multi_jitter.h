// Correlated multi-jittered sampling (Kensler 2013), a table-free form of
// multi-jittered sampling (Chiu, Shirley & Wang 1994): n = m x k points that
// are jittered in an m x k grid and, at the same time, stratified into n
// strata in each 1D projection (n-rooks). Sample s of the set with pattern p
// is computed on its own, without generating the rest of the set.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace penumbra {

/// A pseudo-random permutation of [0, n) chosen by a pattern id: a bijection
/// on [0, 2^w) built from invertible steps, applied by cycle-walking until the
/// value falls below n. The keys are derived once, when it is constructed.
class IndexPermutation {
public:
    IndexPermutation() = default;
    IndexPermutation(uint32_t n, uint32_t pattern);
    uint32_t operator()(uint32_t i) const;

private:
    uint32_t n_ = 1, mask_ = 0, k0_ = 0, k1_ = 1, k2_ = 0;
};

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
    MultiJitterSet(uint32_t n, uint32_t pattern);
    /// Sample s (0 <= s < n) in [0,1)^2.
    Vec2f sample(uint32_t s) const;
    uint32_t size() const { return n_; }

private:
    uint32_t n_, m_, k_, pattern_;
    float invM_, invK_;
    IndexPermutation cells_;  // chooses which n of the m*k cells are used (n not m*k)
    IndexPermutation cols_, rows_;
};

/// Sample s of the n-sample set with pattern p (builds the set; prefer
/// MultiJitterSet when drawing several samples of one set).
inline Vec2f multiJitter2D(uint32_t s, uint32_t n, uint32_t p) { return MultiJitterSet(n, p).sample(s); }

/// Pattern id for one set of samples: scrambles per (seed, pixel, set, dimension).
uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension);

}  // namespace penumbra
