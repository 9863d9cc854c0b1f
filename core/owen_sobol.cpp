#include "core/owen_sobol.h"

#include "core/lane_clones.h"

namespace penumbra {

PENUMBRA_LANE_CLONES void OwenSobol2D::pointLanes(const uint64_t (&keys)[kLanes], const uint32_t (&indices)[kLanes],
                                                  uint32_t n, const uint32_t (&ks)[kLanes], float (&x)[kLanes],
                                                  float (&y)[kLanes]) {
    // The constructor and samplePoints() written out for one point per lane:
    // every step one operation over all lanes. n is the same for all lanes,
    // so the choice between blockPoints and point() is taken once.
    alignas(64) uint32_t shuffled[kLanes], scrambleX[kLanes], scrambleY[kLanes];
    alignas(64) uint32_t shuffle[kLanes];
    for (int l = 0; l < kLanes; ++l) {
        const uint64_t h = mix64(keys[l] ^ kKeySalt), g = mix64(h ^ kSecondSalt);
        shuffle[l] = static_cast<uint32_t>(h);
        scrambleX[l] = static_cast<uint32_t>(h >> 32);
        scrambleY[l] = static_cast<uint32_t>(g);
    }
    if (std::has_single_bit(n)) {
        // blockPoints: the block's place shuffled, the sample's place in it as it is.
        const uint32_t log2n = uint32_t(std::countr_zero(n));
        const uint32_t low = log2n >= 32 ? ~0u : (1u << log2n) - 1u;
        for (int l = 0; l < kLanes; ++l)
            shuffled[l] = (shuffleBySwaps(log2n >= 32 ? 0u : indices[l] << log2n, shuffle[l]) & ~low) | (ks[l] & low);
    } else {
        for (int l = 0; l < kLanes; ++l) shuffled[l] = shuffleBySwaps(indices[l] * n + ks[l], shuffle[l]);
    }
    for (int l = 0; l < kLanes; ++l) shuffledPointBySwaps(shuffled[l], scrambleX[l], scrambleY[l], x[l], y[l]);
}

PENUMBRA_LANE_CLONES void OwenSobol2D::samplePointLanes(uint32_t index, uint32_t n, uint32_t first, float (&x)[kLanes],
                                                        float (&y)[kLanes]) const {
    // samplePoints: where n is a power of two, blockPoints (the block's place
    // shuffled once); else point() for each.
    alignas(64) uint32_t shuffled[kLanes];
    if (std::has_single_bit(n)) {
        const uint32_t log2n = uint32_t(std::countr_zero(n));
        const uint32_t low = log2n >= 32 ? ~0u : (1u << log2n) - 1u;
        const uint32_t base = detail::owenScramble(log2n >= 32 ? 0u : index << log2n, shuffle_) & ~low;
        static_assert(kLanes == 16, "kSobolSecondOfLane holds 16 lanes");
        if (low >= uint32_t(kLanes - 1) && first % uint32_t(kLanes) == 0) {
            // The 16 lanes are high | k, k < 16, with high's low four bits clear.
            // Sobol's matrix is linear over GF(2), so the second dimension of
            // high | k is that of high xor that of k: one evaluation for all
            // lanes, and a constant per lane.
            const uint32_t high = base | (first & low);
            const uint32_t sobolHigh = detail::sobolSecondReversedByShifts(high);
            for (int k = 0; k < kLanes; ++k)
                shuffledPointFromSobol(high | uint32_t(k), sobolHigh ^ detail::kSobolSecondOfLane.v[k], scrambleX_,
                                       scrambleY_, x[k], y[k]);
            return;
        }
        for (int k = 0; k < kLanes; ++k) shuffled[k] = base | ((first + uint32_t(k)) & low);
    } else {
        for (int k = 0; k < kLanes; ++k) shuffled[k] = shuffleBySwaps(index * n + first + uint32_t(k), shuffle_);
    }
    for (int k = 0; k < kLanes; ++k) shuffledPointBySwaps(shuffled[k], scrambleX_, scrambleY_, x[k], y[k]);
}

}  // namespace penumbra
