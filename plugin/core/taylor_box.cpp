// restrictToRay over a HornerForm's box (taylor.h; layout in horner_form.h): the nested
// Horner scheme of restrictToRay(const Polynomial&, ...) in taylor.cpp on the same
// non-zero data, with the same operations per coefficient in the same order, so the
// derivation of the bound there covers this path unchanged. (nestedHorner also skips the
// products of a still-zero G or F and a z-column's leading zeros; zero rows inside the
// box add exact zeros. The two paths agree in value; nestedHorner's dense arrays can turn
// a zero coefficient's -0 into +0: tests/support/box_reference.h.)
//
// Speed from compile-time lengths, not other arithmetic: the bits are those of the
// run-time-loop version kept in tests/support/box_reference.h (tests/taylor_test.cpp).
//  - a z-row of L <= kUnrolled slots is one unrolled function with H in registers
//    (rowStep<L>), followed by F <- F * Y + H in one pass over F (mulAdd);
//  - F <- F * Y for a zero row, G <- G * X for a zero block, G <- G * X + F for a block
//    one degree above G and F <- F * Y + c, G <- G * X + c for one-constant rows and
//    blocks call unrolled passes of fixed degree (mulLinearN, mulAddN, mulAddConstN;
//    Chmutov's boxes are mostly such rows and blocks).
// Branch mispredictions at the exits of short loops of varying length, and the loads and
// stores of H, were most of the run-time version's cost. Measured in
// tests/bench/taylor_bench (medians of 5 interleaved runs, ns per ray, with the one-load
// terms of HornerForm::signedTerms()): BM_GalleryDirect Sarti's dodecic 703 -> 311,
// Barth's decic 420 -> 191, Endrass' octic 279 -> 133, Chmutov-16 372 -> 212, sphere
// 63 -> 32; BM_RestrictToRayBox dense degree 12 1537 -> 673 (3 runs). The kernels then
// run at about 1.4 cycles per (value, magnitude) multiply-add pair (2 mulpd + 1 addpd).
// Did not pay (same benchmarks): a table of function pointers instead of the switch over
// row lengths (3-7 % slower); inlining the kernels into boxHorner (5-15 % slower);
// passing the axes as a struct (by value it travels in memory, by reference it is
// reloaded after every store to F: 5-10 % slower); fusing a zero row's F * Y into the
// next row's pass on even surfaces (no change); writing g straight from G without the
// magnitude array (no change, kept as simpler); the bound's factor from a compile-time
// table instead of gamma()'s division per call (no change).
// The same bits need the same roundings: no FMA contraction (none in baseline x86-64,
// and the build's -ffp-contract=off for hosts that build with -march=native).
#include "algray/taylor.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

#include "ray_horner.h"

namespace algray {

namespace {

using ray_horner::hornerStep;
using ray_horner::mulLinear;
using ray_horner::Pair;

// A slot's (c, |c|), the term(c) of ray_horner.h, in one aligned load.
inline Pair load(const HornerForm::SignedTerm& t) {
  static_assert(sizeof(Pair) == sizeof(HornerForm::SignedTerm) &&
                alignof(HornerForm::SignedTerm) == alignof(Pair));
  Pair v;
  std::memcpy(&v, &t, sizeof v);
  return v;
}

// Row lengths and product degrees with unrolled code: up to degree 16 (Chmutov-16's
// z-row has 17 slots); longer ones take the run-time loops.
constexpr int kUnrolled = 17;

// acc <- acc * (p + d s) + q on both chains, acc of degree da (-1: still zero), q of
// degree dq >= 0; returns the new degree. The operations of mulLinear followed by the
// run-time version's add into a zero-filled acc (0 + q[r] stays: it turns -0 into +0),
// fused into one pass when acc is not shorter than q (always, in the gallery's boxes).
inline int mulAdd(Pair* acc, int da, const Pair* q, int dq, Pair p, Pair d) {
  const Pair zero = {0.0, 0.0};
  if (da < 0) {
    for (int r = 0; r <= dq; ++r) acc[r] = zero + q[r];
    return dq;
  }
  if (da + 1 < dq) {
    mulLinear(acc, da, p, d);
    for (int r = da + 2; r <= dq; ++r) acc[r] = zero;
    for (int r = 0; r <= dq; ++r) acc[r] += q[r];
    return dq;
  }
  acc[da + 1] = da + 1 <= dq ? d * acc[da] + q[da + 1] : d * acc[da];
  int r = da;
  for (; r > dq; --r) acc[r] = p * acc[r] + d * acc[r - 1];
  for (; r >= 1; --r) acc[r] = p * acc[r] + d * acc[r - 1] + q[r];
  acc[0] = p * acc[0] + q[0];
  return da + 1;
}

// mulLinear with a compile-time degree N, for a zero row's F <- F * Y and a zero block's
// G <- G * X.
template <int N>
__attribute__((noinline)) void mulLinearN(Pair* q, Pair p, Pair d) {
  q[N + 1] = d * q[N];
#pragma GCC unroll 64
  for (int r = N; r >= 1; --r) q[r] = p * q[r] + d * q[r - 1];
  q[0] = p * q[0];
}

using MulLinearFn = void (*)(Pair*, Pair, Pair);
template <int... N>
constexpr std::array<MulLinearFn, sizeof...(N)> mulLinearTable(std::integer_sequence<int, N...>) {
  return {&mulLinearN<N>...};
}
constexpr auto kMulLinear = mulLinearTable(std::make_integer_sequence<int, kUnrolled>{});

inline void mulLinearAny(Pair* q, int deg, Pair p, Pair d) {
  if (deg < kUnrolled)
    kMulLinear[deg](q, p, d);
  else
    mulLinear(q, deg, p, d);
}

// One z-row of L slots, its first one non-zero (a row ends at its highest non-zero k,
// horner_form.h): the hornerStep sequence with a compile-time length, H in registers.
// Then F <- F * Y + H, mulAdd's fused pass with H's indices known at compile time.
// Not inlined: inlining 17 of them into boxHorner cost 5-15 % (register allocation of
// the one big function), and the Pair arguments travel in registers.
template <int L>
__attribute__((noinline)) void rowStep(const HornerForm::SignedTerm* s, Pair pz, Pair dz, Pair py,
                                       Pair dy, Pair* fy, int& degF) {
  Pair h[L];
  h[0] = load(s[0]);
#pragma GCC unroll 64
  for (int t = 1; t < L; ++t) {
    h[t] = dz * h[t - 1];
#pragma GCC unroll 64
    for (int r = t - 1; r >= 1; --r) h[r] = pz * h[r] + dz * h[r - 1];
    h[0] = pz * h[0] + load(s[t]);
  }
  if (degF < 0 || degF < L - 2) {
    degF = mulAdd(fy, degF, h, L - 1, py, dy);
    return;
  }
  // F's degree da >= L - 2: the top of F * Y, then its indices >= L (no H there), then
  // those with H.
  const int da = degF;
  if constexpr (L >= 2) {
    if (da + 1 == L - 1) {
      fy[L - 1] = dy * fy[L - 2] + h[L - 1];
    } else {
      fy[da + 1] = dy * fy[da];
      for (int r = da; r >= L; --r) fy[r] = py * fy[r] + dy * fy[r - 1];
      fy[L - 1] = py * fy[L - 1] + dy * fy[L - 2] + h[L - 1];
    }
  } else {
    fy[da + 1] = dy * fy[da];
    for (int r = da; r >= 1; --r) fy[r] = py * fy[r] + dy * fy[r - 1];
  }
#pragma GCC unroll 64
  for (int r = L - 2; r >= 1; --r) fy[r] = py * fy[r] + dy * fy[r - 1] + h[r];
  fy[0] = py * fy[0] + h[0];
  degF = da + 1;
}

// Any row: the run-time hornerStep loop.
void rowStepAny(const HornerForm::SignedTerm* s, int len, Pair pz, Pair dz, Pair py, Pair dy,
                Pair* fy, int& degF) {
  Pair fz[kMaxDegree + 2];
  int degH = -1;
  for (const HornerForm::SignedTerm* end = s + len; s != end; ++s)
    hornerStep(fz, degH, s->c, pz, dz);
  if (degH >= 0) {
    degF = mulAdd(fy, degF, fz, degH, py, dy);
  } else if (degF >= 0) {
    mulLinear(fy, degF++, py, dy);
  }
}

// G <- G * X + F when F's degree is G's plus one (a dense-like box), mulAdd's fused pass
// with a compile-time degree N of G.
template <int N>
__attribute__((noinline)) void mulAddN(Pair* acc, const Pair* q, Pair p, Pair d) {
  acc[N + 1] = d * acc[N] + q[N + 1];
#pragma GCC unroll 64
  for (int r = N; r >= 1; --r) acc[r] = p * acc[r] + d * acc[r - 1] + q[r];
  acc[0] = p * acc[0] + q[0];
}

using MulAddFn = void (*)(Pair*, const Pair*, Pair, Pair);
template <int... N>
constexpr std::array<MulAddFn, sizeof...(N)> mulAddTable(std::integer_sequence<int, N...>) {
  return {&mulAddN<N>...};
}
constexpr auto kMulAdd = mulAddTable(std::make_integer_sequence<int, kUnrolled>{});

// G <- G * X + c (a block that is one constant) and F <- F * Y + c (a row of one slot),
// mulAdd's fused pass for q of degree 0 with a compile-time degree N of the accumulator.
template <int N>
__attribute__((noinline)) void mulAddConstN(Pair* acc, Pair c, Pair p, Pair d) {
  acc[N + 1] = d * acc[N];
#pragma GCC unroll 64
  for (int r = N; r >= 1; --r) acc[r] = p * acc[r] + d * acc[r - 1];
  acc[0] = p * acc[0] + c;
}

using MulAddConstFn = void (*)(Pair*, Pair, Pair, Pair);
template <int... N>
constexpr std::array<MulAddConstFn, sizeof...(N)> mulAddConstTable(
    std::integer_sequence<int, N...>) {
  return {&mulAddConstN<N>...};
}
constexpr auto kMulAddConst = mulAddConstTable(std::make_integer_sequence<int, kUnrolled>{});

// G = f(p + s d) on both chains into gx; returns G's degree (-1: zero).
int boxHorner(const HornerForm& f, const glm::dvec3& p, const glm::dvec3& d, Pair* gx) {
  const Pair px = {p.x, std::abs(p.x)}, py = {p.y, std::abs(p.y)}, pz = {p.z, std::abs(p.z)};
  const Pair dx = {d.x, std::abs(d.x)}, dy = {d.y, std::abs(d.y)}, dz = {d.z, std::abs(d.z)};
  Pair fy[kMaxDegree + 2];
  int degG = -1;  // -1: still zero
  const HornerForm::SignedTerm* s = f.signedTerms().data();
  const std::uint8_t* len = f.rowLengths().data();
  for (const std::uint8_t rows : f.blockRows()) {
    int degF = -1;
    for (int r = 0; r < rows; ++r, s += *len++) {
      const int n = *len;
      if (n == 1 && s->c == 0.0) {
        if (degF >= 0) mulLinearAny(fy, degF++, py, dy);  // a zero row: F <- F * Y
        continue;
      }
      if (n == 1 && degF >= 0 && degF < kUnrolled) {
        kMulAddConst[degF++](fy, load(*s), py, dy);
        continue;
      }
      if (s->c == 0.0) {
        rowStepAny(s, n, pz, dz, py, dy, fy, degF);  // not from HornerForm's constructor
      } else {
        // A switch: 3-7 % faster than a table of function pointers (BM_GalleryDirect).
        static_assert(kUnrolled == 17);
        switch (n) {
          case 1:
            rowStep<1>(s, pz, dz, py, dy, fy, degF);
            break;
          case 2:
            rowStep<2>(s, pz, dz, py, dy, fy, degF);
            break;
          case 3:
            rowStep<3>(s, pz, dz, py, dy, fy, degF);
            break;
          case 4:
            rowStep<4>(s, pz, dz, py, dy, fy, degF);
            break;
          case 5:
            rowStep<5>(s, pz, dz, py, dy, fy, degF);
            break;
          case 6:
            rowStep<6>(s, pz, dz, py, dy, fy, degF);
            break;
          case 7:
            rowStep<7>(s, pz, dz, py, dy, fy, degF);
            break;
          case 8:
            rowStep<8>(s, pz, dz, py, dy, fy, degF);
            break;
          case 9:
            rowStep<9>(s, pz, dz, py, dy, fy, degF);
            break;
          case 10:
            rowStep<10>(s, pz, dz, py, dy, fy, degF);
            break;
          case 11:
            rowStep<11>(s, pz, dz, py, dy, fy, degF);
            break;
          case 12:
            rowStep<12>(s, pz, dz, py, dy, fy, degF);
            break;
          case 13:
            rowStep<13>(s, pz, dz, py, dy, fy, degF);
            break;
          case 14:
            rowStep<14>(s, pz, dz, py, dy, fy, degF);
            break;
          case 15:
            rowStep<15>(s, pz, dz, py, dy, fy, degF);
            break;
          case 16:
            rowStep<16>(s, pz, dz, py, dy, fy, degF);
            break;
          case 17:
            rowStep<17>(s, pz, dz, py, dy, fy, degF);
            break;
          default:
            rowStepAny(s, n, pz, dz, py, dy, fy, degF);
            break;
        }
      }
    }
    if (degG >= 0 && degF == degG + 1 && degG < kUnrolled) {
      kMulAdd[degG++](gx, fy, px, dx);
    } else if (degG >= 0 && degF == 0 && degG < kUnrolled) {
      kMulAddConst[degG++](gx, fy[0], px, dx);
    } else if (degF >= 0) {
      degG = mulAdd(gx, degG, fy, degF, px, dx);
    } else if (degG >= 0) {
      mulLinearAny(gx, degG++, px, dx);
    }
  }
  return degG;
}

}  // namespace

std::array<double, kMaxDegree + 1> restrictionUnderflowFloor(const HornerForm& f,
                                                             const glm::dvec3& p,
                                                             const glm::dvec3& d) {
  std::array<double, kMaxDegree + 1> floor{};
  if (f.degree() < 0) return floor;
  ray_horner::UnderflowFloor u;
  ray_horner::initUnderflowFloor(u, f.degree(), p, d, f.absCoeffSum());
  for (int r = 0; r <= f.degree(); ++r) floor[r] = u.at(r);
  return floor;
}

void restrictToRay(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                   RayPolynomial& g) {
  g.tShift = tShift;
  const int m = f.degree();
  g.degree = m;
  if (m < 0) return;
  const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
  // The bound of restrictToRay(const Polynomial&, ...) (taylor.cpp): the same operations,
  // and the same underflow floor (sum |c| added in the same order: the slots are the box).
  // The floor first: its exponent arithmetic then overlaps the box instead of lengthening
  // the path to the bound's stores (5-6 ns of a gallery restriction, BM_GalleryDirect).
  ray_horner::UnderflowFloor floor;
  ray_horner::initUnderflowFloor(floor, m, p, d, f.absCoeffSum());
  Pair gx[kMaxDegree + 2];
  const int degG = boxHorner(f, p, d, gx);
  // Above G's degree coefficient and bound are +0, as RayPolynomial's initialiser
  // leaves them (factor * +0 before).
  const double factor = ray_horner::kRestrictFactor[m];
  for (int i = 0; i <= degG; ++i) {
    g.coeff[i] = gx[i][0];
    g.error[i] = ray_horner::boundOrInfinity(factor * gx[i][1] + floor.at(i));
  }
  for (int i = std::max(degG + 1, 0); i <= m; ++i) g.coeff[i] = g.error[i] = 0.0;
}

RayPolynomial restrictToRay(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift) {
  RayPolynomial g;
  restrictToRay(f, o, d, tShift, g);
  return g;
}

}  // namespace algray
