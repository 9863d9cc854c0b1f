#include "core/owen_sobol.h"

#include "core/lane_clones.h"

namespace penumbra {

PENUMBRA_LANE_CLONES void OwenSobol2D::pointLanes(const uint64_t* keys, const uint32_t* indices, int n, float* x,
                                                  float* y) {
    // The constructor, point() and shuffledPoint() written out, with the bit
    // reversals by swaps and Sobol's second dimension by columns instead of
    // tables: every step one operation over all lanes.
    for (int l = 0; l < n; ++l) {
        const uint64_t h = mix64(keys[l] ^ kKeySalt), g = mix64(h ^ kSecondSalt);
        const uint32_t shuffle = static_cast<uint32_t>(h), scrambleX = static_cast<uint32_t>(h >> 32),
                       scrambleY = static_cast<uint32_t>(g);
        const uint32_t i =
            detail::reverseBitsBySwaps(detail::upwardHash(detail::reverseBitsBySwaps(indices[l]), shuffle));
        const uint32_t bx = detail::reverseBitsBySwaps(detail::upwardHash(i, scrambleX));
        const uint32_t by = detail::reverseBitsBySwaps(detail::upwardHash(detail::sobolSecondReversedByColumns(i), scrambleY));
        x[l] = detail::fixedToUnit(bx);
        y[l] = detail::fixedToUnit(by);
    }
}

}  // namespace penumbra
