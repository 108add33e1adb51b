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
