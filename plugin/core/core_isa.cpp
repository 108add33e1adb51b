#include "core_isa.h"

#include <cstdlib>
#include <string_view>

namespace algray::core_isa {

namespace {

bool cpuHasAvx2() {
#if ALGRAY_CORE_AVX2
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

}  // namespace

namespace detail {

std::atomic<signed char> active{-1};

Isa detect() {
  const char* env = std::getenv("ALGRAY_CORE_ISA");
  const bool sse2 = env != nullptr && std::string_view(env) == "sse2";
  const Isa isa = !sse2 && cpuHasAvx2() ? Isa::kAvx2 : Isa::kSse2;
  active.store(static_cast<signed char>(isa), std::memory_order_relaxed);
  return isa;
}

}  // namespace detail

bool select(Isa isa) {
  if (isa == Isa::kAvx2 && !cpuHasAvx2()) return false;
  detail::active.store(static_cast<signed char>(isa), std::memory_order_relaxed);
  return true;
}

}  // namespace algray::core_isa
