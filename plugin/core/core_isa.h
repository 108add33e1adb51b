#pragma once
// Which kernels the math core runs (private; tests include it to run both): the baseline
// x86-64 ones (SSE2, 2-double vectors) or AVX2 clones of the hot ones (4-double vectors:
// the direct restriction over a HornerForm's box, taylor_box_avx.cpp, and
// HornerForm::evaluate's z-rows). Both compute the same bits: the same operations in the
// same order per lane, separate multiplies and adds (no FMA: the rounding-error bounds are
// derived for exactly these roundings), only more lanes per instruction.
//
// The default build targets baseline x86-64, so the AVX2 code is compiled per function
// (ALGRAY_TARGET_BEGIN, isa_target.h) and chosen at run time, once per process: AVX2 where
// the CPU has it, unless ALGRAY_CORE_ISA=sse2 (the tests run both, tests/CMakeLists.txt).
#include <atomic>

namespace algray::core_isa {

enum class Isa : signed char { kSse2 = 0, kAvx2 = 1 };

// Whether the AVX2 kernels exist in this build: x86-64 with GCC or Clang (the compilers
// isa_target.h serves).
#if defined(__x86_64__) && defined(__GNUC__)
#define ALGRAY_CORE_AVX2 1
#else
#define ALGRAY_CORE_AVX2 0
#endif

namespace detail {
extern std::atomic<signed char> active;  // an Isa, or -1 before the first call
Isa detect();
}  // namespace detail

// The kernels in use (a relaxed load and a predicted branch per call).
inline Isa active() {
  const signed char v = detail::active.load(std::memory_order_relaxed);
  return v >= 0 ? static_cast<Isa>(v) : detail::detect();
}

// For tests: run `isa` from now on; false (and no change) if this CPU or build lacks it.
bool select(Isa isa);

}  // namespace algray::core_isa
