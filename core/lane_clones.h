// Loops over the lanes of a batch (structure of arrays) are compiled three
// times: for AVX-512 (x86-64-v4), for AVX2 (x86-64-v3) and for the x86-64
// baseline (SSE2), and the dynamic loader binds each call to the widest copy
// the CPU runs (GCC's target_clones, an ifunc). The library itself stays a
// baseline x86-64 build that runs everywhere; a 16-lane loop is then one or
// two vector steps instead of four. Every copy gives the same values: no
// fast-math, and no fused multiply-add (-ffp-contract=off, cmake/PenumbraWarnings.cmake).
// The sanitizer build keeps the baseline copy only, so that one is tested too.
//
// The same copies serve the render loop's few large functions that run once
// per 16-ray batch (a block's camera samples, the batch's shading and direct
// light, the packet queries): their small loops over a batch and the inline
// helpers they pull in compile to AVX code there, which the baseline build
// cannot use. Only large functions: a call to a copy goes through the
// dispatcher and cannot be inlined, which costs small functions (the shapes'
// completeHit) what their wider code gains.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_LANE_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define PENUMBRA_LANE_CLONES
#endif
