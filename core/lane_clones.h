// Loops over the lanes of a batch (structure of arrays) are compiled three
// times: for AVX-512 (x86-64-v4), for AVX2 (x86-64-v3) and for the x86-64
// baseline (SSE2), and the dynamic loader binds each call to the widest copy
// the CPU runs (GCC's target_clones, an ifunc). The library itself stays a
// baseline x86-64 build that runs everywhere; a 16-lane loop is then one or
// two vector steps instead of four. Every copy gives the same values: no
// fast-math, and no fused multiply-add (-ffp-contract=off, cmake/PenumbraWarnings.cmake).
// The sanitizer build keeps the baseline copy only, so that one is tested too.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_LANE_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define PENUMBRA_LANE_CLONES
#endif
