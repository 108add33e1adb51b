// The direct restriction's box scheme (taylor_box_kernels.inc) compiled for AVX2, chosen
// at run time (core_isa.h). The same source, so the same operations in the same order
// (no FMA: the build's -ffp-contract=off), on the same 2-lane (value, magnitude) vectors:
// the same bits. What AVX2 brings is the VEX encoding: three-operand instructions, so
// fewer register copies in the unrolled kernels (p * q[r] + d * q[r - 1] no longer copies
// p or d first).
#include "taylor_box_avx.h"

#if ALGRAY_CORE_AVX2

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "algray/taylor.h"
#include "isa_target.h"
#include "ray_horner.h"

ALGRAY_TARGET_BEGIN("avx2")

namespace algray {

namespace {

#include "taylor_box_kernels.inc"

}  // namespace

void restrictToRayAvx2(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                       RayPolynomial& g) {
  restrictBox(f, o, d, tShift, g);
}

}  // namespace algray

ALGRAY_TARGET_END

#endif  // ALGRAY_CORE_AVX2
