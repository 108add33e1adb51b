#pragma once
// Code compiled for an instruction set the build does not target (the kernels chosen at run
// time, core_isa.h and quadric_packet.cpp): everything between ALGRAY_TARGET_BEGIN("avx2")
// and ALGRAY_TARGET_END is built for that ISA whatever the build's -march. GCC takes
// `#pragma GCC target` for a region; Clang does not, and instead gives every function
// declared in the region the same `target` attribute (`#pragma clang attribute`), which is
// what GCC's pragma does too.
#define ALGRAY_PRAGMA(x) _Pragma(#x)
#if defined(__clang__)
#define ALGRAY_TARGET_BEGIN(isa) \
  ALGRAY_PRAGMA(clang attribute push(__attribute__((target(isa))), apply_to = function))
#define ALGRAY_TARGET_END ALGRAY_PRAGMA(clang attribute pop)
#else
#define ALGRAY_TARGET_BEGIN(isa) ALGRAY_PRAGMA(GCC push_options) ALGRAY_PRAGMA(GCC target(isa))
#define ALGRAY_TARGET_END ALGRAY_PRAGMA(GCC pop_options)
#endif
