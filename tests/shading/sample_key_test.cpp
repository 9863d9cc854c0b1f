// The sample keys' lane-wise points: a batch's lanes drawn together give
// each lane the point it draws alone, also in a batch of fewer than 16.
#include <gtest/gtest.h>

#include "core/hash.h"
#include "shading/sample_key.h"

using namespace penumbra;

TEST(SampleKey, DimensionPointLanesAreEachLanesPointBitForBit) {
    for (const size_t n : {size_t(1), size_t(5), size_t(16)}) {
        SampleKey keys[OwenSobol2D::kLanes];
        for (size_t l = 0; l < n; ++l)
            keys[l] = SampleKey{mix64(l * 131 + n), l == 0 ? 0u : uint32_t(mix64(l + 7 * n) >> 37)};
        for (const uint32_t dim : {kFirstLightDimension, VertexDimensions(3, 4).bsdf()}) {
            alignas(64) float x[OwenSobol2D::kLanes], y[OwenSobol2D::kLanes];
            dimensionPointLanes(keys, n, dim, x, y);
            for (size_t l = 0; l < n; ++l) {
                const Vec2f p = dimensionSequence(keys[l], dim).point(keys[l].index);
                EXPECT_EQ(x[l], p.x) << "batch of " << n << ", lane " << l << ", dimension " << dim;
                EXPECT_EQ(y[l], p.y) << "batch of " << n << ", lane " << l << ", dimension " << dim;
            }
        }
    }
}
