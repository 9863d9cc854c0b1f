// Sample s of 16 correlated multi-jittered sets of one size at once, one set
// per lane (the renderer's 16 pixels of a block): the same points as
// MultiJitterSet::sample, bit for bit, from one loop over the lanes. Sample s
// falls in the same grid cell (column, row) of every set, so what differs
// between lanes is a table look-up at one index (tables stored index-major:
// the 16 lanes' entries side by side) and the jitter's hash.
#pragma once

#include <cstdint>

#include "core/multi_jitter.h"

namespace penumbra {

class MultiJitterLanes {
public:
    static constexpr int kLanes = 16;

    /// Whether sets of n samples can be drawn as lanes: their grid holds
    /// exactly n cells (no cell permutation) and its permutations fit the
    /// tables. Where not, draw each set with MultiJitterSet.
    static bool supports(uint32_t n);

    /// Lanes for sets of n samples (supports(n) must hold); set each lane's
    /// pattern before drawing.
    explicit MultiJitterLanes(uint32_t n);

    /// Lane l draws from the set MultiJitterSet(n, pattern).
    void setLane(int l, uint32_t pattern);
    /// setLane(l, patterns[l]) for l < count, the patterns' hashes as one loop over the lanes.
    void setLanes(const uint32_t* patterns, int count);

    /// Sample s (0 <= s < n) of every lane's set: (x[l], y[l]) =
    /// MultiJitterSet(n, pattern of lane l).sample(s). Lanes never set give
    /// points of no use, but no fault.
    void sample(uint32_t s, float* x, float* y) const;

private:
    void setLanes(const uint32_t* patterns, int first, int last);

    static constexpr uint32_t kMaxTable = MultiJitterSet::kMaxTable;
    uint32_t m_, k_;
    float invM_, invK_;
    alignas(64) uint64_t jitterX_[kLanes], jitterY_[kLanes];  // the jitter hashes' keys, before the sample index
    alignas(64) uint8_t colTable_[kMaxTable][kLanes], rowTable_[kMaxTable][kLanes];
};

}  // namespace penumbra
