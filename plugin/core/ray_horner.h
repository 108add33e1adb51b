#pragma once
// Private building blocks of the direct restriction to a ray (taylor.cpp, taylor_box.cpp):
// nested Horner of f(p + s d) in R[s]. Not installed.
//
// Each step multiplies a univariate polynomial by a linear factor (a + b s) and adds the
// next term. The same steps run on absolute values in the same loops, giving the
// coefficients of |f|(|p| + s |d|), the magnitudes the error bound scales: two independent
// dependency chains, so the second one is nearly free on a pipelined core.
//
// A (value, magnitude) pair is one 2-lane vector (GCC/Clang vector extension): both chains
// advance in one SIMD operation and every load matches the width of the store that wrote
// it. (With separate scalar arrays the compiler vectorised the additions, and 16-byte
// loads of two 8-byte stores defeated store forwarding: a 3x slowdown, found by perf.)
#include <cmath>

namespace algray::ray_horner {

typedef double Pair __attribute__((vector_size(16)));

// A coefficient on both chains.
inline Pair term(double c) { return Pair{c, std::abs(c)}; }

// q <- q * (p + d s) on both chains; q has degree deg >= 0 before the call.
inline void mulLinear(Pair* q, int deg, Pair p, Pair d) {
  q[deg + 1] = d * q[deg];
  for (int r = deg; r >= 1; --r) q[r] = p * q[r] + d * q[r - 1];
  q[0] = p * q[0];
}

// H <- H * (p + d s) + c on both chains, H of degree degH (-1: still zero, and then a zero
// c is skipped, so leading zero coefficients of a sparse column cost nothing).
inline void hornerStep(Pair* h, int& degH, double c, Pair p, Pair d) {
  if (degH < 0 && c == 0.0) return;
  if (degH < 0) {
    h[0] = term(c);
  } else {
    mulLinear(h, degH, p, d);
    h[0] += term(c);
  }
  ++degH;
}

}  // namespace algray::ray_horner
