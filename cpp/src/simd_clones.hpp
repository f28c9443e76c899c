// (ours) Function multi-versioning for the loops over whole frames.
//
// A function marked GRASP_SIMD_CLONES is compiled twice, for AVX2 and for the baseline
// x86-64 (SSE2), and the dynamic loader picks the clone the CPU supports (GCC
// target_clones). The clones perform the same IEEE float operations in the same order
// (-mavx2 does not enable FMA contraction), so they give bit-identical results; the AVX2
// clone handles 8 floats per instruction instead of 4. On other compilers/architectures the
// macro is empty and the plain build is used.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GRASP_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GRASP_SIMD_CLONES
#endif
