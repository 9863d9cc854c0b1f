#include "core/owen_sobol.h"

#include "core/lane_clones.h"

namespace penumbra {

PENUMBRA_LANE_CLONES void OwenSobol2D::pointLanes(const uint64_t (&keys)[kLanes], const uint32_t (&indices)[kLanes],
                                                  float (&x)[kLanes], float (&y)[kLanes]) {
    // The constructor, point() and shuffledPoint() written out, with the bit
    // reversals by swaps and Sobol's second dimension by columns instead of
    // tables: every step one operation over all lanes.
    for (int l = 0; l < kLanes; ++l) {
        const uint64_t h = mix64(keys[l] ^ kKeySalt), g = mix64(h ^ kSecondSalt);
        const uint32_t shuffle = static_cast<uint32_t>(h), scrambleX = static_cast<uint32_t>(h >> 32),
                       scrambleY = static_cast<uint32_t>(g);
        const uint32_t i =
            detail::reverseBitsBySwaps(detail::upwardHash(detail::reverseBitsBySwaps(indices[l]), shuffle));
        const uint32_t bx = detail::reverseBitsBySwaps(detail::upwardHash(i, scrambleX));
        const uint32_t by =
            detail::reverseBitsBySwaps(detail::upwardHash(detail::sobolSecondReversedByColumns(i), scrambleY));
        x[l] = detail::fixedToUnit(bx);
        y[l] = detail::fixedToUnit(by);
    }
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
        for (int k = 0; k < kLanes; ++k) shuffled[k] = base | ((first + uint32_t(k)) & low);
    } else {
        for (int k = 0; k < kLanes; ++k)
            shuffled[k] = detail::reverseBitsBySwaps(
                detail::upwardHash(detail::reverseBitsBySwaps(index * n + first + uint32_t(k)), shuffle_));
    }
    for (int k = 0; k < kLanes; ++k) {
        const uint32_t i = shuffled[k];
        x[k] = detail::fixedToUnit(detail::reverseBitsBySwaps(detail::upwardHash(i, scrambleX_)));
        y[k] = detail::fixedToUnit(
            detail::reverseBitsBySwaps(detail::upwardHash(detail::sobolSecondReversedByColumns(i), scrambleY_)));
    }
}

}  // namespace penumbra
