#pragma once
// The direct restriction's box scheme with AVX2 kernels (taylor_box_avx.cpp; private).
// Call only when core_isa::active() is Isa::kAvx2: it is compiled for AVX2.
#include <glm/vec3.hpp>

#include "algray/horner_form.h"
#include "algray/taylor.h"
#include "core_isa.h"

namespace algray {

#if ALGRAY_CORE_AVX2
// restrictToRay(const HornerForm&, ...) (taylor.h), the same bits.
void restrictToRayAvx2(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                       RayPolynomial& g);
#endif

}  // namespace algray
