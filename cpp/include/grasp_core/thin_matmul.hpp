// Thin matrix products: many points (M x K, K small) times a few axes (K x N), on the calling
// thread, each element summed in one fixed order — out[i][j] = (a[i][0] b[0][j] +
// a[i][1] b[1][j]) + ... in the operands' precision, with no fused multiply-add (this file's
// object is compiled with -ffp-contract=off) — so the result is the same on every machine and
// for every thread count, unlike a BLAS call whose kernel and blocking depend on both.
#pragma once

#include <cstddef>

namespace grasp_core {

/// out (M x N, row-major) = a (M x K, row-major) times b (K x N, row-major), K >= 1.
template <typename T>
void thin_matmul(std::size_t m, std::size_t k, std::size_t n, const T* a, const T* b, T* out);

}  // namespace grasp_core
