// Correlated multi-jittered sampling (Kensler 2013), a table-free form of
// multi-jittered sampling (Chiu, Shirley & Wang 1994): n = m x k points that
// are jittered in an m x k grid and, at the same time, stratified into n
// strata in each 1D projection (n-rooks). Sample s of the set with pattern p
// is computed on its own, without generating the rest of the set.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace penumbra {

/// Pseudo-random permutation of [0, n): element i of the permutation with
/// pattern p. A bijection on [0, 2^w) built from invertible steps, applied by
/// cycle-walking until the value falls below n.
uint32_t permuteIndex(uint32_t i, uint32_t n, uint32_t p);

/// Grid shape for a set of n samples: cols x rows >= n, as square as possible,
/// with cols * rows == n whenever n is a perfect square.
struct MjGrid {
    uint32_t cols, rows;
};
MjGrid mjGrid(uint32_t n);

/// Sample s (0 <= s < n) of the n-sample correlated multi-jittered set with
/// pattern p, in [0,1)^2.
Vec2f multiJitter2D(uint32_t s, uint32_t n, uint32_t p);

/// Pattern id for one set of samples: scrambles per (seed, pixel, set, dimension).
uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension);

}  // namespace penumbra
