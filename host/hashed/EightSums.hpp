#pragma once
// The 8-bit mask of the sums (x[i] + y[j]) + z[k] < r2 over i, j, k in {0, 1},
// bit i + 2j + 4k: which of a 2x2x2 block of cells (or of a cell's octants) a
// sphere reaches, from per-axis squared gaps. Every caller's coverage test is
// these sums in this order, so that masks computed in different places agree
// bit for bit (IEEE additions; no contraction, since no FMA is involved).
// Hand-vectorised because dynamic updates evaluate it for every cell on the
// moved lights' surfaces (twice) and compilers keep the 8 compares scalar.
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ml::hashed {

inline std::uint8_t eightSumsBelow(const double* x, const double* y, const double* z, double r2) {
#if defined(__SSE2__)
  const __m128d xs = _mm_loadu_pd(x);
  const __m128d xy0 = _mm_add_pd(xs, _mm_set1_pd(y[0]));  // (x0 + y0, x1 + y0): bits 0, 1
  const __m128d xy1 = _mm_add_pd(xs, _mm_set1_pd(y[1]));  // bits 2, 3
  const __m128d z0 = _mm_set1_pd(z[0]), z1 = _mm_set1_pd(z[1]), r = _mm_set1_pd(r2);
  const int m = _mm_movemask_pd(_mm_cmplt_pd(_mm_add_pd(xy0, z0), r)) |
                (_mm_movemask_pd(_mm_cmplt_pd(_mm_add_pd(xy1, z0), r)) << 2) |
                (_mm_movemask_pd(_mm_cmplt_pd(_mm_add_pd(xy0, z1), r)) << 4) |
                (_mm_movemask_pd(_mm_cmplt_pd(_mm_add_pd(xy1, z1), r)) << 6);
  return std::uint8_t(m);
#else
  const double xy[4] = {x[0] + y[0], x[1] + y[0], x[0] + y[1], x[1] + y[1]};
  unsigned m = 0;
  for (unsigned k = 0; k < 8; ++k) m |= unsigned(xy[k & 3] + z[k >> 2] < r2) << k;
  return std::uint8_t(m);
#endif
}

}  // namespace ml::hashed
