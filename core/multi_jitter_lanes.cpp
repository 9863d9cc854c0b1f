#include "core/multi_jitter_lanes.h"

#include "core/lane_clones.h"

namespace penumbra {

bool MultiJitterLanes::supports(uint32_t n) {
    const MjGrid g = mjGrid(n);
    return n > 0 && g.cols * g.rows == n && g.cols <= kMaxTable && g.rows <= kMaxTable;
}

MultiJitterLanes::MultiJitterLanes(uint32_t n) {
    const MjGrid g = mjGrid(n);
    m_ = g.cols;
    k_ = g.rows;
    invM_ = 1.f / static_cast<float>(m_);
    invK_ = 1.f / static_cast<float>(k_);
    for (int l = 0; l < kLanes; ++l) setLane(l, 0);
}

void MultiJitterLanes::setLane(int l, uint32_t p) {
    // detail::jitter(s, p * salt) is mix64 of this key xor s.
    jitterX_[l] = (uint64_t(p * detail::kJitterXSalt) << 32) ^ 0x5bd1e995ULL;
    jitterY_[l] = (uint64_t(p * detail::kJitterYSalt) << 32) ^ 0x5bd1e995ULL;
    const IndexPermutation cols(m_, p * detail::kColSalt), rows(k_, p * detail::kRowSalt);
    for (uint32_t c = 0; c < m_; ++c) colTable_[c][l] = static_cast<uint8_t>(cols(c));
    for (uint32_t r = 0; r < k_; ++r) rowTable_[r][l] = static_cast<uint8_t>(rows(r));
}

PENUMBRA_LANE_CLONES void MultiJitterLanes::sample(uint32_t s, float* x, float* y) const {
    // MultiJitterSet::sample with the cell (col, row) common to all lanes.
    const uint32_t col = s % m_, row = s / m_;
    const float fc = static_cast<float>(col), fr = static_cast<float>(row);
    const float invM = invM_, invK = invK_;
    const uint8_t* sxs = colTable_[col];
    const uint8_t* sys = rowTable_[row];
    for (int l = 0; l < kLanes; ++l) {
        const float jx = toUnitFloat(mix64(jitterX_[l] ^ s));
        const float jy = toUnitFloat(mix64(jitterY_[l] ^ s));
        const float rx = (fc + (static_cast<float>(sys[l]) + jx) * invK) * invM;
        const float ry = (fr + (static_cast<float>(sxs[l]) + jy) * invM) * invK;
        x[l] = 0x1.fffffep-1f < rx ? 0x1.fffffep-1f : rx;  // std::min(rx, 0x1.fffffep-1f), as sample() takes it
        y[l] = 0x1.fffffep-1f < ry ? 0x1.fffffep-1f : ry;
    }
}

}  // namespace penumbra
