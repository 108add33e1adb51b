// Packets through the quadric path (issue 5): the float rays of one rtcIntersect4/8/16 or
// rtcOccluded4/8/16 call, four at a time in GCC vector extensions (two SSE2 registers
// each on baseline x86-64), from the world-space ray to the first root of the quadric's
// restriction. Every lane's result is the scalar path's bit for bit: each value below is
// the same IEEE operations in the same order as objectRay (embree_bridge.cpp),
// quadricSpan, restrictQuadricRay, quadraticFirst and linearFirst (quadric_path.cpp) and
// the glm calls they make (dot (x + y) + z, matrix times vector by rows, length =
// sqrt(dot)); std::max/min/clamp are written with libstdc++'s comparisons so that they
// agree on signed zeros too. No FMA is formed: the build targets SSE2, which has none, and
// the one std::fma of the scalar path (Kahan's discriminant) is Dekker's exact product
// here, equal to it whenever the operands pass quadraticFirst's range checks.
// What this file does not decide exactly - a sample within noise, a ray tangent at or
// leaving from the surface twice, a root needing the library's fallback, rays the tight
// box does not cover, non-finite input - is marked kScalar, and the bridge runs that
// lane's scalar quadricLane.
#include "surface_data.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace algray {

#if defined(__SSE2__)
namespace {

// Two lanes per vector: one SSE2 register. GCC's vector extensions do the arithmetic;
// comparisons and selects are SSE2's own (cmppd, and/andn/or): GCC 12 lowers a vector
// comparison kept as a mask, and a select on such a mask, element by element through
// general registers (no 64-bit compare in SSE2), which cost more than the lane loop saved.
// (Four lanes, as two registers each, were measured: 1370 instructions a lane, the
// packets twice slower than the lane loop.)
constexpr unsigned kW = 2;
typedef double VD __attribute__((vector_size(16)));
typedef std::int64_t VI __attribute__((vector_size(16)));  // masks: all ones or zero

constexpr double kFloatRoundoff = 0x1p-24;  // the bridge's float ray (objectRay's roundoff)
constexpr std::int64_t kAbs = std::numeric_limits<std::int64_t>::max();

inline VD splat(double x) { return _mm_set1_pd(x); }
inline VD load(const double* p) { return _mm_loadu_pd(p); }
inline void store(double* p, VD v) { _mm_storeu_pd(p, v); }
inline VD vabs(VD a) { return (VD)((VI)a & kAbs); }
inline VD copySign(VD mag, VD sign) { return (VD)(((VI)mag & kAbs) | ((VI)sign & ~kAbs)); }
// C++'s comparisons: ordered (false with a NaN), != unordered (true with a NaN).
inline VI lt(VD a, VD b) { return (VI)_mm_cmplt_pd(a, b); }
inline VI le(VD a, VD b) { return (VI)_mm_cmple_pd(a, b); }
inline VI eq(VD a, VD b) { return (VI)_mm_cmpeq_pd(a, b); }
inline VI ne(VD a, VD b) { return (VI)_mm_cmpneq_pd(a, b); }
inline VD blend(VI m, VD a, VD b) { return (VD)(((VI)a & m) | ((VI)b & ~m)); }  // m ? a : b
// std::max(a, b) and std::min(a, b) of libstdc++: a < b ? b : a, and b < a ? b : a.
inline VD vmax(VD a, VD b) { return blend(lt(a, b), b, a); }
inline VD vmin(VD a, VD b) { return blend(lt(b, a), b, a); }
inline VI finite(VD a) { return eq(a - a, splat(0.0)); }
inline VD vsqrt(VD a) { return _mm_sqrt_pd(a); }  // correctly rounded, as std::sqrt
inline unsigned laneBits(VI m) { return static_cast<unsigned>(_mm_movemask_pd((VD)m)); }
inline bool any(VI m) { return laneBits(m) != 0; }
// inRange of quadric_path.cpp.
inline VI inRange(VD x) {
  const VD a = vabs(x);
  return eq(x, splat(0.0)) | (le(splat(1e-100), a) & le(a, splat(1e100)));
}
// a b - fl(a b) exactly (Dekker's product by Veltkamp's split), i.e. std::fma(a, b, -p):
// exact when no split overflows and no partial product underflows, which |a|, |b| in
// [1e-100, 4e100] or 0 guarantee (the products' low parts are multiples of ~1e-232).
inline VD productError(VD a, VD b, VD p) {
  const VD ca = 134217729.0 * a, cb = 134217729.0 * b;  // 2^27 + 1
  const VD ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
  return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

struct V3 {
  VD x, y, z;
};
inline VD dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 vabs(const V3& a) { return {vabs(a.x), vabs(a.y), vabs(a.z)}; }
// glm's mat3 * vec3: row r is m[0][r] v.x + m[1][r] v.y + m[2][r] v.z.
inline V3 mul(const glm::dmat3& m, const V3& v) {
  return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
          m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}
inline V3 blend(VI m, const V3& a, const V3& b) { return {blend(m, a.x, b.x), blend(m, a.y, b.y), blend(m, a.z, b.z)}; }

// evalQuadric (surface_data.h).
struct Value {
  VD value, error;
  V3 gradient;
};
inline Value evalQuadric(const QuadricForm& q, const V3& p) {
  const V3 ap = mul(q.a, p), absP = vabs(p);
  const V3 b{splat(q.b.x), splat(q.b.y), splat(q.b.z)}, absB{splat(q.absB.x), splat(q.absB.y), splat(q.absB.z)};
  const VD sumAbs = dot(absP, mul(q.absA, absP)) + dot(absB, absP) + std::abs(q.c);
  return {dot(p, ap) + dot(b, p) + q.c, gamma(8) * sumAbs,
          {2.0 * ap.x + q.b.x, 2.0 * ap.y + q.b.y, 2.0 * ap.z + q.b.z}};
}

// safeLength (surface_data.h); std::max({x, y, z}) keeps the first largest.
inline VD safeLength(const V3& v) {
  const VD m = vmax(vmax(vabs(v.x), vabs(v.y)), vabs(v.z));
  const V3 w{v.x / m, v.y / m, v.z / m};
  return blend(lt(splat(0.0), m) & finite(m), m * vsqrt(dot(w, w)), m);
}

// The status of lane k from the decisions' lane bits, in quadricSpan's and quadricRoot's
// order (the first decisive one wins).
struct Decisions {
  unsigned ok = 0, sphere = 0, covered = 0, span = 0, again = 0, sSpan = 0, on = 0;
  unsigned linSafe = 0, linNone = 0, linFound = 0, quadSafe = 0, quadRoot = 0, quadFound = 0;
};
int laneStatus(const Decisions& b, unsigned k) {
  const auto has = [k](unsigned bits) { return (bits >> k & 1u) != 0; };
  if (!has(b.ok)) return QuadricPacket::kScalar;
  if (!has(b.sphere)) return QuadricPacket::kNone;
  if (!has(b.covered)) return QuadricPacket::kScalar;
  if (!has(b.span)) return QuadricPacket::kNone;
  if (has(b.again)) return QuadricPacket::kScalar;
  if (!has(b.sSpan)) return QuadricPacket::kNone;
  if (has(b.on))
    return !has(b.linSafe) ? QuadricPacket::kScalar
           : has(b.linNone) ? QuadricPacket::kNone
           : has(b.linFound) ? QuadricPacket::kRoot
                             : QuadricPacket::kScalar;
  return !has(b.quadSafe)   ? QuadricPacket::kScalar
         : !has(b.quadRoot) ? QuadricPacket::kNone
         : has(b.quadFound) ? QuadricPacket::kRoot
                            : QuadricPacket::kScalar;
}

void writeStatus(const Decisions& b, QuadricPacket& p, unsigned i) {
  for (unsigned k = 0; k < kW; ++k) {
    p.status[i + k] = laneStatus(b, k);
    p.degree[i + k] = (b.on >> k & 1u) != 0 ? 1 : 2;
  }
}

// kW lanes from index i. Each stage runs only when a lane still needs it: lanes that
// miss the clip sphere (a third of a camera's), leave the surface (shadow rays: no
// re-centring, the linear root) or stay off it (no division by s) skip the rest.
void quadricGroup(const SurfaceData& data, const ClipSphere& sphere, double invNorm, double lenB, QuadricPacket& p,
                  unsigned i) {
  const QuadricForm& q = *data.quadric;
  Decisions b;
  // ---- objectRay for a float ray (orgError 0, roundoff u_float) ---------------------------
  V3 o{load(p.ox + i), load(p.oy + i), load(p.oz + i)}, d{load(p.dx + i), load(p.dy + i), load(p.dz + i)};
  const VD tnear = load(p.tnear + i), tfar = load(p.tfar + i);
  VD orgError = splat(0.0);
  if (!data.identity) {
    const V3 wo = o;
    o = mul(data.aInv, V3{wo.x - data.b.x, wo.y - data.b.y, wo.z - data.b.z});
    d = mul(data.aInv, d);
    orgError = invNorm * (orgError + 4.0 * kFloatRoundoff * (vsqrt(dot(wo, wo)) + lenB));
  }
  const V3 oc{o.x - data.centre.x, o.y - data.centre.y, o.z - data.centre.z};
  orgError += 16.0 * kFloatRoundoff * (vsqrt(dot(oc, oc)) + data.radius);

  // ---- quadricSpan: input, clip sphere, the tight box's coverage, (tnear, tfar) ------------
  const VD dd = dot(d, d);
  const VI ok = finite(o.x) & finite(o.y) & finite(o.z) & finite(d.x) & finite(d.y) & finite(d.z) &
                eq(tnear, tnear) & eq(tfar, tfar) & le(splat(0.0), orgError) & lt(splat(0.0), dd) &
                lt(tnear, tfar);
  const V3 sc{o.x - sphere.center.x, o.y - sphere.center.y, o.z - sphere.center.z};
  const VD tc = -dot(sc, d) / dd;
  const V3 cq{sc.x + tc * d.x, sc.y + tc * d.y, sc.z + tc * d.z};
  const VD h2 = sphere.radius * sphere.radius - dot(cq, cq);
  const VD dt = vsqrt(h2 / dd);
  const VD r0 = vmax(splat(-std::numeric_limits<double>::infinity()), tc - dt),
           r1 = vmin(splat(std::numeric_limits<double>::infinity()), tc + dt);
  const VI inSphere = le(splat(0.0), h2) & le(r0, r1);
  VI covered = eq(tnear, tnear) | ~eq(tnear, tnear);  // all set
  if (data.quadricCellClip) {
    const QuadricBox& box = data.quadricBox;
    covered = le(orgError, splat(box.orgError)) & le(dot(oc, oc), splat(box.distance * box.distance));
  }
  const VD lo = vmax(r0, tnear), hi = vmin(r1, tfar);
  const VI inSpan = lt(lo, hi);
  b.ok = laneBits(ok);
  b.sphere = laneBits(inSphere);
  b.covered = laneBits(covered);
  b.span = laneBits(inSpan);
  if ((b.ok & b.sphere & b.covered & b.span) == 0) return writeStatus(b, p, i);

  // ---- restrictQuadricRay: the self-root rule, then re-centring --------------------------------
  const V3 absD = vabs(d);
  const Value atO = evalQuadric(q, o);
  const V3 absG = vabs(atO.gradient);
  const VD moveRound = kFloatRoundoff * dot(absG, vabs(o));
  const VD moveUpper = moveRound + (1.0 + 0x1p-20) * (absG.x + absG.y + absG.z) * orgError;
  const VD absV = vabs(atO.value);
  VI onSurface = ~lt(4.0 * atO.error + 2.0 * moveUpper, absV);
  if (any(onSurface)) {
    const VD move = blend(ne(orgError, splat(0.0)), safeLength(atO.gradient) * orgError, splat(0.0));
    onSurface &= le(absV, 4.0 * atO.error + 2.0 * (moveRound + move));
  }
  b.on = laneBits(onSurface);
  const bool anyOff = b.on != (1u << kW) - 1, anyOn = b.on != 0;
  VD tShift = splat(0.0), value = atO.value, valueError = atO.error, shiftError0 = splat(0.0),
     shiftError1 = splat(0.0);
  V3 p3 = o, grad = atO.gradient;
  if (anyOff) {
    // std::clamp(tc, r0, r1) = std::min(std::max(tc, r0), r1).
    tShift = blend(onSurface, splat(0.0), vmin(vmax(tc, r0), r1));
    const V3 pShift{o.x + tShift * d.x, o.y + tShift * d.y, o.z + tShift * d.z};
    const Value atP = evalQuadric(q, pShift);
    const V3 absPShift = vabs(pShift);
    const VD absT = vabs(tShift);
    const V3 off{gamma(2) * (absPShift.x + absT * absD.x), gamma(2) * (absPShift.y + absT * absD.y),
                 gamma(2) * (absPShift.z + absT * absD.z)};
    shiftError0 = blend(onSurface, splat(0.0), dot(vabs(atP.gradient), off));
    shiftError1 = blend(onSurface, splat(0.0), 2.0 * dot(mul(q.absA, off), absD));
    p3 = blend(onSurface, o, pShift);
    grad = blend(onSurface, atO.gradient, atP.gradient);
    value = blend(onSurface, atO.value, atP.value);
    valueError = blend(onSurface, atO.error, atP.error);
  }
  const V3 absAP = mul(q.absA, vabs(p3));
  const V3 w{2.0 * absAP.x + q.absB.x, 2.0 * absAP.y + q.absB.y, 2.0 * absAP.z + q.absB.z};
  const VD c0 = value, c1 = dot(grad, d), c2 = dot(d, mul(q.a, d));
  const VD e0 = valueError + shiftError0, e1 = gamma(7) * dot(w, absD) + shiftError1,
           e2 = gamma(5) * dot(absD, mul(q.absA, absD));
  // deflateAtZero on the self-root lanes: g / s, degree 1; a second division (tangent at
  // the origin) is left to the scalar path.
  const VD g0 = blend(onSurface, c1, c0), g1 = blend(onSurface, c2, c1), g2 = blend(onSurface, splat(0.0), c2);
  const VD f0 = blend(onSurface, e1, e0), f1 = blend(onSurface, e2, e1), f2 = blend(onSurface, splat(0.0), e2);
  b.again = laneBits(onSurface & le(vabs(g0), 4.0 * f0));
  const VD slo = lo - tShift, shi = hi - tShift;
  const VI sSpan = lt(slo, shi);
  b.sSpan = laneBits(sSpan);

  // ---- quadricRoot from slo: the checks shared by quadraticFirst and linearFirst -------------
  const VD scale = vmax(vabs(slo), vabs(shi));
  const VI safeSpan = finite(slo) & finite(shi) & sSpan & le(scale, splat(1e30)) & inRange(g0) & inRange(g1) &
                      inRange(f0) & inRange(f1) & finite(f0) & finite(f1);
  VD s = splat(0.0);
  if (anyOff) {
    // quadraticFirst (c2 != 0): the sweep lo, vertex (if inside), hi with no sample within
    // noise, the root of the first sign change by citardauq.
    const VI quadSafe = safeSpan & ne(c2, splat(0.0)) & inRange(c2) & inRange(e2) & finite(e2) &
                        lt(4.0 * kUnitRoundoff * vmax(vabs(c0), vabs(c1) * scale), (vabs(c2) * scale) * scale) &
                        lt(2.0 * e2, vabs(c2));
    const VD n0 = e0 + gamma(5) * vabs(c0), n1 = e1 + gamma(5) * vabs(c1), n2 = e2 + gamma(5) * vabs(c2);
    auto value2 = [&](VD x) { return (c2 * x + c1) * x + c0; };
    auto noise2 = [&](VD x) {
      const VD ax = vabs(x);
      return (n2 * ax + n1) * ax + n0;
    };
    const VD vertex = -c1 / (2.0 * c2);
    const VI interior = lt(slo, vertex) & lt(vertex, shi);
    const VD fLo = value2(slo), fV = value2(vertex), fHi = value2(shi);
    const VI zLo = le(vabs(fLo), noise2(slo)), zV = le(vabs(fV), noise2(vertex)), zHi = le(vabs(fHi), noise2(shi));
    // Signs as f < 0: no sample decided here is zero (|f| > noise >= 0) or NaN (the
    // checks). Masks are -1 or 0: ^ is "differ" (SSE2 has no 64-bit compare).
    const VD zero = splat(0.0);
    const VI change1 = interior & (lt(fV, zero) ^ lt(fLo, zero));
    const VI needHi = ~change1;
    const VI changeHi = lt(fHi, zero) ^ lt(blend(interior, fV, fLo), zero);
    const VI quadNoisy = zLo | (interior & zV) | (needHi & zHi);
    const VI quadRoot = change1 | (needHi & changeHi);
    b.quadSafe = laneBits(quadSafe & ~quadNoisy);
    b.quadRoot = laneBits(quadRoot);
    if ((b.quadSafe & b.quadRoot & ~b.on) != 0) {
      const VD xa = blend(change1, slo, blend(interior, vertex, slo)), xb = blend(change1, vertex, shi);
      // quadraticRoots with Kahan's discriminant (roots_detail.h).
      const VD pp = c1 * c1, dp = productError(c1, c1, pp);
      const VD c4 = 4 * c2, q4 = c4 * c0, dq = productError(c4, c0, q4);
      const VD disc = (pp - q4) + (dp - dq);
      const VD qq = -(c1 + copySign(vsqrt(disc), c1)) / 2;
      const VD ra = qq / c2, rb = c0 / qq;
      const VI swap = lt(rb, ra);
      const VD rLo = blend(swap, rb, ra), rHi = blend(swap, ra, rb);
      const VI inLo = lt(xa, rLo) & lt(rLo, xb), inHi = lt(xa, rHi) & lt(rHi, xb);
      b.quadFound = laneBits(lt(zero, disc) & ne(qq, zero) & (inLo | inHi));
      s = blend(inLo, rLo, rHi);
    }
  }
  if (anyOn) {
    // linearFirst (leaving the surface, degree 1 after the division).
    const VD zero = splat(0.0);
    b.linSafe = laneBits(safeSpan & ne(g1, zero) & lt(f1, vabs(g1)) &
                         lt(2.0 * kUnitRoundoff * vabs(g0), vabs(g1) * scale));
    const VD m0 = f0 + gamma(3) * vabs(g0), m1 = f1 + gamma(3) * vabs(g1);
    const VD gLo = g1 * slo + g0, gHi = g1 * shi + g0;
    // Within noise of lo: no root; of hi: the root hi, which quadricLane does not report.
    b.linNone = laneBits(le(vabs(gLo), m1 * vabs(slo) + m0) | le(vabs(gHi), m1 * vabs(shi) + m0) |
                         ~(lt(gLo, zero) ^ lt(gHi, zero)));
    const VD linS = -g0 / g1;
    b.linFound = laneBits(lt(slo, linS) & lt(linS, shi));
    s = blend(onSurface, linS, s);
  }
  writeStatus(b, p, i);
  store(p.s + i, s);
  store(p.kox + i, o.x);
  store(p.koy + i, o.y);
  store(p.koz + i, o.z);
  store(p.kdx + i, d.x);
  store(p.kdy + i, d.y);
  store(p.kdz + i, d.z);
  store(p.orgError + i, orgError);
  store(p.tShift + i, tShift);
  store(p.c0 + i, g0);
  store(p.c1 + i, g1);
  store(p.c2 + i, g2);
  store(p.e0 + i, f0);
  store(p.e1 + i, f1);
  store(p.e2 + i, f2);
  store(p.slo + i, slo);
  store(p.shi + i, shi);
}

}  // namespace
#endif  // __SSE2__

bool usesQuadricPacket(const SurfaceData& data) {
#if !defined(__SSE2__)
  return false;  // the lane loop (no SIMD path written for other targets)
#endif
  const auto* sphere = std::get_if<ClipSphere>(&data.desc.clip);
  // The re-centring point is the clip sphere's closest point (quadricSpan passes tc only
  // when the sphere is centred on data.centre); a cell the build shrank below the tight
  // box has no QuadricBox and every ray would be clipped to it (left to the scalar path).
  return usesQuadricPath(data) && data.desc.options.packetSimd && data.desc.options.recentre && sphere &&
         sphere->center == data.centre && (!data.quadricCellClip || data.quadricBox.distance >= 0.0);
}

void quadricPacket(const SurfaceData& data, QuadricPacket& p) noexcept {
#if !defined(__SSE2__)
  for (unsigned i = 0; i < p.count; ++i) p.status[i] = QuadricPacket::kScalar;
  return;
#else
  const ClipSphere& sphere = std::get<ClipSphere>(data.desc.clip);
  // objectRay's Frobenius norm of A^-1 and |b|, the same operations once per packet.
  const double invNorm = std::sqrt(glm::dot(data.aInv[0], data.aInv[0]) + glm::dot(data.aInv[1], data.aInv[1]) +
                                   glm::dot(data.aInv[2], data.aInv[2]));
  const double lenB = glm::length(data.b);
  // Pad to whole vectors with copies of the first lane (computed, never read).
  const unsigned end = (p.count + kW - 1) / kW * kW;
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
  for (unsigned i = 0; i < end; i += kW) quadricGroup(data, sphere, invNorm, lenB, p, i);
#endif
}

}  // namespace algray
