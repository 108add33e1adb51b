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
//
// The kernels live in taylor_box_kernels.inc, compiled here for baseline x86-64 and in
// taylor_box_avx.cpp for AVX2, chosen per call by core_isa::active() (core_isa.h). The
// AVX2 copy runs the same 2-lane vectors, VEX-encoded: three-operand instructions drop
// the register copies the unrolled kernels needed. The kernels start on 64-byte
// boundaries: without, the AVX2 copy's gain came and went with the code layout (Sarti's
// dodecic 460-500 ns in builds that did not touch this code). Measured (taylor_bench
// BM_GalleryDirect, AMD EPYC Zen 3, ns per ray, the two paths of one binary, 3
// interleaved runs, two layouts): Sarti's dodecic 502-514 -> 450-470, Barth's decic
// 317-323 -> 289-300, the sphere 71 -> 68.5, the Barth sextic 134 -> 133-142 (noise of
// the layout); primary rays of speed_report (one thread, Mrays/s, medians of 3):
// Barth sextic 2.86 -> 2.99, Sarti's dodecic 0.93 -> 1.00 (with evaluate's AVX2 kernel).
// The whole restriction is in the AVX2 file (with only boxHorner there, the extra call
// cost the sphere 9 ns), compiled without the loop vectoriser (plugin/CMakeLists.txt).
// Did not pay with AVX2: two z-rows of a block at once, H of one row in each half of a
// 4-double vector (the rows after the zero rows between them; F <- F * Y + H still per row,
// in order). Aligned at their ends (blends for the shorter row's first slot and top
// coefficients) Sarti's dodecic took 499 ns and the Barth sextic 143; aligned at their
// starts (no blends) 483 and 137; the AVX2 kernels one row at a time 461 and 132 (same
// session). A row's H is a chain of dependent multiply-adds (latency, not throughput, bounds
// it) and out-of-order execution already overlaps one row's H with the previous row's F
// update; a pair delays the first row's F update until the longer H is done.
//
// ---- Even axes: the restriction on squared coordinates (taylor_box_even_kernels.inc) ----
// When every exponent of x (y, z) is even, f(x, y, z) = F(x^2, y, z) (HornerForm's
// evenAxes(), horner_form.cpp "Even axes"), and along the ray x^2 is the quadratic
//   X(s) = (p_x + s d_x)^2 = a0 + a1 s + a2 s^2,  a0 = p_x^2, a1 = 2 p_x d_x, a2 = d_x^2,
// so the nested Horner scheme runs over F's box (about half the slots per even axis)
// with one quadratic step in place of two linear ones: a z-row of L = 2L' - 1 slots of
// f's box (~4 L'^2 pair multiply-adds) becomes L' slots of F's (~3 L'^2). Taken when
// HornerForm::restrictsOnSquares(p, d): every component of p and d +-0 or normal, those
// on an even axis in [2^-400, 2^401) (the range of evaluate()'s reduced path); otherwise
// f's own box runs as before (non-finite and subnormal components among them).
//
// Bound (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., model (2.4)
// per operation, Lemma 3.1). The computed factor is fl(p^2), 2 fl(p d) (the doubling
// exact), fl(d^2): each within one rounding of the exact coefficient (in range all three
// are normal and finite: |p|, |d| >= 2^-400 gives products >= 2^-800, < 2^401 gives
// < 2^803). A coefficient of a quadratic step is ((a0 A_r + a1 A_{r-1}) + a2 A_{r-2}) + q_r:
// a term through a0 or a1 collects the factor's rounding, the product's and three
// additions (5), one through a2 four, q_r one. Two linear steps of f's own scheme put up to
// 3 + 3 = 6 on a term. So a slot (a, b, c) of F's box collects at most as many roundings
// as its slot (2a, b, c) (etc.) of f's box: the same additions where it enters each level,
// and per even-axis step 5 instead of 6. Every term of coefficient r of g is then the exact
// product of a coefficient, one coefficient of an exact factor per step, and
// (1 + theta_n) with n <= 3m + 3 (taylor.cpp: "Every coefficient of g is reached through
// at most m linear-factor steps ..."). The exact factors' magnitudes are the coefficients
// of (|p_a| + s |d_a|)^2, so the terms' magnitudes sum to the coefficient of
// |f|(|p| + s |d|) the linear scheme bounds with, and the magnitude chain runs the same
// operations on |c|, |p_a|^2, 2 |p_a| |d_a|, |d_a|^2: the same factor
// gamma_{3m+3} (1 + gamma_{3m+3}) (kRestrictFactor) covers it. (Loose by one rounding per
// quadratic step; a count per box, as evaluate() keeps, would tighten it slightly.)
//
// Underflow: the floor of taylor.cpp ("Underflow") carries over. An eta travels through
// the computed factors, whose magnitudes are at most (1 + u) (|p_a| + s |d_a|)^2 <=
// (1 + u) (P + s D)^2 coefficientwise (P = max(1, |p_a|), D = max(1, |d_a|)): a quadratic
// step acts as two linear factors of the argument there, and (1 + u)^(m/2) is inside its
// (1 + gamma) slack. The number of etas: a quadratic step on an accumulator of degree
// <= m - 2 takes at most 3 (m - 1) products and 2 (m - 1) + (m + 1) additions, together
// 6m - 4 < 2 (4m + 3), the allowance of the two linear steps of f's box it stands for
// (f's box has the slots, rows or blocks 2a and 2a - 1 for F's a, the odd ones zero); so
// counting a quadratic step twice, F's scheme has no more steps than f's, and taylor.cpp's
// N <= 4 (m + 2) termCount(m + 1) still counts them. The factors themselves never
// underflow (range above), and no component is subnormal on this path (DAZ reads nothing
// as 0), so the same UnderflowFloor (f's degree, P, D and sum |c|) bounds the rest.
// Non-finite input (inf, NaN, a square that would overflow) never takes this path.
//
// Kernels: the z-row's H with compile-time length (K = 2 rows up to 11 slots), F <- F Y + H
// unrolled when F has the dense-like degree (every gallery row but a block's first, which
// copies H), and tables of unrolled passes per accumulator degree for one-constant and
// zero rows and blocks (Chmutov's) and dense-like blocks; run-time loops for other shapes.
// Measured (taylor_bench BM_GalleryDirect/horner-box, AMD EPYC Zen 3, AVX2, pinned to one
// core, ns per ray, medians of 5 interleaved runs against the parent commit, ranges over
// the runs; the host is noisy): Sarti's dodecic 509 (493-545) -> 322 (318-326), Barth's
// decic 298 (291-453) -> 238 (236-240), Endrass' octic 276 -> 169, Chmutov-12 240 -> 179,
// Chmutov-16 367 -> 240, the heart 170 -> 122, the Barth sextic 137 -> 121, Kummer's
// quartic 103 -> 93, the torus 103 -> 92.5; the quadrics (on f's box from here, see
// HornerForm::restrictsOnSquares) and the odd cubics unchanged within the noise (sphere
// 70.7 -> 69.7, Clebsch 105 -> 101, Roman 91.3 -> 90.3). SSE2 kernels (ALGRAY_CORE_ISA=sse2,
// medians of 3): Sarti 555 -> 385, Barth decic 331 -> 247, Chmutov-16 389 -> 264. Primary
// rays (speed_report, one thread, Mrays/s, medians of 3 interleaved pairs): Sarti
// 1.16 -> 1.31, Barth decic 1.56 -> 1.65, Chmutov-12 1.55 -> 1.68, torus 3.86 -> 4.17; the
// Barth sextic 3.14 -> 3.10 (7 pairs: 3.08-3.17 -> 2.71-3.12; its shadow rays 2.37 -> 2.39).
//
#include "algray/taylor.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

#include "core_isa.h"
#include "ray_horner.h"
#include "taylor_box_avx.h"

namespace algray {

namespace {

#include "taylor_box_kernels.inc"

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
#if ALGRAY_CORE_AVX2
  if (core_isa::active() == core_isa::Isa::kAvx2) return restrictToRayAvx2(f, o, d, tShift, g);
#endif
  restrictBox(f, o, d, tShift, g);
}

RayPolynomial restrictToRay(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift) {
  RayPolynomial g;
  restrictToRay(f, o, d, tShift, g);
  return g;
}

}  // namespace algray
