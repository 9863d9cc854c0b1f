// The 2D sample sequence of the integrators: the first two Sobol dimensions,
// a (0,2)-sequence, with hash-based nested uniform (Owen) scrambling
// (Burley 2020, "Practical Hash-based Owen Scrambling").
//
// Why a sequence and not a set per shading point: a (0,2)-sequence is a
// progressive multi-jittered sequence (Christensen, Kensler & Kilpatrick
// 2018). Every aligned block of 2^k consecutive points is a (0,k,2)-net,
// stratified in every 2^a x 2^b grid with a + b = k: a multi-jittered set of
// its own (jittered in the square grid when k is even, n-rooks in x and y).
// A pixel draws light sample k of camera sample s as point s*n + k of its
// sequence: each shading point's n samples form one such block (stratified
// per shading point, as before), and all spp*n samples of the pixel are one
// larger net, stratified across the camera samples too. With one light
// sample and many camera samples that is the difference between spp
// independent points on a light and spp stratified ones.
//
// Owen scrambling keeps the nets and makes every point uniform on its own,
// so estimators stay unbiased; the index is also scrambled (within the block
// structure) per sequence, so that the sequences of different dimensions of
// one pixel are not correlated point by point.
#pragma once

#include <bit>
#include <cstdint>

#include "core/hash.h"
#include "core/math.h"

namespace penumbra {

namespace detail {

// Bit reversal by bytes through a 256-entry table: four loads instead of a
// byte swap and three mask-and-shift rounds, faster per point, the same values.
struct ByteReverseTable {
    uint8_t t[256];
    constexpr ByteReverseTable() : t{} {
        for (uint32_t x = 0; x < 256; ++x) {
            uint32_t r = 0;
            for (int k = 0; k < 8; ++k) r |= ((x >> k) & 1U) << (7 - k);
            t[x] = static_cast<uint8_t>(r);
        }
    }
};
inline constexpr ByteReverseTable kByteReverse{};

inline uint32_t reverseBits(uint32_t x) {
    const uint8_t* t = kByteReverse.t;
    return uint32_t(t[x & 0xffU]) << 24 | uint32_t(t[(x >> 8) & 0xffU]) << 16 | uint32_t(t[(x >> 16) & 0xffU]) << 8 |
           uint32_t(t[x >> 24]);
}

/// reverseBits by swapping ever larger groups of bits: the same values, and
/// in a loop over lanes it vectorises (a table lookup per byte would not;
/// one value at a time, the table is faster).
inline uint32_t reverseBitsBySwaps(uint32_t x) {
    x = ((x >> 1) & 0x55555555U) | ((x & 0x55555555U) << 1);
    x = ((x >> 2) & 0x33333333U) | ((x & 0x33333333U) << 2);
    x = ((x >> 4) & 0x0f0f0f0fU) | ((x & 0x0f0f0f0fU) << 4);
    x = ((x >> 8) & 0x00ff00ffU) | ((x & 0x00ff00ffU) << 8);
    return (x >> 16) | (x << 16);
}

// A random permutation of 32-bit values in which each bit is flipped as a
// function of the bits below it only (carries and multiplication by even
// constants move information upwards): applied to bit-reversed values it is
// a nested uniform scramble. Constants: the Laine-Karras construction with
// Vegdahl's mixing constants.
inline uint32_t upwardHash(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cU;
    x ^= x * 0xb82f1e52U;
    x ^= x * 0xc7afe638U;
    x ^= x * 0x8d22f6e6U;
    return x;
}

/// Owen scramble of a 0.32 fixed-point value: each bit is flipped by a hash
/// of the bits above it.
inline uint32_t owenScramble(uint32_t x, uint32_t seed) { return reverseBits(upwardHash(reverseBits(x), seed)); }

// Second Sobol dimension (generator matrix: Pascal's triangle mod 2), bit
// reversed (scrambling works on reversed values), one table of 256 entries
// per byte of the index: column j of the matrix is v_0 = 2^31,
// v_{j+1} = v_j ^ (v_j >> 1).
struct SobolSecondTable {
    uint32_t t[4][256];
    constexpr SobolSecondTable() : t{} {
        uint32_t v[32] = {};
        v[0] = 0x80000000U;
        for (int j = 1; j < 32; ++j) v[j] = v[j - 1] ^ (v[j - 1] >> 1);
        for (int b = 0; b < 4; ++b)
            for (uint32_t x = 0; x < 256; ++x) {
                uint32_t y = 0;
                for (int bit = 0; bit < 8; ++bit)
                    if (x >> bit & 1U) y ^= v[8 * b + bit];
                uint32_t r = 0;  // reverseBits, spelled out for constexpr
                for (int k = 0; k < 32; ++k) r |= ((y >> k) & 1U) << (31 - k);
                t[b][x] = r;
            }
    }
};
inline constexpr SobolSecondTable kSobolSecondReversed{};

/// Second Sobol dimension of index i, bit-reversed: reverseBits of the 0.32
/// fixed-point value. (The first dimension, reversed, is i itself.)
inline uint32_t sobolSecondReversed(uint32_t i) {
    const auto& t = kSobolSecondReversed.t;
    return t[0][i & 0xffU] ^ t[1][(i >> 8) & 0xffU] ^ t[2][(i >> 16) & 0xffU] ^ t[3][i >> 24];
}

/// sobolSecondReversed by five shifts and xors: the same values, and a loop
/// over lanes of it vectorises (table lookups would be taken lane by lane).
/// Column j of the matrix (Pascal's triangle mod 2, Lucas' theorem) has bit k
/// of the reversed value set where k's bits are a subset of j's, so bit k of
/// the result is the xor of the index bits j that hold k: a sum over
/// supersets, taken one bit of the bit position at a time: 15 operations
/// where an xor of the 32 columns took about 130.
constexpr uint32_t sobolSecondReversedByShifts(uint32_t i) {
    i ^= (i >> 1) & 0x55555555U;
    i ^= (i >> 2) & 0x33333333U;
    i ^= (i >> 4) & 0x0f0f0f0fU;
    i ^= (i >> 8) & 0x00ff00ffU;
    i ^= i >> 16;
    return i;
}

/// sobolSecondReversed(k) for k = 0 .. 15: the lanes' share of a block's points.
struct SobolSecondOfSixteen {
    uint32_t v[16];
    constexpr SobolSecondOfSixteen() : v{} {
        for (uint32_t k = 0; k < 16; ++k) v[k] = sobolSecondReversedByShifts(k);
    }
};
inline constexpr SobolSecondOfSixteen kSobolSecondOfLane{};

/// Second Sobol dimension of index i, as a 0.32 fixed-point value.
inline uint32_t sobolSecond(uint32_t i) { return reverseBits(sobolSecondReversed(i)); }

/// The top 24 bits of a 0.32 fixed-point value as a float in [0, 1): exact,
/// and at most 1 - 2^-24, so no clamp is needed (the signed conversion is
/// the single instruction; the value fits either way).
inline float fixedToUnit(uint32_t x) { return static_cast<float>(static_cast<int32_t>(x >> 8)) * (1.f / 16777216.f); }

}  // namespace detail

/// One scrambled sequence: a pixel's sequence in one dimension. The key
/// (e.g. the pixel's sample key xor a dimension) chooses the scrambles; a
/// point then costs a few multiplications and table lookups.
class OwenSobol2D {
public:
    explicit OwenSobol2D(uint64_t key) {
        const uint64_t h = mix64(key ^ kKeySalt), g = mix64(h ^ kSecondSalt);
        shuffle_ = static_cast<uint32_t>(h);
        scrambleX_ = static_cast<uint32_t>(h >> 32);
        scrambleY_ = static_cast<uint32_t>(g);
    }

    /// Point `index` of the sequence, in [0,1)^2.
    [[gnu::always_inline]] Vec2f point(uint32_t index) const {
        // Shuffle the index with an Owen scramble of its own bits (each
        // flipped by a hash of the bits above it): each aligned block of 2^k
        // indices maps onto one aligned block, so blocks stay nets.
        // Scrambling works on bit-reversed values, and Sobol's first dimension
        // is the reversed index: owenScramble(reverseBits(i)) is
        // reverseBits(upwardHash(i)).
        return shuffledPoint(detail::owenScramble(index, shuffle_));
    }

    /// Points first .. first + count - 1 (of 2^log2n) of the aligned block of
    /// 2^log2n indices that starts at block * 2^log2n: together, the block's
    /// points exactly as point() gives them, in another order. The index
    /// shuffle maps an aligned block onto an aligned block, so the block's
    /// place is shuffled once and its points then skip the shuffle (about a
    /// third of a point's cost). For estimators that sum a whole block.
    void blockPoints(uint32_t block, uint32_t log2n, uint32_t first, uint32_t count, Vec2f* out) const {
        const uint32_t low = log2n >= 32 ? ~0u : (1u << log2n) - 1u;
        const uint32_t base = detail::owenScramble(log2n >= 32 ? 0u : block << log2n, shuffle_) & ~low;
        for (uint32_t k = 0; k < count; ++k) out[k] = shuffledPoint(base | ((first + k) & low));
    }

    /// Points first .. first + count - 1 of the n points that camera sample
    /// `index` draws (indices index * n ..): blockPoints where n is a power of
    /// two, else point() one by one. The n points together are the same
    /// either way; summed over the whole block, so is the estimate.
    void samplePoints(uint32_t index, uint32_t n, uint32_t first, uint32_t count, Vec2f* out) const {
        if (std::has_single_bit(n)) {
            blockPoints(index, uint32_t(std::countr_zero(n)), first, count, out);
            return;
        }
        for (uint32_t k = 0; k < count; ++k) out[k] = point(index * n + first + k);
    }

    /// Sixteen lanes: the points of a batch's lanes or a shading point's samples.
    static constexpr int kLanes = 16;
    /// For each of the 16 lanes: sample ks[l] of the n that camera sample
    /// indices[l] draws from the sequence of keys[l], that is
    /// OwenSobol2D(keys[l]).samplePoints(indices[l], n, ks[l], 1, ...), as
    /// x[l], y[l]: the same values, as loops over the lanes
    /// (core/owen_sobol.cpp). With n = 1 and every ks[l] = 0 it is
    /// point(indices[l]): a batch's lanes, one sample each. Always all 16 (a
    /// fixed count leaves no lanes to a scalar tail): fill the lanes not
    /// needed with anything.
    static void pointLanes(const uint64_t (&keys)[kLanes], const uint32_t (&indices)[kLanes], uint32_t n,
                           const uint32_t (&ks)[kLanes], float (&x)[kLanes], float (&y)[kLanes]);
    /// samplePoints(index, n, first, 16, ...) as arrays: the same values, as
    /// loops over the 16 points (those past the n points are not to be used).
    void samplePointLanes(uint32_t index, uint32_t n, uint32_t first, float (&x)[kLanes], float (&y)[kLanes]) const;

private:
    static constexpr uint64_t kKeySalt = 0x3c6ef372fe94f82bULL, kSecondSalt = 0xa54ff53a5f1d36f1ULL;

    // The point of shuffled index i.
    [[gnu::always_inline]] Vec2f shuffledPoint(uint32_t i) const {
        const uint32_t x = detail::reverseBits(detail::upwardHash(i, scrambleX_));
        const uint32_t y = detail::reverseBits(detail::upwardHash(detail::sobolSecondReversed(i), scrambleY_));
        return {detail::fixedToUnit(x), detail::fixedToUnit(y)};
    }

    // shuffledPoint with the bit reversals by swaps and Sobol's second
    // dimension by shifts (no tables): for loops over lanes, which vectorise.
    [[gnu::always_inline]] static void shuffledPointBySwaps(uint32_t i, uint32_t scrambleX, uint32_t scrambleY,
                                                            float& x, float& y) {
        shuffledPointFromSobol(i, detail::sobolSecondReversedByShifts(i), scrambleX, scrambleY, x, y);
    }
    // The same, given sobolSecondReversed(i).
    [[gnu::always_inline]] static void shuffledPointFromSobol(uint32_t i, uint32_t sobol, uint32_t scrambleX,
                                                              uint32_t scrambleY, float& x, float& y) {
        x = detail::fixedToUnit(detail::reverseBitsBySwaps(detail::upwardHash(i, scrambleX)));
        y = detail::fixedToUnit(detail::reverseBitsBySwaps(detail::upwardHash(sobol, scrambleY)));
    }

    // The shuffled index of point `index` (point()'s shuffle), by swaps.
    [[gnu::always_inline]] static uint32_t shuffleBySwaps(uint32_t index, uint32_t shuffle) {
        return detail::reverseBitsBySwaps(detail::upwardHash(detail::reverseBitsBySwaps(index), shuffle));
    }

    uint32_t shuffle_, scrambleX_, scrambleY_;
};

}  // namespace penumbra
