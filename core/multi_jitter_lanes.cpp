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
    const uint32_t zeros[kLanes] = {};
    setLanes(zeros, kLanes);
}

void MultiJitterLanes::setLane(int l, uint32_t p) { setLanes(&p, l, l + 1); }

void MultiJitterLanes::setLanes(const uint32_t* patterns, int count) { setLanes(patterns, 0, count); }

namespace {

// table[i][first + l] = IndexPermutation(size, {k0[l], k1[l], k2[l]})(i) for
// i < size and l < n, one row (one i, every lane) at a time as loops over the
// lanes: each lane takes the walk's steps until its value falls inside
// [0, size); one that is inside already keeps it. The same values as
// IndexPermutation, which walks one lane's cycle at a time.
[[gnu::always_inline]] inline void permutationRows(uint32_t size, const uint32_t* k0, const uint32_t* k1,
                                                   const uint32_t* k2, int first, int n,
                                                   uint8_t (*table)[MultiJitterLanes::kLanes]) {
    const uint32_t mask = IndexPermutation::maskOf(size);
    for (uint32_t i = 0; i < size; ++i) {
        alignas(64) uint32_t x[MultiJitterLanes::kLanes];
        uint32_t outside = 0;
        for (int l = 0; l < n; ++l) {
            x[l] = size <= 1 ? 0 : IndexPermutation::step(i, mask, k0[l], k1[l], k2[l]);
            outside |= uint32_t(x[l] >= size);
        }
        while (outside) {
            outside = 0;
            for (int l = 0; l < n; ++l) {
                x[l] = x[l] < size ? x[l] : IndexPermutation::step(x[l], mask, k0[l], k1[l], k2[l]);
                outside |= uint32_t(x[l] >= size);
            }
        }
        for (int l = 0; l < n; ++l) table[i][first + l] = static_cast<uint8_t>(x[l]);
    }
}

}  // namespace

// Lanes first..last-1 from patterns[0..last-first): the hashes as loops over
// the lanes, then the tables a row at a time.
PENUMBRA_LANE_CLONES void MultiJitterLanes::setLanes(const uint32_t* patterns, int first, int last) {
    alignas(64) uint32_t c0[kLanes], c1[kLanes], c2[kLanes], r0[kLanes], r1[kLanes], r2[kLanes];
    const int n = last - first;
    for (int i = 0; i < n; ++i) {
        const uint32_t p = patterns[i];
        // detail::jitter(s, p * salt) is mix64 of this key xor s.
        jitterX_[first + i] = (uint64_t(p * detail::kJitterXSalt) << 32) ^ 0x5bd1e995ULL;
        jitterY_[first + i] = (uint64_t(p * detail::kJitterYSalt) << 32) ^ 0x5bd1e995ULL;
        const IndexPermutation::Keys c = IndexPermutation::keysOf(p * detail::kColSalt);
        const IndexPermutation::Keys r = IndexPermutation::keysOf(p * detail::kRowSalt);
        c0[i] = c.k0;
        c1[i] = c.k1;
        c2[i] = c.k2;
        r0[i] = r.k0;
        r1[i] = r.k1;
        r2[i] = r.k2;
    }
    permutationRows(m_, c0, c1, c2, first, n, colTable_);
    permutationRows(k_, r0, r1, r2, first, n, rowTable_);
}

PENUMBRA_LANE_CLONES void MultiJitterLanes::sample(uint32_t s, float* x, float* y) const {
    // MultiJitterSet::sample with the cell (col, row) common to all lanes.
    const uint32_t col = s % m_, row = s / m_;
    const float fc = static_cast<float>(col), fr = static_cast<float>(row);
    const float invM = invM_, invK = invK_;
    const uint8_t* sxs = colTable_[col];
    const uint8_t* sys = rowTable_[row];
    // The hashes' top 24 bits first, as a loop of 64-bit lanes alone: mixed
    // with the float and byte lanes below in one loop, GCC vectorised it two
    // lanes at a time.
    alignas(64) uint32_t hx[kLanes], hy[kLanes];
    for (int l = 0; l < kLanes; ++l) {
        hx[l] = static_cast<uint32_t>(mix64(jitterX_[l] ^ s) >> 40);
        hy[l] = static_cast<uint32_t>(mix64(jitterY_[l] ^ s) >> 40);
    }
    for (int l = 0; l < kLanes; ++l) {
        // toUnitFloat of the hashes: exact either way (24 bits).
        const float jx = static_cast<float>(static_cast<int32_t>(hx[l])) * (1.f / 16777216.f);
        const float jy = static_cast<float>(static_cast<int32_t>(hy[l])) * (1.f / 16777216.f);
        const float rx = (fc + (static_cast<float>(sys[l]) + jx) * invK) * invM;
        const float ry = (fr + (static_cast<float>(sxs[l]) + jy) * invM) * invK;
        x[l] = 0x1.fffffep-1f < rx ? 0x1.fffffep-1f : rx;  // std::min(rx, 0x1.fffffep-1f), as sample() takes it
        y[l] = 0x1.fffffep-1f < ry ? 0x1.fffffep-1f : ry;
    }
}

}  // namespace penumbra
