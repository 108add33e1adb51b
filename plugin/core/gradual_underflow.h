#pragma once
// Gradual underflow for the scope of one call (private to plugin/core; not installed).
//
// The interval arithmetic of interval.h assumes IEEE gradual underflow: a rounded sum is 0
// only if the exact sum is, and a product that underflows is off by at most the smallest
// subnormal, which its widening adds (Hauser, "Handling floating-point exceptions in
// numeric programs", TOPLAS 1996). Threads with flush-to-zero and denormals-are-zero
// (Embree's and TBB's workers, and so a host that builds surfaces inside tbb::parallel_for)
// flush such results and that widening itself to 0: buildCells dropped cells a surface
// passes through (tests/cells_test.cpp, CellsTest.FlushToZeroLosesNoCell). The entry
// points that run interval arithmetic (buildCells, rangeOverBox, rangeOverInterval) hold
// this guard: it clears FTZ and DAZ for their duration and restores the caller's mode,
// also when they throw. It costs two MXCSR accesses per call; the per-ray kernels do not
// use it (their bounds count 2^-1022 per operation instead, taylor.cpp).
// x86 only (MXCSR); elsewhere a no-op.
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace algray {

class GradualUnderflow {
 public:
#if defined(__SSE__)
  GradualUnderflow() : saved_(_mm_getcsr()) {
    if (saved_ & kFlush) _mm_setcsr(saved_ & ~kFlush);
  }
  ~GradualUnderflow() {
    if (saved_ & kFlush) _mm_setcsr(saved_);
  }
#endif
  GradualUnderflow(const GradualUnderflow&) = delete;
  GradualUnderflow& operator=(const GradualUnderflow&) = delete;

#if defined(__SSE__)
 private:
  static constexpr unsigned kFlush = 0x8040u;  // FTZ (bit 15) | DAZ (bit 6)
  unsigned saved_;
#endif
};

}  // namespace algray
