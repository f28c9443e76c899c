#include "grasp_core/thin_matmul.hpp"

namespace grasp_core {

template <typename T>
void thin_matmul(std::size_t m, std::size_t k, std::size_t n, const T* a, const T* b, T* out) {
  for (std::size_t i = 0; i < m; ++i) {
    const T* ai = a + i * k;
    T* oi = out + i * n;
    const T a0 = ai[0];
    for (std::size_t j = 0; j < n; ++j) oi[j] = a0 * b[j];
    for (std::size_t p = 1; p < k; ++p) {
      const T ap = ai[p];
      const T* bp = b + p * n;
      for (std::size_t j = 0; j < n; ++j) oi[j] = oi[j] + ap * bp[j];
    }
  }
}

template void thin_matmul<float>(std::size_t, std::size_t, std::size_t, const float*, const float*, float*);
template void thin_matmul<double>(std::size_t, std::size_t, std::size_t, const double*, const double*,
                                  double*);

}  // namespace grasp_core
