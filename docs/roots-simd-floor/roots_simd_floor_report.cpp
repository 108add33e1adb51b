// Scratch measurement (session 47, not meant for merging): does SIMD within one polynomial
// make roots_floor_report's floor fast enough for issue #3's 5x? Figures and judgement:
// docs/roots-simd-floor/ (raw runs, summaries) and docs/roots.md, session 47.
//
//   roots_simd_floor_report [--problems 2000] [--rounds 61] [--degrees 6,..] [--tiny]
//   roots_simd_floor_report --parts [...]   each part alone (below)
//
// The floor is roots_floor_report's bare pipeline (Bernstein coefficients on the interval,
// left-first subdivision by Descartes' rule, Halley polish), here a template over which of
// its parts run in AVX-512 registers (one zmm holds 8 coefficients; degrees 8-15 use two):
//  kBasis   power -> Bernstein as register waves: the Taylor shift to lo as N masked
//           `a += lo * (a shifted down one lane)` steps (the scalar loop's wavefront, same
//           operations in the same order), the scale by w^j / C(N, j) as one multiply and
//           one divide, the Pascal passes as N masked `b += (b shifted up one lane)` steps;
//  kSplit   de Casteljau as N `x = s x + t (x shifted down)` steps, the halves' ends taken
//           by blends (the scalar triangle's operations, in its order);
//  kSigns   Descartes' count from the sign-bit mask (vpmovq2m), xor with itself shifted,
//           and the margin test as one compare mask;
//  kPolish  Halley's f, f', f''/2 as dot products of coefficient vectors with a vector of
//           powers of x (depth log N instead of Horner's N; NOT usable by Auto as is: its
//           last evaluation must be Horner's, docs/roots.md session 8);
//  kMatSplit de Casteljau as a matrix product: the halves are sums of the node's
//           coefficients (broadcast) times precomputed columns, one table per degree and
//           split point (the floor splits at k/16, k = 4..12);
//  kMatBasis the change of basis as sums of shifted coefficient loads times lo^m and
//           binomials, then a precomputed (Pascal x 1/C(N, j)) matrix;
//  kReg     the node kept in registers throughout (regFloorSolve). Without it the node is
//           an array that scalar and vector parts hand to each other through memory, and
//           every such handoff is a store-forwarding stall (a zmm load of scalar stores, or
//           scalar loads of a zmm store): those mixed variants time the stalls as much as
//           the parts, so each part's own gain is measured alone (--parts: the part behind
//           a call of its own, its input chained on the previous call's output, "lat", or
//           independent, "thr").
// kBasis, kSplit and kSigns perform the scalar floor's operations in its order (no FMA:
// -ffp-contract=off and no fused intrinsics), so with them the answers are bit-identical
// to the scalar floor's; the kPolish/kMat* variants are checked within 1e-9.
// Columns "roots_floor_report's floor" are that program's Floor, verbatim, as it was and
// with the binomial table (commit "roots_floor_report's change of basis divides by C(N, j)
// from a compile-time table"); "scalar" is the same pipeline in this file's 16-lane node
// layout, the SIMD variants' baseline.
// Everything runs interleaved in one process (order rotated per round): Auto, Sturm, the
// scalar floors and each SIMD variant on the same problems (roots_problems.h, the seeds of
// roots_floor_report). The SIMD code is compiled with target attributes (a GCC target
// pragma) behind __builtin_cpu_supports, so the default x86-64 build carries it.
#if !defined(__x86_64__) || !defined(__GNUC__)
#include <cstdio>
int main() {
  std::puts("roots_simd_floor_report: x86-64 with GCC or Clang only; nothing measured");
  return 0;
}
#else
#include "algray/roots.h"

#include "roots_problems.h"

// GCC 12's AVX-512 intrinsics read _mm512_undefined_pd() as uninitialized under -Werror.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr int kMaxDepth = 8;
enum Parts : int {
  kBasis = 1,
  kSplit = 2,
  kSigns = 4,
  kPolish = 8,
  kMatSplit = 16,
  kMatBasis = 32,
  kReg = 64,     // the register-resident driver (regFloorSolve)
  kCount = 128,  // count nodes, splits and polish iterations (not timed)
};
struct Counts {
  long solves = 0, nodes = 0, splits = 0, polishes = 0, iterations = 0;
} gCounts;
enum class FloorAnswer { kRoot, kNone, kGaveUp };

constexpr double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

struct alignas(64) Node {
  double b[16];
  double u0, u1;
  int depth;
};

// Precomputed tables (built in main, before any timing).
struct Tables {
  // split matrices: [t index 0..8 for t = (k+4)/16][column i][lane] for left and right
  alignas(64) double left[9][16][16];
  alignas(64) double right[9][16][16];
  alignas(64) double binom[16];           // C(N, j)
  alignas(64) double pascal[16][16];      // [column j][lane i] = C(i, j) / C(N, j)
  alignas(64) double shiftBinom[16][16];  // [m][lane j] = C(j + m, j)
};
Tables gTables[16];

void buildTables(int n) {
  Tables& tb = gTables[n];
  for (int ti = 0; ti < 9; ++ti) {
    const long double t = (ti + 4) / 16.0L, s = 1 - t;
    for (int col = 0; col <= n; ++col) {
      long double x[16] = {}, l[16] = {}, r[16] = {};
      x[col] = 1;
      l[0] = x[0];
      r[n] = x[n];
      for (int k = 1; k <= n; ++k) {
        for (int i = 0; i <= n - k; ++i) x[i] = s * x[i] + t * x[i + 1];
        l[k] = x[0];
        r[n - k] = x[n - k];
      }
      for (int lane = 0; lane < 16; ++lane) {
        tb.left[ti][col][lane] = lane <= n ? static_cast<double>(l[lane]) : 0;
        tb.right[ti][col][lane] = lane <= n ? static_cast<double>(r[lane]) : 0;
      }
    }
  }
  for (int j = 0; j < 16; ++j) {
    tb.binom[j] = j <= n ? binomial(n, j) : 1;
    for (int i = 0; i < 16; ++i) {
      tb.pascal[j][i] =
          (i <= n && j <= i)
              ? static_cast<double>(static_cast<long double>(binomial(i, j)) / binomial(n, j))
              : 0;
      tb.shiftBinom[j][i] = (i + j <= n) ? binomial(i + j, i) : 0;
    }
  }
}

// ---------------------------------------------------------------------------------------
// The scalar floor, roots_floor_report's, with the node in the aligned layout above.
template <int N>
void scalarBasis(const double* c, double lo, double hi, Node& cur) {
  const double w = hi - lo;
  for (int j = 0; j < 16; ++j) cur.b[j] = j <= N ? c[j] : 0;
#pragma GCC unroll 24
  for (int k = 0; k < N; ++k)
#pragma GCC unroll 24
    for (int i = N - 1; i >= k; --i) cur.b[i] += lo * cur.b[i + 1];
  double p = 1;
#ifdef FLOOR_RUNTIME_BINOMIAL  // roots_floor_report's loop, as it stands
  for (int j = 0; j <= N; ++j, p *= w) cur.b[j] = cur.b[j] * p / binomial(N, j);
#else
  // The binomials as compile-time constants: roots_floor_report's loop above is not unrolled
  // at N = 12 by GCC 12, which then computes C(N, j) at run time (j divisions each).
  static constexpr auto kBinomial = [] {
    std::array<double, N + 1> b{};
    for (int j = 0; j <= N; ++j) b[j] = binomial(N, j);
    return b;
  }();
  for (int j = 0; j <= N; ++j, p *= w) cur.b[j] = cur.b[j] * p / kBinomial[j];
#endif
#pragma GCC unroll 24
  for (int k = 1; k <= N; ++k)
#pragma GCC unroll 24
    for (int i = N; i >= k; --i) cur.b[i] += cur.b[i - 1];
}

template <int N>
void scalarSplit(const Node& node, double t, Node& left, Node& right) {
  double x[N + 1];
  for (int i = 0; i <= N; ++i) x[i] = node.b[i];
  const double s = 1 - t;
  left.b[0] = x[0];
  right.b[N] = x[N];
#pragma GCC unroll 24
  for (int k = 1; k <= N; ++k) {
#pragma GCC unroll 24
    for (int i = 0; i <= N - k; ++i) x[i] = s * x[i] + t * x[i + 1];
    left.b[k] = x[0];
    right.b[N - k] = x[N - k];
  }
}

template <int N, bool kCounted = false>
double scalarPolish(const double* c, double x) {
  for (int it = 0; it < 8; ++it) {
    if constexpr (kCounted) ++gCounts.iterations;
    double f = c[N], df = 0, dd = 0;
    for (int k = N - 1; k >= 0; --k) {
      dd = dd * x + df;
      df = df * x + f;
      f = f * x + c[k];
    }
    const double step = f * df / (df * df - f * dd);
    x -= step;
    if (!(std::abs(step) > 1e-12 * std::abs(x))) break;
  }
  return x;
}

// The floor, with P choosing scalar or SIMD for each part. Defined twice: floorSolve
// (AVX-512 target, the SIMD variants) and scalarFloorSolve (the default target: the scalar
// floor exactly as roots_floor_report builds it, P == 0 only).
#define FLOOR_DRIVER(NAME)                                                                       \
  template <int N, int P>                                                                        \
  FloorAnswer NAME(const double* c, double lo, double hi, double& root) {                        \
    using S = SimdFloor<N>;                                                                      \
    const double w = hi - lo;                                                                    \
    Node cur;                                                                                    \
    if constexpr ((P & kMatBasis) != 0)                                                          \
      S::matBasis(c, lo, hi, cur);                                                               \
    else if constexpr ((P & kBasis) != 0)                                                        \
      S::basis(c, lo, hi, cur);                                                                  \
    else                                                                                         \
      scalarBasis<N>(c, lo, hi, cur);                                                            \
    cur.u0 = 0;                                                                                  \
    cur.u1 = 1;                                                                                  \
    cur.depth = 0;                                                                               \
    constexpr double kMargin = 1e-14;                                                            \
    Node stack[kMaxDepth + 1];                                                                   \
    int top = 0;                                                                                 \
    bool gaveUp = false;                                                                         \
    if constexpr ((P & kCount) != 0) ++gCounts.solves;                                           \
    for (;;) {                                                                                   \
      if constexpr ((P & kCount) != 0) ++gCounts.nodes;                                          \
      unsigned changes = 0;                                                                      \
      bool clear;                                                                                \
      if constexpr ((P & kSigns) != 0) {                                                         \
        changes = S::signs(cur, kMargin, clear);                                                 \
      } else {                                                                                   \
        double smallest = std::abs(cur.b[0]);                                                    \
        for (int i = 0; i < N; ++i) {                                                            \
          changes |= static_cast<unsigned>(std::signbit(cur.b[i]) != std::signbit(cur.b[i + 1])) \
                     << i;                                                                       \
          smallest = std::min(smallest, std::abs(cur.b[i + 1]));                                 \
        }                                                                                        \
        clear = smallest > kMargin;                                                              \
      }                                                                                          \
      if (changes != 0 && (changes & (changes - 1)) == 0 && clear) {                             \
        const int i = std::countr_zero(changes);                                                 \
        if constexpr ((P & kCount) != 0) ++gCounts.polishes;                                     \
        const double u = (i + cur.b[i] / (cur.b[i] - cur.b[i + 1])) / N;                         \
        const double x = lo + w * (cur.u0 + (cur.u1 - cur.u0) * u);                              \
        if constexpr ((P & kPolish) != 0)                                                        \
          root = S::polish(c, x);                                                                \
        else                                                                                     \
          root = scalarPolish<N, (P & kCount) != 0>(c, x);                                       \
        return FloorAnswer::kRoot;                                                               \
      }                                                                                          \
      if (changes != 0 && cur.depth < kMaxDepth) {                                               \
        const unsigned rest = changes & (changes - 1);                                           \
        int k = 8;                                                                               \
        if (rest != 0) {                                                                         \
          const int c1 = std::countr_zero(changes), c2 = std::countr_zero(rest);                 \
          k = std::clamp((8 * (c1 + c2 + 1) + N / 2) / N, 4, 12);                                \
        }                                                                                        \
        const double t = k / 16.0;                                                               \
        if constexpr ((P & kCount) != 0) ++gCounts.splits;                                       \
        Node& right = stack[top++];                                                              \
        Node left;                                                                               \
        if constexpr ((P & kMatSplit) != 0)                                                      \
          S::matSplit(cur, k - 4, left, right);                                                  \
        else if constexpr ((P & kSplit) != 0)                                                    \
          S::split(cur, t, left, right);                                                         \
        else                                                                                     \
          scalarSplit<N>(cur, t, left, right);                                                   \
        const double m = cur.u0 + (cur.u1 - cur.u0) * t;                                         \
        left.u0 = cur.u0;                                                                        \
        left.u1 = m;                                                                             \
        right.u0 = m;                                                                            \
        right.u1 = cur.u1;                                                                       \
        left.depth = right.depth = cur.depth + 1;                                                \
        cur = left;                                                                              \
        continue;                                                                                \
      }                                                                                          \
      gaveUp |= changes != 0;                                                                    \
      if (top == 0) return gaveUp ? FloorAnswer::kGaveUp : FloorAnswer::kNone;                   \
      cur = stack[--top];                                                                        \
    }                                                                                            \
  }

// ---------------------------------------------------------------------------------------
// The SIMD parts. Everything between push_options and pop_options is compiled for AVX-512.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq,avx512vl,avx512bw")

template <int R>
struct V {
  __m512d r[R];
};

template <int R>
inline V<R> vload(const double* p) {
  V<R> v;
  for (int i = 0; i < R; ++i) v.r[i] = _mm512_load_pd(p + 8 * i);
  return v;
}
template <int R>
inline void vstore(double* p, const V<R>& v) {
  for (int i = 0; i < R; ++i) _mm512_store_pd(p + 8 * i, v.r[i]);
}
template <int R>
inline V<R> vset1(double x) {
  V<R> v;
  for (int i = 0; i < R; ++i) v.r[i] = _mm512_set1_pd(x);
  return v;
}
template <int R>
inline V<R> vmul(const V<R>& a, const V<R>& b) {
  V<R> v;
  for (int i = 0; i < R; ++i) v.r[i] = _mm512_mul_pd(a.r[i], b.r[i]);
  return v;
}
template <int R>
inline V<R> vadd(const V<R>& a, const V<R>& b) {
  V<R> v;
  for (int i = 0; i < R; ++i) v.r[i] = _mm512_add_pd(a.r[i], b.r[i]);
  return v;
}
template <int R>
inline V<R> vdiv(const V<R>& a, const V<R>& b) {
  V<R> v;
  for (int i = 0; i < R; ++i) v.r[i] = _mm512_div_pd(a.r[i], b.r[i]);
  return v;
}
// a where mask is clear, a + b where set
template <int R>
inline V<R> vmaskAdd(const V<R>& a, unsigned mask, const V<R>& b) {
  V<R> v;
  for (int i = 0; i < R; ++i)
    v.r[i] = _mm512_mask_add_pd(a.r[i], static_cast<__mmask8>(mask >> (8 * i)), a.r[i], b.r[i]);
  return v;
}
template <int R>
inline V<R> vmaskMul(const V<R>& a, unsigned mask, const V<R>& b, const V<R>& c) {
  V<R> v;
  for (int i = 0; i < R; ++i)
    v.r[i] = _mm512_mask_mul_pd(a.r[i], static_cast<__mmask8>(mask >> (8 * i)), b.r[i], c.r[i]);
  return v;
}
template <int R>
inline V<R> vblend(unsigned mask, const V<R>& a, const V<R>& b) {
  V<R> v;
  for (int i = 0; i < R; ++i)
    v.r[i] = _mm512_mask_blend_pd(static_cast<__mmask8>(mask >> (8 * i)), a.r[i], b.r[i]);
  return v;
}
#define ALIGNR(hi, lo, n) \
  _mm512_castsi512_pd(    \
      _mm512_maskz_alignr_epi64(0xFF, _mm512_castpd_si512(hi), _mm512_castpd_si512(lo), n))
// lane i <- lane i + 1 (the top lane: anything)
template <int R>
inline V<R> vshiftDown(const V<R>& a) {
  V<R> v;
  if constexpr (R == 1) {
    v.r[0] = ALIGNR(a.r[0], a.r[0], 1);
  } else {
    v.r[0] = ALIGNR(a.r[1], a.r[0], 1);
    v.r[1] = ALIGNR(a.r[1], a.r[1], 1);
  }
  return v;
}
// lane i <- lane i - 1, lane 0 <- 0
template <int R>
inline V<R> vshiftUp(const V<R>& a) {
  V<R> v;
  const __m512d z = _mm512_setzero_pd();
  if constexpr (R == 1) {
    v.r[0] = ALIGNR(a.r[0], z, 7);
  } else {
    v.r[0] = ALIGNR(a.r[0], z, 7);
    v.r[1] = ALIGNR(a.r[1], a.r[0], 7);
  }
  return v;
}
template <int R>
inline unsigned vsignMask(const V<R>& a) {
  unsigned m = 0;
  for (int i = 0; i < R; ++i)
    m |= static_cast<unsigned>(_mm512_movepi64_mask(_mm512_castpd_si512(a.r[i]))) << (8 * i);
  return m;
}
template <int R>
inline unsigned vabsAbove(const V<R>& a, double margin) {
  unsigned m = 0;
  const __m512d mv = _mm512_set1_pd(margin);
  for (int i = 0; i < R; ++i)
    m |= static_cast<unsigned>(_mm512_cmp_pd_mask(_mm512_abs_pd(a.r[i]), mv, _CMP_GT_OQ))
         << (8 * i);
  return m;
}
inline double vsum(__m512d a) { return _mm512_reduce_add_pd(a); }

template <int N>
struct SimdFloor {
  static constexpr int R = N < 8 ? 1 : 2;
  static constexpr unsigned kAll = (1u << (N + 1)) - 1;
  using Vec = V<R>;

  // c_0..c_N straight from memory (masked: no read past c_N, no store-forwarding stall).
  static Vec loadCoefficients(const double* c, int from = 0) {
    Vec v;
    const unsigned mask = kAll >> from;
    for (int i = 0; i < R; ++i)
      v.r[i] = _mm512_maskz_loadu_pd(static_cast<__mmask8>(mask >> (8 * i)), c + from + 8 * i);
    return v;
  }

  // Bit-identical to scalarBasis (see the file's comment).
  [[gnu::always_inline]] static Vec basisV(const double* c, double lo, double hi) {
    const double w = hi - lo;
    Vec a = loadCoefficients(c);
    const Vec lov = vset1<R>(lo);
    // wave j updates lanes N-1-j .. N-1
#pragma GCC unroll 24
    for (int j = 0; j < N; ++j) {
      const unsigned mask = ((1u << (j + 1)) - 1) << (N - 1 - j);
      a = vmaskAdd<R>(a, mask, vmul<R>(lov, vshiftDown<R>(a)));
    }
    // powers of w: lane j = ((w * w) * w) ... as the scalar loop
    Vec p = vset1<R>(1.0);
    const Vec wv = vset1<R>(w);
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) {
      const unsigned mask = kAll & ~((1u << k) - 1);
      p = vmaskMul<R>(p, mask, vshiftUp<R>(p), wv);
    }
    a = vdiv<R>(vmul<R>(a, p), vload<R>(gTables[N].binom));
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) {
      const unsigned mask = kAll & ~((1u << k) - 1);
      a = vmaskAdd<R>(a, mask, vshiftUp<R>(a));
    }
    return a;
  }

  static double lane(const Vec& v, int i) {
    const __m512i idx = _mm512_set1_epi64(i);
    if constexpr (R == 1)
      return _mm512_cvtsd_f64(_mm512_permutexvar_pd(idx, v.r[0]));
    else
      return _mm512_cvtsd_f64(_mm512_permutex2var_pd(v.r[0], idx, v.r[1]));
  }
  static Vec broadcastLane(const Vec& v, int i) {  // i a compile-time constant after unrolling
    Vec out;
    const __m512d x = _mm512_permutexvar_pd(_mm512_set1_epi64(i & 7), v.r[i >> 3]);
    for (int k = 0; k < R; ++k) out.r[k] = x;
    return out;
  }

  // The change of basis as sums: a_j = sum_m lo^m C(j+m, j) c_{j+m}, then
  // b = sum_j (a_j w^j) * column_j of (Pascal / C(N, j)).
  // always_inline: GCC 12 compiled an out-of-line copy returning V<1> (one zmm) with a
  // vzeroupper before the ret, zeroing lanes 2-7 of the result (seen at N = 6, 7).
  [[gnu::always_inline]] static Vec matBasisV(const double* c, double lo, double hi) {
    const double w = hi - lo;
    const Tables& tb = gTables[N];
    Vec acc[2] = {loadCoefficients(c), vset1<R>(0.0)};
    double lm = 1;
#pragma GCC unroll 24
    for (int m = 1; m <= N; ++m) {
      lm *= lo;
      acc[m & 1] = vadd<R>(acc[m & 1], vmul<R>(vset1<R>(lm), vmul<R>(loadCoefficients(c, m),
                                                                     vload<R>(tb.shiftBinom[m]))));
    }
    Vec a = vadd<R>(acc[0], acc[1]);
    // times w^j (lane j), as the scalar loop's powers
    Vec p = vset1<R>(1.0);
    const Vec wv = vset1<R>(w);
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) p = vmaskMul<R>(p, kAll & ~((1u << k) - 1), vshiftUp<R>(p), wv);
    a = vmul<R>(a, p);
    Vec out[4] = {vset1<R>(0.0), vset1<R>(0.0), vset1<R>(0.0), vset1<R>(0.0)};
#pragma GCC unroll 24
    for (int j = 0; j <= N; ++j)
      out[j & 3] = vadd<R>(out[j & 3], vmul<R>(broadcastLane(a, j), vload<R>(tb.pascal[j])));
    return vadd<R>(vadd<R>(out[0], out[1]), vadd<R>(out[2], out[3]));
  }

  // Bit-identical to scalarSplit.
  [[gnu::always_inline]] static void splitV(const Vec& b, double t, Vec& left, Vec& right) {
    Vec x = b, l = b, r = b;
    const Vec sv = vset1<R>(1 - t), tv = vset1<R>(t);
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) {
      x = vadd<R>(vmul<R>(sv, x), vmul<R>(tv, vshiftDown<R>(x)));
      Vec x0;
      for (int i = 0; i < R; ++i) x0.r[i] = _mm512_broadcastsd_pd(_mm512_castpd512_pd128(x.r[0]));
      l = vblend<R>(1u << k, l, x0);
      r = vblend<R>(1u << (N - k), r, x);
    }
    left = l;
    right = r;
  }

  [[gnu::always_inline]] static void matSplitV(const Vec& b, int ti, Vec& left, Vec& right) {
    const Tables& tb = gTables[N];
    Vec l[2] = {vset1<R>(0.0), vset1<R>(0.0)}, r[2] = {vset1<R>(0.0), vset1<R>(0.0)};
#pragma GCC unroll 24
    for (int i = 0; i <= N; ++i) {
      const Vec bi = broadcastLane(b, i);
      l[i & 1] = vadd<R>(l[i & 1], vmul<R>(bi, vload<R>(tb.left[ti][i])));
      r[i & 1] = vadd<R>(r[i & 1], vmul<R>(bi, vload<R>(tb.right[ti][i])));
    }
    left = vadd<R>(l[0], l[1]);
    right = vadd<R>(r[0], r[1]);
  }

  // Sign variations (bit i: b_i and b_{i+1} differ in sign) and whether every |b_i| > margin.
  [[gnu::always_inline]] static unsigned signsV(const Vec& b, double margin, bool& clear) {
    const unsigned m = vsignMask<R>(b);
    clear = (vabsAbove<R>(b, margin) & kAll) == kAll;
    return (m ^ (m >> 1)) & (kAll >> 1);
  }

  // Node wrappers for the mixed (scalar driver) variants.
  static void basis(const double* c, double lo, double hi, Node& cur) {
    vstore<R>(cur.b, basisV(c, lo, hi));
  }
  static void matBasis(const double* c, double lo, double hi, Node& cur) {
    vstore<R>(cur.b, matBasisV(c, lo, hi));
  }
  static void split(const Node& node, double t, Node& left, Node& right) {
    Vec l, r;
    splitV(vload<R>(node.b), t, l, r);
    vstore<R>(left.b, l);
    vstore<R>(right.b, r);
  }
  static void matSplit(const Node& node, int ti, Node& left, Node& right) {
    Vec l, r;
    matSplitV(vload<R>(node.b), ti, l, r);
    vstore<R>(left.b, l);
    vstore<R>(right.b, r);
  }
  static unsigned signs(const Node& node, double margin, bool& clear) {
    return signsV(vload<R>(node.b), margin, clear);
  }

  // Halley with f, f', f'' as dot products with powers of x.
  static double polish(const double* c, double x) {
    alignas(64) static constexpr double k1[16] = {1, 2,  3,  4,  5,  6,  7,  8,
                                                  9, 10, 11, 12, 13, 14, 15, 16};
    alignas(64) static constexpr double k2[16] = {1,  3,  6,  10, 15, 21,  28,  36,
                                                  45, 55, 66, 78, 91, 105, 120, 136};
    // f''/2 = sum_j C(j+2, 2) c_{j+2} x^j, as the scalar Horner's dd
    const Vec vc = loadCoefficients(c), v1 = vmul<R>(loadCoefficients(c, 1), vload<R>(k1)),
              v2 = vmul<R>(loadCoefficients(c, 2), vload<R>(k2));
    const __m512d one = _mm512_set1_pd(1.0);
    for (int it = 0; it < 8; ++it) {
      const __m512d xv = _mm512_set1_pd(x);
      const __m512d x2 = _mm512_mul_pd(xv, xv), x4 = _mm512_mul_pd(x2, x2);
      __m512d pw = _mm512_mask_blend_pd(0xAA, one, xv);             // 1 x 1 x 1 x 1 x
      pw = _mm512_mul_pd(pw, _mm512_mask_blend_pd(0xCC, one, x2));  // 1 x x2 x3 1 x ..
      pw = _mm512_mul_pd(pw, _mm512_mask_blend_pd(0xF0, one, x4));
      Vec pv;
      pv.r[0] = pw;
      if constexpr (R == 2) pv.r[1] = _mm512_mul_pd(pw, _mm512_mul_pd(x4, x4));
      const Vec pf = vmul<R>(vc, pv), p1 = vmul<R>(v1, pv), p2 = vmul<R>(v2, pv);
      double f, df, dd;
      if constexpr (R == 1) {
        f = vsum(pf.r[0]);
        df = vsum(p1.r[0]);
        dd = vsum(p2.r[0]);
      } else {
        f = vsum(_mm512_add_pd(pf.r[0], pf.r[1]));
        df = vsum(_mm512_add_pd(p1.r[0], p1.r[1]));
        dd = vsum(_mm512_add_pd(p2.r[0], p2.r[1]));
      }
      const double step = f * df / (df * df - f * dd);
      x -= step;
      if (!(std::abs(step) > 1e-12 * std::abs(x))) break;
    }
    return x;
  }
};

// The floor with the node in registers throughout (kSigns always; basis, split and polish
// as P says). No scalar part reads a node, so no store-forwarding stall between parts.
template <int N, int P>
FloorAnswer regFloorSolve(const double* c, double lo, double hi, double& root) {
  using S = SimdFloor<N>;
  using Vec = typename S::Vec;
  struct VNode {
    Vec b;
    double u0, u1;
    int depth;
  };
  const double w = hi - lo;
  VNode cur;
  if constexpr ((P & kMatBasis) != 0)
    cur.b = S::matBasisV(c, lo, hi);
  else
    cur.b = S::basisV(c, lo, hi);
  cur.u0 = 0;
  cur.u1 = 1;
  cur.depth = 0;
  constexpr double kMargin = 1e-14;
  VNode stack[kMaxDepth + 1];
  int top = 0;
  bool gaveUp = false;
  for (;;) {
    bool clear;
    const unsigned changes = S::signsV(cur.b, kMargin, clear);
    if (changes != 0 && (changes & (changes - 1)) == 0 && clear) {
      const int i = std::countr_zero(changes);
      const double bi = S::lane(cur.b, i), bj = S::lane(cur.b, i + 1);
      const double u = (i + bi / (bi - bj)) / N;
      const double x = lo + w * (cur.u0 + (cur.u1 - cur.u0) * u);
      if constexpr ((P & kPolish) != 0)
        root = S::polish(c, x);
      else
        root = scalarPolish<N>(c, x);
      return FloorAnswer::kRoot;
    }
    if (changes != 0 && cur.depth < kMaxDepth) {
      const unsigned rest = changes & (changes - 1);
      int k = 8;
      if (rest != 0) {
        const int c1 = std::countr_zero(changes), c2 = std::countr_zero(rest);
        k = std::clamp((8 * (c1 + c2 + 1) + N / 2) / N, 4, 12);
      }
      const double t = k / 16.0;
      VNode& right = stack[top++];
      Vec left;
      if constexpr ((P & kMatSplit) != 0)
        S::matSplitV(cur.b, k - 4, left, right.b);
      else
        S::splitV(cur.b, t, left, right.b);
      const double m = cur.u0 + (cur.u1 - cur.u0) * t;
      right.u0 = m;
      right.u1 = cur.u1;
      right.depth = cur.depth + 1;
      cur.b = left;
      cur.u1 = m;
      cur.depth += 1;
      continue;
    }
    gaveUp |= changes != 0;
    if (top == 0) return gaveUp ? FloorAnswer::kGaveUp : FloorAnswer::kNone;
    cur = stack[--top];
  }
}

#pragma GCC pop_options

// The stripped pipeline for a compile-time degree N (loops unroll, as Auto's up to 20).
// roots_floor_report's Floor, verbatim but for the name and the binomials (kTable: C(N, j)
// from a compile-time table; the original computes them at run time where GCC does not
// unroll the scale loop, N = 12).
template <int N, bool kTable>
struct OrigFloor {
  static constexpr double binomial(int n, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
    return r;
  }

  struct Node {
    double b[N + 1];
    double u0, u1;
    int depth;
  };

  static FloorAnswer solve(const double* c, double lo, double hi, double& root) {
    // ---- Bernstein coefficients on [lo, hi]: Taylor shift to lo, scale, Pascal passes
    const double w = hi - lo;
    Node cur;
    for (int j = 0; j <= N; ++j) cur.b[j] = c[j];
#pragma GCC unroll 24
    for (int k = 0; k < N; ++k)
#pragma GCC unroll 24
      for (int i = N - 1; i >= k; --i) cur.b[i] += lo * cur.b[i + 1];
    double p = 1;
    static constexpr auto kBinomial = [] {
      std::array<double, N + 1> b{};
      for (int j = 0; j <= N; ++j) b[j] = binomial(N, j);
      return b;
    }();
    for (int j = 0; j <= N; ++j, p *= w)
      cur.b[j] = cur.b[j] * p / (kTable ? kBinomial[j] : binomial(N, j));
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k)
#pragma GCC unroll 24
      for (int i = N; i >= k; --i) cur.b[i] += cur.b[i - 1];
    cur.u0 = 0;
    cur.u1 = 1;
    cur.depth = 0;

    // ---- Left-first subdivision ------------------------------------------------------
    constexpr double kMargin = 1e-14;  // (Auto: the node's rounding and noise bounds)
    Node stack[kMaxDepth + 1];
    int top = 0;
    bool gaveUp = false;
    for (;;) {
      unsigned changes = 0;
      double smallest = std::abs(cur.b[0]);
      for (int i = 0; i < N; ++i) {
        changes |= static_cast<unsigned>(std::signbit(cur.b[i]) != std::signbit(cur.b[i + 1])) << i;
        smallest = std::min(smallest, std::abs(cur.b[i + 1]));
      }
      if (changes != 0 && (changes & (changes - 1)) == 0 && smallest > kMargin) {
        root = polish(c, cur, std::countr_zero(changes), lo, w);
        return FloorAnswer::kRoot;
      }
      if (changes != 0 && cur.depth < kMaxDepth) {
        // Split between the first two crossings (Auto's plain nodes), else at the middle.
        const unsigned rest = changes & (changes - 1);
        double t = 0.5;
        if (rest != 0) {
          const int c1 = std::countr_zero(changes), c2 = std::countr_zero(rest);
          t = std::clamp((8 * (c1 + c2 + 1) + N / 2) / N, 4, 12) / 16.0;
        }
        Node left, right;
        split(cur, t, left, right);
        stack[top++] = right;
        cur = left;
        continue;
      }
      gaveUp |= changes != 0;
      if (top == 0) return gaveUp ? FloorAnswer::kGaveUp : FloorAnswer::kNone;
      cur = stack[--top];
    }
  }

  // de Casteljau at t.
  static void split(const Node& node, double t, Node& left, Node& right) {
    double x[N + 1];
    for (int i = 0; i <= N; ++i) x[i] = node.b[i];
    const double s = 1 - t;
    left.b[0] = x[0];
    right.b[N] = x[N];
#pragma GCC unroll 24
    for (int k = 1; k <= N; ++k) {
#pragma GCC unroll 24
      for (int i = 0; i <= N - k; ++i) x[i] = s * x[i] + t * x[i + 1];
      left.b[k] = x[0];
      right.b[N - k] = x[N - k];
    }
    const double m = node.u0 + (node.u1 - node.u0) * t;
    left.u0 = node.u0;
    left.u1 = m;
    right.u0 = m;
    right.u1 = node.u1;
    left.depth = right.depth = node.depth + 1;
  }

  // Halley's method on the power form from the control polygon's crossing in segment i.
  static double polish(const double* c, const Node& node, int i, double lo, double w) {
    const double u = (i + node.b[i] / (node.b[i] - node.b[i + 1])) / N;
    double x = lo + w * (node.u0 + (node.u1 - node.u0) * u);
    for (int it = 0; it < 8; ++it) {
      double f = c[N], df = 0, dd = 0;
      for (int k = N - 1; k >= 0; --k) {
        dd = dd * x + df;
        df = df * x + f;
        f = f * x + c[k];
      }
      const double step = f * df / (df * df - f * dd);
      x -= step;
      if (!(std::abs(step) > 1e-12 * std::abs(x))) break;
    }
    return x;
  }
};

FLOOR_DRIVER(scalarFloorSolve)

// Each part behind a call of its own (noinline, the same for both kinds), for measureParts.
template <int N>
__attribute__((noinline)) double sBasis(const double* c, double lo, double hi) {
  Node n;
  scalarBasis<N>(c, lo, hi, n);
  return n.b[N / 2];
}
template <int N>
__attribute__((noinline)) double sSplit(const Node& nd, double dep) {
  Node in = nd, l, r;
  in.b[0] += dep;
  scalarSplit<N>(in, 0.5, l, r);
  return l.b[N] + r.b[0];
}
template <int N>
__attribute__((noinline)) unsigned sSigns(const Node& nd, double dep) {
  Node in = nd;
  in.b[0] += dep;
  unsigned ch = 0;
  double smallest = std::abs(in.b[0]);
  for (int i = 0; i < N; ++i) {
    ch |= static_cast<unsigned>(std::signbit(in.b[i]) != std::signbit(in.b[i + 1])) << i;
    smallest = std::min(smallest, std::abs(in.b[i + 1]));
  }
  return ch + (smallest > 1e-14);
}
template <int N>
__attribute__((noinline)) double sPolish(const double* c, double x) {
  return scalarPolish<N>(c, x);
}
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq,avx512vl,avx512bw")
FLOOR_DRIVER(floorSolve)

template <int N>
__attribute__((noinline)) double vBasis(const double* c, double lo, double hi, int kind) {
  using S = SimdFloor<N>;
  return S::lane(kind == 1 ? S::basisV(c, lo, hi) : S::matBasisV(c, lo, hi), N / 2);
}
// The dependency enters in registers: no store-forwarding stall in the timing.
template <int N>
__attribute__((noinline)) double vSplit(const Node& nd, double dep, int kind) {
  using S = SimdFloor<N>;
  constexpr int R = S::R;
  const V<R> in = vadd<R>(vload<R>(nd.b), vset1<R>(dep));
  V<R> l, r;
  if (kind == 1)
    S::splitV(in, 0.5, l, r);
  else
    S::matSplitV(in, 4, l, r);
  return S::lane(l, N) + S::lane(r, 0);
}
template <int N>
__attribute__((noinline)) unsigned vSigns(const Node& nd, double dep) {
  using S = SimdFloor<N>;
  constexpr int R = S::R;
  bool clear;
  const unsigned ch = S::signsV(vadd<R>(vload<R>(nd.b), vset1<R>(dep)), 1e-14, clear);
  return ch + clear;
}
template <int N>
__attribute__((noinline)) double vPolish(const double* c, double x) {
  return SimdFloor<N>::polish(c, x);
}
#pragma GCC pop_options

using SolveFn = FloorAnswer (*)(const double*, double, double, double&);

template <int P, int... Ns>
SolveFn pick(int n, std::integer_sequence<int, Ns...>) {
  SolveFn f = nullptr;
  if constexpr (P == -1 || P == -2)
    static_cast<void>(
        ((n == Ns + 6 ? (f = &OrigFloor<Ns + 6, P == -2>::solve, true) : false) || ...));
  else if constexpr (P == 0 || P == kCount)
    static_cast<void>(((n == Ns + 6 ? (f = &scalarFloorSolve<Ns + 6, P>, true) : false) || ...));
  else if constexpr ((P & kReg) != 0)
    static_cast<void>(((n == Ns + 6 ? (f = &regFloorSolve<Ns + 6, P>, true) : false) || ...));
  else
    static_cast<void>(((n == Ns + 6 ? (f = &floorSolve<Ns + 6, P>, true) : false) || ...));
  return f;
}

struct Variant {
  const char* name;
  int parts;
};
// Parts sets measured, in column order.
constexpr Variant kVariants[] = {
    {"scalar", 0},
    {"roots_floor_report's floor", -1},
    {"roots_floor_report's floor, binomial table", -2},
    {"basis", kBasis},
    {"split", kSplit},
    {"signs", kSigns},
    {"polish", kPolish},
    {"basis+split+signs", kBasis | kSplit | kSigns},
    {"all wave", kBasis | kSplit | kSigns | kPolish},
    {"matsplit", kMatSplit},
    {"matbasis", kMatBasis},
    {"mat+signs", kMatBasis | kMatSplit | kSigns},
    {"mat+signs+polish", kMatBasis | kMatSplit | kSigns | kPolish},
    {"reg wave", kReg | kBasis | kSplit | kSigns},
    {"reg wave+polish", kReg | kBasis | kSplit | kSigns | kPolish},
    {"reg wave basis+matsplit", kReg | kBasis | kMatSplit | kSigns},
    {"reg mat", kReg | kMatBasis | kMatSplit | kSigns},
    {"reg mat+polish", kReg | kMatBasis | kMatSplit | kSigns | kPolish},
};
constexpr int kNumVariants = sizeof(kVariants) / sizeof(kVariants[0]);

template <int I = 0>
void pickAll(int n, SolveFn* out) {
  if constexpr (I < kNumVariants) {
    out[I] = pick<kVariants[I].parts>(n, std::make_integer_sequence<int, 10>{});
    pickAll<I + 1>(n, out);
  }
}

struct Problem {
  std::vector<double> c;
  double lo, hi;
};

double median(std::vector<double> v) { return algray::bench::quantile(std::move(v), 0.5); }
double lowest(std::vector<double> v) { return algray::bench::quantile(std::move(v), 0.0); }
double highest(std::vector<double> v) { return algray::bench::quantile(std::move(v), 1.0); }

void measure(int degree, bool cell, int count, int rounds) {
  std::mt19937_64 rng(static_cast<uint64_t>(42 + 2 * degree + (cell ? 1 : 0)));
  std::vector<Problem> problems;
  for (int i = 0; i < count; ++i) {
    const auto shape = algray::bench::randomProblemShape(degree, cell, rng);
    problems.push_back({algray::bench::expandInDouble(shape), shape.lo, shape.hi});
  }
  SolveFn fns[kNumVariants];
  pickAll(degree, fns);
  {
    gCounts = Counts{};
    const SolveFn counted = pick<kCount>(degree, std::make_integer_sequence<int, 10>{});
    for (const Problem& p : problems) {
      double r;
      counted(p.c.data(), p.lo, p.hi, r);
    }
  }
  // Agreement of each variant with the scalar floor: same answer kind and the root within
  // 1e-9 (relative above 1); and bit-identical roots.
  int within[kNumVariants] = {}, identical[kNumVariants] = {}, agreeAuto = 0;
  for (const Problem& p : problems) {
    double r0 = 0, ra = 0;
    const FloorAnswer a0 = fns[0](p.c.data(), p.lo, p.hi, r0);
    const bool a = algray::solveFirstRoot(p.c, {}, p.lo, p.hi, ra);
    agreeAuto += a == (a0 == FloorAnswer::kRoot) &&
                 (!a || std::abs(ra - r0) <= 1e-9 * std::max(1.0, std::abs(ra)));
    for (int v = 0; v < kNumVariants; ++v) {
      double r = 0;
      const FloorAnswer av = fns[v](p.c.data(), p.lo, p.hi, r);
      within[v] += av == a0 && (av != FloorAnswer::kRoot ||
                                std::abs(r - r0) <= 1e-9 * std::max(1.0, std::abs(r0)));
      identical[v] += av == a0 && (av != FloorAnswer::kRoot ||
                                   std::bit_cast<uint64_t>(r) == std::bit_cast<uint64_t>(r0));
    }
  }

  const algray::RootOptions autoOptions{};
  algray::RootOptions sturmOptions;
  sturmOptions.method = algray::RootMethod::Sturm;
  using Clock = std::chrono::steady_clock;
  double sink = 0;
  constexpr int kMethods = 2 + kNumVariants;  // 0 Auto, 1 Sturm, 2.. variants
  auto pass = [&](int method) {
    const auto t0 = Clock::now();
    if (method < 2) {
      const algray::RootOptions& options = method == 0 ? autoOptions : sturmOptions;
      for (const Problem& p : problems) {
        double r = 0;
        if (algray::solveFirstRoot(p.c, {}, p.lo, p.hi, r, options)) sink += r;
      }
    } else {
      const SolveFn f = fns[method - 2];
      for (const Problem& p : problems) {
        double r = 0;
        if (f(p.c.data(), p.lo, p.hi, r) == FloorAnswer::kRoot) sink += r;
      }
    }
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
           static_cast<double>(problems.size());
  };
  std::vector<double> ns[kMethods], ratio[kMethods];  // ratio: Sturm / method
  for (int round = 0; round < rounds; ++round) {
    double t[kMethods];
    for (int k = 0; k < kMethods; ++k) {
      const int m = (k + round) % kMethods;
      t[m] = pass(m);
    }
    for (int m = 0; m < kMethods; ++m) {
      ns[m].push_back(t[m]);
      ratio[m].push_back(t[1] / t[m]);
    }
  }
  if (sink == 0.125) std::puts("");
  std::printf("| %s | %d | %.0f | %.0f | %.2f |", cell ? "cell" : "ray", degree, median(ns[0]),
              median(ns[1]), median(ratio[0]));
  for (int v = 0; v < kNumVariants; ++v)
    std::printf(" %.0f ns %.2f (%.2f-%.2f) |", median(ns[v + 2]), median(ratio[v + 2]),
                lowest(ratio[v + 2]), highest(ratio[v + 2]));
  std::printf(" %d |", agreeAuto);
  for (int v = 1; v < kNumVariants; ++v) std::printf(" %d/%d", within[v], identical[v]);
  const double per = 1.0 / static_cast<double>(gCounts.solves);
  std::printf(" | %.2f nodes, %.2f splits, %.2f polishes, %.2f Halley steps |\n",
              static_cast<double>(gCounts.nodes) * per, static_cast<double>(gCounts.splits) * per,
              static_cast<double>(gCounts.polishes) * per,
              static_cast<double>(gCounts.iterations) * per);
  std::fflush(stdout);
}

// Each part alone, ns per call: "lat" chains every call's input on the previous call's
// output (the time of the dependency chain), "thr" runs the calls independently.
template <int N>
void measureParts(bool cell, int count, int rounds) {
  std::mt19937_64 rng(static_cast<uint64_t>(42 + 2 * N + (cell ? 1 : 0)));
  std::vector<Problem> problems;
  std::vector<Node> nodes;
  std::vector<std::pair<double, int> > starts;  // polish start and problem index
  for (int i = 0; i < count; ++i) {
    const auto shape = algray::bench::randomProblemShape(N, cell, rng);
    problems.push_back({algray::bench::expandInDouble(shape), shape.lo, shape.hi});
    Node n;
    scalarBasis<N>(problems.back().c.data(), shape.lo, shape.hi, n);
    nodes.push_back(n);
    double r;
    if (scalarFloorSolve<N, 0>(problems.back().c.data(), shape.lo, shape.hi, r) ==
        FloorAnswer::kRoot)
      starts.emplace_back(r + 1e-3 * (shape.hi - shape.lo), i);
  }
  using Clock = std::chrono::steady_clock;
  double sink = 0;
  // kind: 0 scalar, 1 wave, 2 matrix; part: 0 basis, 1 split, 2 signs, 3 polish
  auto run = [&](int part, int kind, bool chain) {
    const auto t0 = Clock::now();
    double dep = 0;
    size_t calls = 0;
    if (part == 0) {
      for (const Problem& p : problems) {
        const double lo = p.lo + dep;
        const double out =
            kind == 0 ? sBasis<N>(p.c.data(), lo, p.hi) : vBasis<N>(p.c.data(), lo, p.hi, kind);
        sink += out;
        if (chain) dep = out * 0.0;
      }
      calls = problems.size();
    } else if (part == 1) {
      for (const Node& nd : nodes) {
        const double out = kind == 0 ? sSplit<N>(nd, dep) : vSplit<N>(nd, dep, kind);
        sink += out;
        if (chain) dep = out * 0.0;
      }
      calls = nodes.size();
    } else if (part == 2) {
      for (const Node& nd : nodes) {
        const unsigned out = kind == 0 ? sSigns<N>(nd, dep) : vSigns<N>(nd, dep);
        sink += out;
        if (chain) dep = static_cast<double>(out & 0);
      }
      calls = nodes.size();
    } else {
      for (const auto& [x0, i] : starts) {
        const double* c = problems[static_cast<size_t>(i)].c.data();
        const double out = kind == 0 ? sPolish<N>(c, x0 + dep) : vPolish<N>(c, x0 + dep);
        sink += out;
        if (chain) dep = out * 0.0;
      }
      calls = starts.size();
    }
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() /
           static_cast<double>(calls);
  };
  const int kinds[4] = {3, 3, 2, 2};
  const char* partNames[4] = {"basis", "split", "signs", "polish"};
  for (int part = 0; part < 4; ++part)
    for (const bool chain : {true, false}) {
      std::vector<double> ns[3], ratio[3];
      for (int round = 0; round < rounds; ++round) {
        double t[3];
        for (int k = 0; k < kinds[part]; ++k) {
          const int m = (k + round) % kinds[part];
          t[m] = run(part, m, chain);
        }
        for (int m = 0; m < kinds[part]; ++m) {
          ns[m].push_back(t[m]);
          ratio[m].push_back(t[0] / t[m]);
        }
      }
      std::printf("| %s | %d | %s | %s | %.1f |", cell ? "cell" : "ray", N, partNames[part],
                  chain ? "lat" : "thr", median(ns[0]));
      for (int m = 1; m < 3; ++m)
        if (m < kinds[part])
          std::printf(" %.1f (%.2f) |", median(ns[m]), median(ratio[m]));
        else
          std::printf(" - |");
      std::printf("\n");
    }
  if (sink == 0.125) std::puts("");
}

template <int... Ns>
void measurePartsFor(int n, bool cell, int count, int rounds, std::integer_sequence<int, Ns...>) {
  static_cast<void>(
      ((n == Ns + 6 ? (measureParts<Ns + 6>(cell, count, rounds), true) : false) || ...));
}

int parseInt(const std::string& text) { return std::atoi(text.c_str()); }

}  // namespace

int main(int argc, char** argv) {
  int count = 2000, rounds = 61;
  bool parts = false;
  std::vector<int> degrees{6, 7, 8, 9, 10, 11, 12};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tiny") {
      count = 50;
      rounds = 3;
      degrees = {6};
    } else if (arg == "--problems" && i + 1 < argc) {
      count = parseInt(argv[++i]);
    } else if (arg == "--rounds" && i + 1 < argc) {
      rounds = parseInt(argv[++i]);
    } else if (arg == "--degrees" && i + 1 < argc) {
      degrees.clear();
      std::stringstream list(argv[++i]);
      for (std::string d; std::getline(list, d, ',');) degrees.push_back(parseInt(d));
    } else if (arg == "--parts") {
      parts = true;
    } else if (arg == "--out" && i + 1 < argc) {
      ++i;  // the smoke test passes --out; nothing is written
    } else {
      std::fprintf(stderr, "unknown argument '%s'\n", arg.c_str());
      return 2;
    }
  }
  for (int d : degrees)
    if (d < 6 || d > 15) {
      std::fprintf(stderr, "degrees 6..15 only\n");
      return 2;
    }
  __builtin_cpu_init();
  if (!(__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))) {
    std::puts("no AVX-512 on this host: nothing measured");
    return 0;
  }
  for (int n = 6; n <= 15; ++n) buildTables(n);
  if (parts) {
    std::printf(
        "| family | degree | part | mode | scalar ns | wave ns (scalar / wave) | "
        "matrix ns (scalar / matrix) |\n|---|---:|---|---|---:|---:|---:|\n");
    for (const bool cell : {false, true})
      for (const int d : degrees)
        measurePartsFor(d, cell, count, rounds, std::make_integer_sequence<int, 10>{});
    return 0;
  }
  std::printf("| family | degree | Auto ns | Sturm ns | Sturm / Auto |");
  for (const Variant& v : kVariants) std::printf(" %s: ns, Sturm / it (range) |", v.name);
  std::printf(
      " scalar floor agrees with Auto | each variant vs scalar floor: within 1e-9 / "
      "bit-identical | scalar floor's work per problem |\n");
  for (const bool cell : {false, true})
    for (const int d : degrees) measure(d, cell, count, rounds);
  return 0;
}
#endif
