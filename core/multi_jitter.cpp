#include "core/multi_jitter.h"

#include <cmath>

#include "core/hash.h"

namespace penumbra {
MjGrid mjGrid(uint32_t n) {
    uint32_t cols = static_cast<uint32_t>(std::sqrt(static_cast<double>(n)));
    if (cols == 0) cols = 1;
    uint32_t rows = (n + cols - 1) / cols;
    return {cols, rows};
}

MultiJitterSet::MultiJitterSet(uint32_t n, const MjGrid& g, uint32_t p, bool tabulate) : n_(n), pattern_(p) {
    m_ = g.cols;
    k_ = g.rows;
    invM_ = 1.f / static_cast<float>(m_);
    invK_ = 1.f / static_cast<float>(k_);
    if (m_ * k_ != n) cells_ = IndexPermutation(m_ * k_, p * detail::kCellSalt);
    // Shuffle the sub-cell offsets of a whole row (resp. column) with one
    // permutation: this is the "correlated" part that keeps the n-rooks
    // property while only needing permutations of length m and k.
    cols_ = IndexPermutation(m_, p * detail::kColSalt);
    rows_ = IndexPermutation(k_, p * detail::kRowSalt);
    if (tabulate && m_ <= kMaxTable && k_ <= kMaxTable) {
        for (uint32_t c = 0; c < m_; ++c) colTable_[c] = static_cast<uint8_t>(cols_(c));
        for (uint32_t r = 0; r < k_; ++r) rowTable_[r] = static_cast<uint8_t>(rows_(r));
        tabulated_ = true;
    }
}

uint32_t mjPattern(uint64_t seed, uint64_t pixel, uint64_t set, uint64_t dimension) {
    return static_cast<uint32_t>(hashValues({seed, pixel, set, dimension}));
}

}  // namespace penumbra
