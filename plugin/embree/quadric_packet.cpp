// Packets through the quadric path (issue 5): the float rays of one rtcIntersect4/8/16 or
// rtcOccluded4/8/16 call, 2, 4 or 8 lanes per instruction (SSE2, AVX2, AVX-512: the same
// group code, quadric_packet_group.inc, for each), from the world-space ray to the first
// root of the quadric's restriction. Every lane's result is the scalar path's bit for bit:
// each value is the same IEEE operations in the same order as objectRay
// (embree_bridge.cpp), quadricSpan, restrictQuadricRay, quadraticFirst and linearFirst
// (quadric_path.cpp) and the glm calls they make (dot (x + y) + z, matrix times vector by
// rows, length = sqrt(dot)); std::max/min/clamp are written with libstdc++'s comparisons
// so that they agree on signed zeros too. No FMA is formed: none of the targets below
// enables it (AVX2 and AVX-512 do not imply FMA), and the one std::fma of the scalar path
// (Kahan's discriminant) is Dekker's exact product here, equal to it whenever the operands
// pass quadraticFirst's range checks.
// What the lanes do not decide exactly - a sample within noise, a ray tangent at or
// leaving from the surface twice, a root needing the library's fallback, rays the tight
// box does not cover, non-finite input - is marked kScalar, and the bridge runs that
// lane's scalar quadricLane.
#include "../core/isa_target.h"
#include "quadric_path.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string_view>
#include <variant>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace algray {

#if defined(__x86_64__)
namespace {

constexpr double kFloatRoundoff = 0x1p-24;  // the bridge's float ray (objectRay's roundoff)
constexpr std::int64_t kAbs = std::numeric_limits<std::int64_t>::max();

// ---- SSE2 (x86-64's baseline): two lanes per register --------------------------------------
// GCC's vector extensions do the arithmetic; comparisons and selects are SSE2's own (cmppd,
// and/andn/or): GCC 12 lowers a vector comparison kept as a mask, and a select on such a
// mask, element by element through general registers (SSE2 has no 64-bit compare), which
// cost more than the lane loop saved. (Four lanes as two SSE2 registers each were measured:
// 1370 instructions a lane, the packets twice slower than the lane loop.)
namespace sse2 {
constexpr unsigned kW = 2;
typedef double VD __attribute__((vector_size(16)));
typedef std::int64_t VI __attribute__((vector_size(16)));
inline VD splat(double x) { return _mm_set1_pd(x); }
inline VD load(const double* p) { return _mm_loadu_pd(p); }
inline void store(double* p, VD v) { _mm_storeu_pd(p, v); }
inline VI lt(VD a, VD b) { return (VI)_mm_cmplt_pd(a, b); }
inline VI le(VD a, VD b) { return (VI)_mm_cmple_pd(a, b); }
inline VI eq(VD a, VD b) { return (VI)_mm_cmpeq_pd(a, b); }
inline VI ne(VD a, VD b) { return (VI)_mm_cmpneq_pd(a, b); }
inline VD vsqrt(VD a) { return _mm_sqrt_pd(a); }  // correctly rounded, as std::sqrt
inline unsigned laneBits(VI m) { return static_cast<unsigned>(_mm_movemask_pd((VD)m)); }
// The sign bit spread over its lane (psrad on the high half, then pshufd).
inline VI signMask(VD a) {
  return (VI)_mm_shuffle_epi32(_mm_srai_epi32((__m128i)a, 31), _MM_SHUFFLE(3, 3, 1, 1));
}
#include "quadric_packet_group.inc"
}  // namespace sse2

// ---- AVX2: four lanes per register, when the CPU has it (checked at run time) ---------------
ALGRAY_TARGET_BEGIN("avx2")
namespace avx2 {
constexpr unsigned kW = 4;
typedef double VD __attribute__((vector_size(32)));
typedef std::int64_t VI __attribute__((vector_size(32)));
inline VD splat(double x) { return _mm256_set1_pd(x); }
inline VD load(const double* p) { return _mm256_loadu_pd(p); }
inline void store(double* p, VD v) { _mm256_storeu_pd(p, v); }
inline VI lt(VD a, VD b) { return (VI)_mm256_cmp_pd(a, b, _CMP_LT_OQ); }
inline VI le(VD a, VD b) { return (VI)_mm256_cmp_pd(a, b, _CMP_LE_OQ); }
inline VI eq(VD a, VD b) { return (VI)_mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
inline VI ne(VD a, VD b) { return (VI)_mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
inline VD vsqrt(VD a) { return _mm256_sqrt_pd(a); }
inline unsigned laneBits(VI m) { return static_cast<unsigned>(_mm256_movemask_pd((VD)m)); }
inline VI signMask(VD a) {
  return (VI)_mm256_shuffle_epi32(_mm256_srai_epi32((__m256i)a, 31), _MM_SHUFFLE(3, 3, 1, 1));
}
#include "quadric_packet_group.inc"
}  // namespace avx2
ALGRAY_TARGET_END

// ---- AVX-512 (F and DQ): eight lanes per register, for packets of five or more lanes -------
// An 8-ray packet in one group instead of two: the sphere's 8-ray shadow packets 1.09x as
// fast as with AVX2, primary packets within noise (three interleaved runs of 512 x 512
// rays, ALGRAY_PACKET_ISA=avx2 against the default). AVX-512 implies no FMA either.
ALGRAY_TARGET_BEGIN("avx512f,avx512dq")
namespace avx512 {
constexpr unsigned kW = 8;
typedef double VD __attribute__((vector_size(64)));
typedef std::int64_t VI __attribute__((vector_size(64)));
inline VD splat(double x) { return _mm512_set1_pd(x); }
inline VD load(const double* p) { return _mm512_loadu_pd(p); }
inline void store(double* p, VD v) { _mm512_storeu_pd(p, v); }
inline VI mask(__mmask8 m) { return (VI)_mm512_movm_epi64(m); }
inline VI lt(VD a, VD b) { return mask(_mm512_cmp_pd_mask(a, b, _CMP_LT_OQ)); }
inline VI le(VD a, VD b) { return mask(_mm512_cmp_pd_mask(a, b, _CMP_LE_OQ)); }
inline VI eq(VD a, VD b) { return mask(_mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ)); }
inline VI ne(VD a, VD b) { return mask(_mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ)); }
// (The masked forms with every lane set: GCC 12's unmasked ones read an undefined source
// register that -Wuninitialized flags.)
inline VD vsqrt(VD a) { return _mm512_mask_sqrt_pd(a, 0xff, a); }
inline unsigned laneBits(VI m) { return static_cast<unsigned>(_mm512_movepi64_mask((__m512i)m)); }
inline VI signMask(VD a) { return (VI)_mm512_mask_srai_epi64((__m512i)a, 0xff, (__m512i)a, 63); }
#include "quadric_packet_group.inc"
}  // namespace avx512
ALGRAY_TARGET_END

// The widest lanes the CPU has. ALGRAY_PACKET_ISA=sse2 or avx2 keeps narrower ones on a
// wider machine: the tests run each (tests/CMakeLists.txt), and speed runs can compare.
enum class PacketIsa { Sse2, Avx2, Avx512 };
PacketIsa packetIsa() {
  static const PacketIsa isa = [] {
    const char* env = std::getenv("ALGRAY_PACKET_ISA");
    const std::string_view want = env ? env : "";
    __builtin_cpu_init();
    if (want == "sse2" || !__builtin_cpu_supports("avx2")) return PacketIsa::Sse2;
    if (want == "avx2" || !__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("avx512dq"))
      return PacketIsa::Avx2;
    return PacketIsa::Avx512;
  }();
  return isa;
}

}  // namespace
#endif  // __x86_64__

bool usesQuadricPacket(const SurfaceData& data) {
#if !defined(__x86_64__)
  (void)data;
  return false;  // the lane loop (no SIMD path written for other targets)
#else
  const auto* sphere = std::get_if<ClipSphere>(&data.desc.clip);
  // The re-centring point is the clip sphere's closest point (quadricSpan passes tc only
  // when the sphere is centred on data.centre); a cell the build shrank below the tight
  // box has no QuadricBox and every ray would be clipped to it (left to the scalar path).
  return usesQuadricPath(data) && data.desc.options.packetSimd && data.desc.options.recentre &&
         sphere && sphere->center == data.centre &&
         (!data.quadricCellClip || data.quadricBox.distance >= 0.0);
#endif
}

void quadricPacket(const SurfaceData& data, QuadricPacket& p) noexcept {
#if !defined(__x86_64__)
  (void)data;
  for (unsigned i = 0; i < p.count; ++i) p.status[i] = QuadricPacket::kScalar;
#else
  const ClipSphere& sphere = *std::get_if<ClipSphere>(&data.desc.clip);  // usesQuadricPacket
  // objectRay's Frobenius norm of A^-1 and |b|, the same operations once per packet (and
  // only for a transform: two roots on the critical path of every packet otherwise).
  double invNorm = 0.0, lenB = 0.0;
  if (!data.identity) {
    invNorm =
        std::sqrt(glm::dot(data.aInv[0], data.aInv[0]) + glm::dot(data.aInv[1], data.aInv[1]) +
                  glm::dot(data.aInv[2], data.aInv[2]));
    lenB = glm::length(data.b);
  }
  // Pad to whole vectors with copies of the first lane (computed, never read); a last
  // lane alone in its vector is cheaper by the scalar path (measured: three active lanes
  // of an 8-ray packet with SSE2, 0.96x of the lane loop when padded to four).
  const PacketIsa isa = packetIsa();
  // Eight lanes when there are more than four (a 4-ray packet, or a half-empty 8-ray one,
  // pads less in AVX2's four).
  const bool wide = isa != PacketIsa::Sse2, widest = isa == PacketIsa::Avx512 && p.count > avx2::kW;
  const unsigned width = widest ? avx512::kW
                         : wide ? avx2::kW
                                : sse2::kW,
                 full = p.count / width * width;
  const unsigned end = p.count - full > 1 ? full + width : full;
  if (end < p.count) p.status[full] = QuadricPacket::kScalar;
  for (unsigned i = p.count; i < end; ++i) {
    p.ox[i] = p.ox[0];
    p.oy[i] = p.oy[0];
    p.oz[i] = p.oz[0];
    p.dx[i] = p.dx[0];
    p.dy[i] = p.dy[0];
    p.dz[i] = p.dz[0];
    p.tnear[i] = p.tnear[0];
    p.tfar[i] = p.tfar[0];
  }
  if (widest)
    avx512::quadricLanes(data, sphere, invNorm, lenB, p, end);
  else if (wide)
    avx2::quadricLanes(data, sphere, invNorm, lenB, p, end);
  else
    sse2::quadricLanes(data, sphere, invNorm, lenB, p, end);
#endif
}

}  // namespace algray
