// The only file that knows Embree 3's callback ABI: bounds, intersect and occluded for
// N = 1, 4, 8, 16 (one lane at a time, honouring the valid mask; the quadric path's
// packets through quadric_packet.cpp), the host filter calls, the callbacks' side of the
// double-precision channel (IntersectContext; its host side, the context set-up and the
// float proxy ray, is double_channel.cpp) and the exception barrier.
// An Embree 4 port rewrites this file; the kernel (surface_intersect.cpp, ray_roots.cpp,
// self_root.cpp, ray_settle.cpp, quadric_path.cpp) stays.
#include "double_channel.h"
#include "quadric_path.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

namespace algray {

// ---- Double channel ----------------------------------------------------------------
// The marker: initIntersectContext (double_channel.cpp) installs this as the context
// filter. For Embree's own geometries Embree calls it only when the host's scene has
// RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION; it then forwards to the host's context filter.
// For algray geometries the bridge never lets rtcFilterIntersection see it (Embree 3
// asserts the scene flag there): see runFilters().
void markerFilter(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const IntersectContext*>(args->context);
  if (context->hostFilter) context->hostFilter(args);
}

namespace {

constexpr float kFloatRoundoff = 0x1p-24f;
constexpr unsigned kMaxN = 16;
constexpr unsigned kHitFields =
    7 + RTC_MAX_INSTANCE_LEVEL_COUNT;  // Ng(3) u v primID geomID instID[]
static_assert(kHitFields * sizeof(float) == offsetof(RTCHit, instID) + sizeof(RTCHit::instID));

// The algray context of a single ray outside any instance, or nullptr. Inside an instance
// Embree has transformed the float ray; the world-space double ray no longer applies.
IntersectContext* doubleContext(RTCIntersectContext* context, unsigned n) {
  if (n != 1 || context->filter != &markerFilter) return nullptr;
  if (context->instID[0] != RTC_INVALID_GEOMETRY_ID) return nullptr;
  auto* ic = reinterpret_cast<IntersectContext*>(context);
  return ic->ray && ic->hit ? ic : nullptr;
}

// The algray context of a single ray inside an instance, or nullptr: the float ray is
// solved there, but the host still reads the HitD, which must not keep a farther hit
// outside the instance (a host checking geomID and instID against it would take that
// one for the scene's closest hit).
IntersectContext* instanceDoubleContext(RTCIntersectContext* context, unsigned n) {
  if (n != 1 || context->filter != &markerFilter) return nullptr;
  if (context->instID[0] == RTC_INVALID_GEOMETRY_ID) return nullptr;
  auto* ic = reinterpret_cast<IntersectContext*>(context);
  return ic->ray && ic->hit ? ic : nullptr;
}

// ---- Rays into object space ------------------------------------------------------------
// deferFloatTerm: leave a float ray's floatOriginError to the kernels
// (KernelRay::orgErrorDeferred).
KernelRay objectRay(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d, double tnear,
                    double tfar, double roundoff, double orgError, bool deferFloatTerm = false) {
  KernelRay r;
  r.tnear = tnear;
  r.tfar = tfar;
  r.orgRoundoff = roundoff;
  r.org = o;
  r.dir = d;
  r.orgError = orgError;
  r.hostBound = roundoff == kUnitRoundoff && orgError > 0.0;
  if (!data.identity) {
    // t is invariant under the affine map. The origin's uncertainty maps through A^-1
    // (Frobenius norm bounds the spectral one), plus the rounding of the map itself. Its
    // world-space part stays known too (KernelRay::orgErrorWorld), for the self-root rule.
    const double inv =
        std::sqrt(glm::dot(data.aInv[0], data.aInv[0]) + glm::dot(data.aInv[1], data.aInv[1]) +
                  glm::dot(data.aInv[2], data.aInv[2]));
    const glm::dvec3 ob = o - data.b;
    r.org = data.aInv * ob;
    r.dir = data.aInv * d;
    if (roundoff > kUnitRoundoff) {
      // A float ray: the bound the quadric packets (quadric_packet_group.inc) and the
      // tight quadric box (boundedQuadricBox) repeat.
      r.orgErrorWorld = orgError + 4.0 * roundoff * (glm::length(o) + glm::length(data.b));
      r.orgError = inv * r.orgErrorWorld;
    } else {
      // A double ray: the world origin stands for a point within orgError plus its own
      // rounding, u |o| (twice, for margin); the map adds the rounding of o - b (u |o - b|)
      // and of the product by A^-1 (gamma(3) |A^-1| |o - b|), gamma(5) |o - b| through the
      // Frobenius norm. Not u (|o| + |b|) for the subtraction: an object of size 1e-8 placed
      // 6e5 from the world origin has o ~ b, and that bound (with the rule's factors) put
      // origins 0.15 radii off the surface on it, so the rule divided a root out of rays
      // that had none at their origin (a clear hit missed, a hit reported where |f| was
      // 0.16 of its scale: EmbreeHits.SelfRootRuleOfFarTranslatedObjects).
      r.orgErrorWorld = orgError + 2.0 * roundoff * glm::length(o);
      r.orgError = inv * (r.orgErrorWorld + gamma(5) * glm::length(ob));
      r.orgErrorObject = inv * gamma(5) * glm::length(ob);
    }
  }
  // A float ray carries no error bound, and a float host computes a leaving ray's origin
  // as o + t d in float from a ray that started anywhere in the scene: its error is
  // gamma_3 (|o| + |t d|) in float units (pbrt-v4 Sec. 6.8.6) with |o| unknown here. The
  // adapter assumes that ray started within a few object sizes: 16 u_float (|o| + R), R
  // the clip radius. Hosts needing better pass double rays with RayD::orgError.
  if (roundoff > kUnitRoundoff) {
    if (deferFloatTerm) {
      r.orgErrorDeferred = true;
    } else {
      const double term = floatOriginError(data, r.org, roundoff);
      r.orgError += term;
      r.orgErrorObject += term;
    }
  }
  return r;
}

glm::dvec3 lanePoint(float x, float y, float z) { return {x, y, z}; }

// ---- Far origins of double rays ----------------------------------------------------------
// The kernels work in t, which resolves a position along the ray only to u |t d|: from
// ~1e15 clip radii away the clip region's span rounds away and the ray missed (a torus
// seen from 1e30), and the point o + t d of the restriction's centre and of each polish
// step rounds by u |o|, which along a ray grazing the surface (f's slope along it small)
// moves the root by that over the slope (a unit sphere grazed from 1e6 radii, its chord
// 1.9e-4: 2.6e-7 off, 2,300 ulps of t; from 1e4 radii 1.15e-9 radii; the audit of session
// 51, when kFarOrigin was 2^40). A double ray from beyond kFarOrigin world radii is re-based
// first: its origin moves along the line to o' = o + T d, four radii before the point
// closest to the clip centre, the kernels trace o' + s d, and a hit reports t = T + s.
// Each move computes o + t d with error-free transformations (pointOnLine,
// double_channel.h), so o' stays on the line to u |o'| + u^2 |t d|; the rounding of t only
// moves o' along the line, by up to u |t d|, and the next move takes that up (a few moves
// from any finite origin). What remains is the interface's own limit: the reported
// t = T + s is rounded to u |t|.
// From 2^8 radii on, where that rounding reaches 2^-44 of the radius, and the moves (one or
// two pointOnLine) cost little against a ray's solve.
constexpr double kFarOrigin = 0x1p8;

// Moves o to o' as above and returns T as an unevaluated sum tBase + tBaseLow (Knuth's
// TwoSum of the moves: T keeps the digits the kernels' t adds to); both 0, o unchanged,
// when o is not that far, its error bound is not small against its distance, or the
// moves do not end outside the clip ball (overflow). orgError becomes the rounding bound
// of o': the self-root rule, the only user of the host's bound, cannot apply to an origin
// this far outside.
double rebaseFarOrigin(const SurfaceData& data, glm::dvec3& o, const glm::dvec3& d,
                       double& orgError, double& tBaseLow) {
  tBaseLow = 0.0;
  const double r = data.worldRadius, far = kFarOrigin * r;
  const glm::dvec3 oc = o - data.worldCentre;
  const double dist2 = glm::dot(oc, oc), dd = glm::dot(d, d);
  if (!(dist2 > far * far) || !(orgError <= 0x1p-20 * std::sqrt(dist2)) || !(dd > 0.0) ||
      !std::isfinite(dd))
    return 0.0;
  const double len = std::sqrt(dd);
  glm::dvec3 p = o;
  double hi = 0.0, low = 0.0;
  for (int move = 0; move < kMaxMoves; ++move) {
    // To four radii before the point of the line closest to the centre; done when within
    // two radii of it (so two to six radii before that point, outside the ball).
    // dot(p - c, d) on p - c scaled by a power of two (exact): unscaled it overflows for
    // origins from ~1e308 / |d| (a diagonal ray from (-1e308, -1e308, -1e308) missed).
    // By ldexp of each component, not a product with 2^-e: that factor is subnormal from
    // e = 1023 and Embree's threads flush subnormals to zero.
    const glm::dvec3 pc = p - data.worldCentre;
    const double m = std::max({std::abs(pc.x), std::abs(pc.y), std::abs(pc.z)});
    const int e = m > 0.0 ? std::ilogb(m) : 0;
    const glm::dvec3 pcScaled(std::ldexp(pc.x, -e), std::ldexp(pc.y, -e), std::ldexp(pc.z, -e));
    const double t = -std::ldexp(glm::dot(pcScaled, d) / dd, e) - 4.0 * r / len;
    if (!std::isfinite(t)) return 0.0;
    if (std::abs(t) * len <= 2.0 * r) break;
    const glm::dvec3 next = pointOnLine(p, d, t);
    if (next == p) break;
    p = next;
    addExact(hi, low, t);
  }
  const glm::dvec3 pc = p - data.worldCentre;
  if (!finite(p) || !std::isfinite(hi + low) || !(glm::dot(pc, pc) > 2.0 * r * r)) return 0.0;
  o = p;
  orgError = 4.0 * kUnitRoundoff * (std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
  tBaseLow = low;
  return hi;
}

// ---- Candidate hits ----------------------------------------------------------------------
struct HitBuffer {
  float storage[kHitFields * kMaxN];
  RTCHitN* hitN() { return reinterpret_cast<RTCHitN*>(storage); }
};

void writeCandidate(RTCHitN* hit, unsigned n, unsigned lane, const glm::vec3& ng, float u, float v,
                    unsigned primID, unsigned geomID, const RTCIntersectContext* context) {
  RTCHitN_Ng_x(hit, n, lane) = ng.x;
  RTCHitN_Ng_y(hit, n, lane) = ng.y;
  RTCHitN_Ng_z(hit, n, lane) = ng.z;
  RTCHitN_u(hit, n, lane) = u;
  RTCHitN_v(hit, n, lane) = v;
  RTCHitN_primID(hit, n, lane) = primID;
  RTCHitN_geomID(hit, n, lane) = geomID;
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
    RTCHitN_instID(hit, n, lane, l) = context->instID[l];
}

void copyLane(RTCHitN* to, const RTCHitN* from, unsigned n, unsigned lane) {
  // A single ray's hit is one RTCHit: one block copy (the field loop was 35 instructions
  // of a primary hit's ~760; callgrind, AMD Zen 3).
  if (n == 1) {
    std::memcpy(to, from, kHitFields * sizeof(float));
    return;
  }
  auto* t = reinterpret_cast<float*>(to);
  const auto* f = reinterpret_cast<const float*>(from);
  for (unsigned field = 0; field < kHitFields; ++field) t[field * n + lane] = f[field * n + lane];
}

struct Lane {
  const void* args;  // RTCIntersectFunctionNArguments or RTCOccludedFunctionNArguments
  const SurfaceData* data;
  unsigned lane;
  IntersectContext* dctx;
  double tfarD;  // the double channel's current far end
  // The double channel's kernel ray (laneRay): host t = 2^-tExp (tBase + tBaseLow +
  // kernel t), for far origins (rebaseFarOrigin) and directions far from unit length.
  double tBase = 0.0, tBaseLow = 0.0;
  int tExp = 0;
  double tnearScaled = 0.0;  // 2^tExp host tnear (the kernel's tnear before the re-basing)
};
// A lane of a packet through quadric_packet.cpp: surfaceUVFloat's u, v (before the cast)
// of the hit at t = uvT and its float normal at t = nT, computed with the packet's lanes
// (NaN: none). A type of its own so that single rays carry and test nothing more
// (measured: the test and the larger record in the lane loop cost the sphere's single
// primary rays 1.5 %).
struct PacketLane : Lane {
  double uvT = std::numeric_limits<double>::quiet_NaN(), uvU = 0, uvV = 0;
  double nT = std::numeric_limits<double>::quiet_NaN();
  glm::vec3 normal{0.0f};
};

// A double-channel kernel t as the host's t (see Lane::tExp). A ray with |d| near 1e308
// has its hits near t = 1e-308, below double's normal range, where Embree's and TBB's
// threads flush arithmetic results to zero (FTZ), glibc's ldexp included: there t is
// scaled in long double (x87, which MXCSR's flags do not touch) and rounded once.
double hostParameter(const Lane& L, double t) {
  const double shifted = L.tBase + (L.tBaseLow + t);
  if (L.tExp == 0) return shifted;
  const double host = std::ldexp(shifted, -L.tExp);
  if (std::abs(host) >= std::numeric_limits<double>::min() || shifted == 0.0) return host;
  return static_cast<double>(std::ldexp(static_cast<long double>(shifted), -L.tExp));
}

// Whether a double-channel kernel t lies past the host's tnear: the kernels keep kernel t
// in (tnear, tfar), but a re-based ray's t = T + s rounds to the host's resolution, and a
// host stepping past a hit 1e9 radii along its ray (tnear = its t) met each root twice, s
// just past the kernel's tnear and T + s on the host's (session 51, with re-basing from 2^8
// radii). Compared before the scaling by 2^-tExp, exact but for subnormal t, which Embree's
// threads read as 0.
bool pastHostTnear(const Lane& L, double t) {
  return L.tBase == 0.0 || L.tBase + (L.tBaseLow + t) > L.tnearScaled;
}

// The candidate's float tfar, and whether it lies inside the ray's current interval: in
// the double channel against the double far end (the float ray is only Embree's
// traversal proxy) and the host's tnear (pastHostTnear), otherwise against the float ray's
// own (tnear, tfar).
bool candidateTfar(const Lane& L, RTCRayN* ray, unsigned n, unsigned lane, double kernelT, double t,
                   float& tf) {
  if (L.dctx) {
    tf = roundUp(((t - L.dctx->floatShift) - L.dctx->floatShiftLow) / L.dctx->floatScale);
    return t < L.tfarD && pastHostTnear(L, kernelT);
  }
  tf = static_cast<float>(t);
  return tf > RTCRayN_tnear(ray, n, lane) && tf < RTCRayN_tfar(ray, n, lane);
}

// The host's filters for one candidate: the geometry filter through Embree, then the
// context filter. With an algray context, the marker is hidden from Embree during the
// call (Embree 3.13 runs, and asserts on, any non-null context filter from
// rtcFilterIntersection whatever the scene flags) and the host's chained context filter,
// if any, is called here instead.
// Hides the marker for the host's geometry filter and puts it back when the filter
// returns or throws: the callbacks count a throw as a miss, and the host's context must
// stay algray's for the rest of the trace and for its next ones (without the marker the
// double channel was silently off, its HitD no longer written).
struct MarkerHidden {
  RTCIntersectContext* context;
  explicit MarkerHidden(RTCIntersectContext* c) : context(c) { context->filter = nullptr; }
  ~MarkerHidden() { context->filter = &markerFilter; }
  MarkerHidden(const MarkerHidden&) = delete;
  MarkerHidden& operator=(const MarkerHidden&) = delete;
};

template <class Args, class Filter>
void runFilters(const Args* args, RTCFilterFunctionNArguments* fargs, IntersectContext* marked,
                Filter filter) {
  RTCIntersectContext* context = args->context;
  if (context->filter != &markerFilter) {
    filter(args, fargs);
    return;
  }
  {
    const MarkerHidden hidden(context);
    filter(args, fargs);
  }
  if (!marked || !marked->hostFilter) return;
  for (unsigned i = 0; i < fargs->N; ++i)
    if (fargs->valid[i] != 0) {
      marked->hostFilter(fargs);
      return;
    }
}

// Any algray context (also inside instances, where its double ray is not used).
IntersectContext* markedContext(RTCIntersectContext* context) {
  return context->filter == &markerFilter ? reinterpret_cast<IntersectContext*>(context) : nullptr;
}

// Embree's Ng is float: a gradient beyond float's range (coefficients like 1e200, or
// 1e-200) would become inf or 0 and lose its direction, so it is scaled by a power of
// two (exact, direction kept) to a largest component in [0.5, 1) in that case. The
// common case inline, the scaling out of line (as one out-of-line function the call was
// 3 % of a sphere's primary ray; inline, those rays 1-2 % faster, measured).
[[gnu::noinline]] glm::vec3 scaledFloatNormal(const glm::dvec3& g, double m) {
  if (!(m > 0.0) || !std::isfinite(m)) return glm::vec3(g);
  int e = 0;
  std::frexp(m, &e);
  return glm::vec3(std::ldexp(g.x, -e), std::ldexp(g.y, -e), std::ldexp(g.z, -e));
}
inline glm::vec3 floatNormal(const glm::dvec3& g) {
  const double m = std::max({std::abs(g.x), std::abs(g.y), std::abs(g.z)});
  if (m >= 1e-30 && m <= 1e30) [[likely]]
    return glm::vec3(g);
  return scaledFloatNormal(g, m);
}

// A candidate's u, v: in double for the double channel (the HitD's) and as the float hit
// buffer takes them, else to float accuracy (surfaceUVFloat); none (0, 0, as Embree's own
// sphere) when the host switched them off (SurfaceOptions::uv).
inline void candidateUV(const Lane& L, const glm::dvec3& point, double& u, double& v, float& uf,
                        float& vf) {
  u = v = 0.0;
  uf = vf = 0.0f;
  if (!L.data->desc.options.uv) return;
  if (L.dctx) {
    surfaceUV(*L.data, point, u, v);
    uf = floatU(u);
    vf = static_cast<float>(v);
  } else {
    surfaceUVFloat(*L.data, point, uf, vf);
  }
}

template <bool kPacketLane>
bool acceptIntersectionOf(void* user, const KernelHit& h) {
  Lane& L = *static_cast<Lane*>(user);
  const auto* args = static_cast<const RTCIntersectFunctionNArguments*>(L.args);
  const unsigned n = args->N, lane = L.lane;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  const double t = L.dctx ? hostParameter(L, h.t) : h.t;  // (nothing added on a float ray's path)
  float tf;
  if (!candidateTfar(L, ray, n, lane, h.t, t, tf)) return false;
  // ---- The candidate, as Embree would write it ---------------------------------------
  glm::dvec3 ng(0.0);
  glm::vec3 ngFloat;
  bool givenNormal = false;
  if constexpr (kPacketLane) {
    const auto& P = static_cast<const PacketLane&>(L);
    if (h.t == P.nT) {
      ngFloat = P.normal;
      givenNormal = true;
    }
  }
  if (!givenNormal) {
    ng = L.data->identity ? h.gradient : L.data->aInvT * h.gradient;
    ngFloat = floatNormal(ng);
  }
  // A gradient that is exactly zero (a hit on a singular point, or on a double surface
  // such as (x^2 + y^2 - 1)^2 = 0, where grad f = 2 g grad g vanishes everywhere) has no
  // direction; a host normalising it gets NaN. Ng is then the ray's reversed direction
  // (facing the ray: the surface has no normal of its own there).
  if (!(ngFloat.x != 0.0f || ngFloat.y != 0.0f || ngFloat.z != 0.0f)) {
    if (L.dctx)
      ng = -L.dctx->ray->dir;
    else
      ng = -lanePoint(RTCRayN_dir_x(ray, n, lane), RTCRayN_dir_y(ray, n, lane),
                      RTCRayN_dir_z(ray, n, lane));
    ngFloat = floatNormal(ng);
  }
  // (A packet lane may come with the u, v of its first root; a packet has no double channel.)
  double u = 0, v = 0;
  float uf = 0, vf = 0;
  bool givenUV = false;
  if constexpr (kPacketLane) {
    const auto& P = static_cast<const PacketLane&>(L);
    if (L.data->desc.options.uv && !L.dctx && h.t == P.uvT) {
      uf = floatU(P.uvU);
      vf = static_cast<float>(P.uvV);
      givenUV = true;
    }
  }
  if (!givenUV) candidateUV(L, h.point, u, v, uf, vf);
  HitBuffer candidate;
  writeCandidate(candidate.hitN(), n, lane, ngFloat, uf, vf, args->primID, args->geomID,
                 args->context);
  // ---- Host filter (geometry filter, then context filter): the filter sees the
  // candidate t as the ray's tfar and may reject it by clearing valid[lane] -------------
  int valid[kMaxN] = {};
  valid[lane] = -1;
  const float oldTfar = RTCRayN_tfar(ray, n, lane);
  RTCRayN_tfar(ray, n, lane) = tf;
  RTCFilterFunctionNArguments fargs{valid,
                                    args->geometryUserPtr,
                                    args->context,
                                    reinterpret_cast<RTCRayN*>(args->rayhit),
                                    candidate.hitN(),
                                    n};
  try {
    runFilters(args, &fargs, markedContext(args->context),
               [](const RTCIntersectFunctionNArguments* a, const RTCFilterFunctionNArguments* f) {
                 rtcFilterIntersection(a, f);
               });
  } catch (...) {
    // A throwing host filter counts as a miss (the callbacks catch it): the ray keeps its
    // far end (else it ended at a hit that was never written, and hid the ones behind).
    RTCRayN_tfar(ray, n, lane) = oldTfar;
    throw;
  }
  if (valid[lane] == 0) {
    RTCRayN_tfar(ray, n, lane) = oldTfar;
    return false;
  }
  copyLane(RTCRayHitN_HitN(args->rayhit, n), candidate.hitN(), n, lane);
  if (L.dctx) {
    HitD& hit = *L.dctx->hit;
    hit.hit = true;
    hit.t = t;
    hit.Ng = ng;
    hit.u = u;
    hit.v = v;
    hit.geomID = args->geomID;
    hit.primID = args->primID;
    hit.instID = RTC_INVALID_GEOMETRY_ID;
    L.tfarD = t;
  } else if (IntersectContext* ic = instanceDoubleContext(args->context, n)) {
    // (A single ray: no packet lane, so ng was computed above.)
    HitD& hit = *ic->hit;
    hit.hit = true;
    hit.t = fromFloatParameter(*ic, t);
    hit.Ng = ng;
    hit.u = hit.v = 0.0;
    if (L.data->desc.options.uv) surfaceUV(*L.data, h.point, hit.u, hit.v);
    hit.geomID = args->geomID;
    hit.primID = args->primID;
    hit.instID = args->context->instID[0];
  }
  return true;
}

bool acceptIntersection(void* user, const KernelHit& h) {
  return acceptIntersectionOf<false>(user, h);
}

bool acceptOcclusion(void* user, const KernelHit& h) {
  Lane& L = *static_cast<Lane*>(user);
  const auto* args = static_cast<const RTCOccludedFunctionNArguments*>(L.args);
  const unsigned n = args->N, lane = L.lane;
  RTCRayN* ray = args->ray;
  const double t = L.dctx ? hostParameter(L, h.t) : h.t;  // (nothing added on a float ray's path)
  float tf;
  if (!candidateTfar(L, ray, n, lane, h.t, t, tf)) return false;
  // Occlusion computes no normal: Ng is zero for the filter. u, v are the intersection's
  // (an alpha-textured shadow reads them in its occlusion filter, as Embree's triangles
  // give them).
  double u, v;
  float uf, vf;
  candidateUV(L, h.point, u, v, uf, vf);
  HitBuffer candidate;
  writeCandidate(candidate.hitN(), n, lane, glm::vec3(0.0f), uf, vf, args->primID, args->geomID,
                 args->context);
  int valid[kMaxN] = {};
  valid[lane] = -1;
  const float oldTfar = RTCRayN_tfar(ray, n, lane);
  RTCRayN_tfar(ray, n, lane) = tf;
  RTCFilterFunctionNArguments fargs{valid, args->geometryUserPtr, args->context,
                                    ray,   candidate.hitN(),      n};
  try {
    runFilters(args, &fargs, markedContext(args->context),
               [](const RTCOccludedFunctionNArguments* a, const RTCFilterFunctionNArguments* f) {
                 rtcFilterOcclusion(a, f);
               });
  } catch (...) {
    RTCRayN_tfar(ray, n, lane) = oldTfar;  // a miss, as above
    throw;
  }
  if (valid[lane] == 0) {
    RTCRayN_tfar(ray, n, lane) = oldTfar;
    return false;
  }
  RTCRayN_tfar(ray, n, lane) = -std::numeric_limits<float>::infinity();
  IntersectContext* ic = L.dctx ? L.dctx : instanceDoubleContext(args->context, n);
  if (ic) {
    HitD& hit = *ic->hit;
    hit.hit = true;
    hit.t = L.dctx ? t : fromFloatParameter(*ic, t);
    hit.geomID = args->geomID;
    hit.primID = args->primID;
    hit.instID = args->context->instID[0];
  }
  return true;
}

// The double channel's ray of a lane in object space (laneRay). Out of line: inlined, its
// scaling and re-basing grew laneRay enough that the quadric path's float rays stopped
// being inlined whole (measured: the sphere's single primary and shadow rays 16 % slower).
template <class Args>
[[gnu::noinline]] KernelRay doubleLaneRay(const Args* args, RTCRayN* ray, unsigned lane, Lane& L) {
  const SurfaceData& data = *L.data;
  const unsigned n = args->N;
  const RayD& r = *L.dctx->ray;
  L.tfarD = std::min(r.tfar, fromFloatParameter(*L.dctx, RTCRayN_tfar(ray, n, lane)));
  if (L.dctx->hit->hit) L.tfarD = std::min(L.tfarD, L.dctx->hit->t);
  // A direction far from unit length is scaled by a power of two first, and t with it
  // (exact): dot(d, d) overflows from |d| ~ 1e154 and underflows below ~1e-160, and the
  // kernels' clip and restriction multiply several such products (every ray of
  // lengths 1e-200 or 1e200 missed). Kernel t = 2^tExp host t.
  glm::dvec3 dir = r.dir;
  double tnear = r.tnear, tfar = L.tfarD;
  const double md = std::max({std::abs(dir.x), std::abs(dir.y), std::abs(dir.z)});
  L.tExp = 0;
  if (md > 0.0 && std::isfinite(md) && (md > 0x1p100 || md < 0x1p-100)) {
    L.tExp = std::ilogb(md);
    dir = glm::dvec3(std::ldexp(dir.x, -L.tExp), std::ldexp(dir.y, -L.tExp),
                     std::ldexp(dir.z, -L.tExp));
    tnear = std::ldexp(tnear, L.tExp);
    tfar = std::ldexp(tfar, L.tExp);
  }
  glm::dvec3 org = r.org;
  double orgError = r.orgError;
  L.tnearScaled = tnear;
  L.tBase = rebaseFarOrigin(data, org, dir, orgError, L.tBaseLow);
  KernelRay kr = objectRay(data, org, dir, (tnear - L.tBase) - L.tBaseLow,
                           (tfar - L.tBase) - L.tBaseLow, kUnitRoundoff, orgError);
  kr.hasTraversalRay = true;
  kr.trace = L.dctx->trace;
  kr.travOrg = lanePoint(RTCRayN_org_x(ray, n, lane), RTCRayN_org_y(ray, n, lane),
                         RTCRayN_org_z(ray, n, lane));
  kr.travDir = lanePoint(RTCRayN_dir_x(ray, n, lane), RTCRayN_dir_y(ray, n, lane),
                         RTCRayN_dir_z(ray, n, lane));
  return kr;
}

// One lane's ray in object space: the double ray of an algray context, else the float ray
// (deferFloatTerm: for the generic walk and the quadric path, see objectRay).
template <class Args>
KernelRay laneRay(const Args* args, RTCRayN* ray, unsigned lane, Lane& L,
                  bool deferFloatTerm = false) {
  if (L.dctx) return doubleLaneRay(args, ray, lane, L);
  const unsigned n = args->N;
  const glm::dvec3 o = lanePoint(RTCRayN_org_x(ray, n, lane), RTCRayN_org_y(ray, n, lane),
                                 RTCRayN_org_z(ray, n, lane));
  const glm::dvec3 d = lanePoint(RTCRayN_dir_x(ray, n, lane), RTCRayN_dir_y(ray, n, lane),
                                 RTCRayN_dir_z(ray, n, lane));
  return objectRay(*L.data, o, d, RTCRayN_tnear(ray, n, lane), RTCRayN_tfar(ray, n, lane),
                   kFloatRoundoff, 0.0, deferFloatTerm);
}

template <class Args>
bool traceLane(const Args* args, RTCRayN* ray, unsigned lane, bool occlusion, AcceptFn accept) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  Lane L{args, data, lane, doubleContext(args->context, args->N), 0.0};
  const KernelRay kr = laneRay(args, ray, lane, L, true);
  return walkRoots(*data, args->primID, kr, occlusion, accept, &L);
}

// The quadric path (quadric_path.cpp): the roots of the closed-form restriction in
// order, offered to the same accept functions as the generic walk's (host filters, the
// double channel, the float tfar), so a rejected root moves on to the next one.
// s: the first root, quadricRoot(q, q.slo, s). (Inlined: a call here cost the lane
// loop's single primary rays ~1 %, measured.)
template <bool kOcclusion, class LaneT>
[[gnu::always_inline]] inline void offerQuadricRoots(LaneT& L, const KernelRay& kr,
                                                     const QuadricSpan& q, double s) {
  // The span is open at its far end, as the generic walk's cell span: a root within
  // noise of it (reported there by the solver) is no hit.
  while (s < q.shi) {
    KernelHit h;
    h.t = q.g.tShift + s;
    if (!(h.t < kr.tfar)) return;
    if (h.t > kr.tnear) {  // else the shift rounded a root in the span onto tnear
      h.point = kr.org + h.t * kr.dir;
      if constexpr (kOcclusion) {
        if (acceptOcclusion(&L, h)) return;
      } else {
        // (A packet lane may come with the normal of its first root.)
        bool givenNormal = false;
        if constexpr (std::is_same_v<LaneT, PacketLane>) givenNormal = h.t == L.nT;
        if (!givenNormal)
          h.gradient = hitGradient(*L.data, kr.dir, h.point, L.data->quadric->gradient(h.point),
                                   hitPointError(kr.org, kr.dir, h.t));
        if (acceptIntersectionOf<std::is_same_v<LaneT, PacketLane>>(&L, h)) return;
      }
    }
    const double slo = s;
    if (!quadricRoot(q, slo, s)) return;
  }
}

// The origin window of the generic walk (deriveRayRoots) for the quadric path: a double ray
// with the host's orgError whose origin the rule did not take; a first root s with |t|
// within twice it is the origin's, and s becomes the next root past it (false: none). (x^2
// - 1e-2 y^2, rays leaving hits 1e-14..1e-8 from its double line: 9 of 1440 hit within it;
// the review of session 47.) Out of line: inlined, quadricLane grew and every single ray of
// the quadric path took 7-11 % longer (the third review).
[[gnu::noinline, gnu::cold]] bool pastOriginWindow(const SurfaceData& data, const KernelRay& kr,
                                                   const QuadricSpan& q, double& s) {
  const double window = selfRootWindow(data, kr, kr.orgError);
  return std::abs(q.g.tShift + s) > window ||
         quadricRoot(q, std::max(q.slo, window - q.g.tShift), s);
}

template <bool kOcclusion, class Args>
void quadricLane(const Args* args, RTCRayN* ray, unsigned lane) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  Lane L{args, data, lane, doubleContext(args->context, args->N), 0.0};
  const KernelRay kr = laneRay(args, ray, lane, L, true);
  QuadricSpan q;
  double s;
  if (!quadricSpan(*data, kr, q) || !quadricRoot(q, q.slo, s)) return;
  // A first root within the self-root window is the origin's own (selfRootWindow): the
  // roots from the window on.
  if (q.g.selfRoot) {
    const double orgError = wholeOrgError(*data, kr);
    if (withinSelfRootWindow(*data, kr, s, orgError) &&
        !quadricRoot(q, std::max(q.slo, selfRootWindow(*data, kr, orgError)), s))
      return;
  } else if (kr.hostBound && !pastOriginWindow(*data, kr, q, s)) [[unlikely]] {
    return;
  }
  offerQuadricRoots<kOcclusion>(L, kr, q, s);
}

// ---- Packets through the quadric path ---------------------------------------------------
// Two or more active lanes of a float packet (never the double channel, which is N = 1):
// quadricPacket (quadric_packet.cpp) computes every lane's span and first root in SIMD,
// then the lanes are finished one at a time in lane order - the roots offered to the
// same accept functions, a lane the packet kernel left undecided by quadricLane - so the
// host filter sees the same calls in the same order as with the lane loop, and every hit
// is the scalar path's bit for bit (tests/embree_packet_test.cpp).
// A lone active lane (Embree's hybrid traversal calls with one) takes quadricLane: the
// lanes would compute a vector for one ray, and the packet record costs its copies.
constexpr unsigned kMinPacketLanes = 2;

template <bool kOcclusion, class Args>
void quadricPacketLanes(const Args* args, RTCRayN* ray) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  unsigned lanes[kMaxN];
  unsigned count = 0;
  for (unsigned lane = 0; lane < n; ++lane) {
    if (args->valid[lane] == 0) continue;
    // Already occluded by an earlier primitive of this packet.
    if (kOcclusion && RTCRayN_tfar(ray, n, lane) < 0.0f) continue;
    lanes[count++] = lane;
  }
  if (count < kMinPacketLanes) {
    for (unsigned i = 0; i < count; ++i) {
      try {
        quadricLane<kOcclusion>(args, ray, lanes[i]);
      } catch (...) {
        data->errors.fetch_add(1, std::memory_order_relaxed);
      }
    }
    return;
  }
  QuadricPacket p;
  for (unsigned i = 0; i < count; ++i) {
    const unsigned lane = lanes[i];
    p.ox[i] = RTCRayN_org_x(ray, n, lane);
    p.oy[i] = RTCRayN_org_y(ray, n, lane);
    p.oz[i] = RTCRayN_org_z(ray, n, lane);
    p.dx[i] = RTCRayN_dir_x(ray, n, lane);
    p.dy[i] = RTCRayN_dir_y(ray, n, lane);
    p.dz[i] = RTCRayN_dir_z(ray, n, lane);
    p.tnear[i] = RTCRayN_tnear(ray, n, lane);
    p.tfar[i] = RTCRayN_tfar(ray, n, lane);
  }
  p.count = count;
  p.wantUV = !kOcclusion && data->desc.options.uv;
  p.wantNormal = !kOcclusion;
  quadricPacket(*data, p);
  for (unsigned i = 0; i < count; ++i) {
    if (p.status[i] == QuadricPacket::kNone) continue;
    try {
      if (p.status[i] == QuadricPacket::kScalar) {
        quadricLane<kOcclusion>(args, ray, lanes[i]);
        continue;
      }
      PacketLane L{{args, data, lanes[i], nullptr, 0.0}};
      if constexpr (!kOcclusion) {
        if (p.wantUV) {
          L.uvT = p.uvT[i];
          L.uvU = p.u[i];
          L.uvV = p.v[i];
        }
        L.nT = p.nT[i];
        L.normal = glm::vec3(p.nx[i], p.ny[i], p.nz[i]);
      }
      KernelRay kr;
      kr.org = glm::dvec3(p.kox[i], p.koy[i], p.koz[i]);
      kr.dir = glm::dvec3(p.kdx[i], p.kdy[i], p.kdz[i]);
      kr.tnear = p.tnear[i];
      kr.tfar = p.tfar[i];
      kr.orgRoundoff = kFloatRoundoff;
      kr.orgError = p.orgError[i];
      QuadricSpan q;
      q.g.degree = p.degree[i];
      q.g.tShift = p.tShift[i];
      q.g.c[0] = p.c0[i];
      q.g.c[1] = p.c1[i];
      q.g.c[2] = p.c2[i];
      q.g.err[0] = p.e0[i];
      q.g.err[1] = p.e1[i];
      q.g.err[2] = p.e2[i];
      q.slo = p.slo[i];
      q.shi = p.shi[i];
      offerQuadricRoots<kOcclusion>(L, kr, q, p.s[i]);
    } catch (...) {
      data->errors.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

// ---- Embree callbacks (no exception may leave them) ---------------------------------
// A surface of one cell registers a second, empty primitive: a point at a corner of the
// cell's box. Embree tests a primitive's box only from the node above it, and the BVH of
// a scene's user geometries is a bare leaf when it holds one primitive, so without the
// point every ray of the scene (triangles' too) called the callback, which rejected those
// outside the box at ~370 instructions each (session 54's audit). With two primitives the
// root is a node whose children's boxes Embree tests; the point's union with the box is the
// box, and a ray through that corner gets one more call, which returns at once. Measured
// (session 57, AMD EPYC Zen 3, one thread; a torus in a clip sphere of radius 1.5 over a
// 100 x 100 floor quad, rays straight down, callgrind in rtcIntersect1): rays onto the floor
// wide of the box 925 -> 549 instructions (1.5-1.8x faster, best of 7 interleaved rounds),
// rays into the box 4229 -> 4263. Far float origins (~1e7 box sizes) now meet Embree's
// non-robust slab test as a scene of several primitives always did (embree.h).
unsigned embreePrimitiveCount(const SurfaceData& data) {
  return static_cast<unsigned>(data.cells.size() + (data.cells.size() == 1 ? 1 : 0));
}

// The empty primitive (primID past the cells) of embreePrimitiveCount.
bool isCornerPoint(const SurfaceData& data, unsigned primID) { return primID >= data.cells.size(); }

void boundsCallback(const RTCBoundsFunctionArguments* args) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  if (isCornerPoint(*data, args->primID)) {
    const RTCBounds& b = data->cells.front().bounds;
    *args->bounds_o =
        RTCBounds{b.lower_x, b.lower_y, b.lower_z, 0.0f, b.lower_x, b.lower_y, b.lower_z, 0.0f};
    return;
  }
  *args->bounds_o = data->cells[args->primID].bounds;
}

void intersectCallback(const RTCIntersectFunctionNArguments* args) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  if (isCornerPoint(*data, args->primID)) return;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] == 0) continue;
    try {
      traceLane(args, ray, lane, false, &acceptIntersection);
    } catch (...) {
      data->errors.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void occludedCallback(const RTCOccludedFunctionNArguments* args) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  if (isCornerPoint(*data, args->primID)) return;
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] == 0) continue;
    // Already occluded by an earlier primitive of this packet.
    if (RTCRayN_tfar(args->ray, args->N, lane) < 0.0f) continue;
    try {
      traceLane(args, args->ray, lane, true, &acceptOcclusion);
    } catch (...) {
      data->errors.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void quadricIntersectCallback(const RTCIntersectFunctionNArguments* args) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  if (isCornerPoint(*data, args->primID)) return;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  if (args->N > 1 && data->packetSimd) {
    quadricPacketLanes<false>(args, ray);
    return;
  }
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] == 0) continue;
    try {
      quadricLane<false>(args, ray, lane);
    } catch (...) {
      data->errors.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void quadricOccludedCallback(const RTCOccludedFunctionNArguments* args) {
  const auto* data = static_cast<const SurfaceData*>(args->geometryUserPtr);
  if (isCornerPoint(*data, args->primID)) return;
  if (args->N > 1 && data->packetSimd) {
    quadricPacketLanes<true>(args, args->ray);
    return;
  }
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] == 0 || RTCRayN_tfar(args->ray, args->N, lane) < 0.0f) continue;
    try {
      quadricLane<true>(args, args->ray, lane);
    } catch (...) {
      data->errors.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

}  // namespace

RTCGeometry createUserGeometry(RTCDevice device, SurfaceData* data) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  if (!g) {
    const RTCError e = rtcGetDeviceError(device);
    throw Error("algray::SurfaceGeometry: rtcNewGeometry failed (RTCError " +
                std::to_string(static_cast<int>(e)) + ")");
  }
  rtcSetGeometryUserPrimitiveCount(g, embreePrimitiveCount(*data));
  // Embree 3 ignores the userPtr of rtcSetGeometryBoundsFunction: the bounds callback
  // reads the geometry user data like the other callbacks.
  rtcSetGeometryUserData(g, data);
  rtcSetGeometryBoundsFunction(g, &boundsCallback, nullptr);
  // The callbacks are chosen once here: a quadric with one cell takes its own.
  const bool quadric = usesQuadricPath(*data);
  data->packetSimd = usesQuadricPacket(*data);
  rtcSetGeometryIntersectFunction(g, quadric ? &quadricIntersectCallback : &intersectCallback);
  rtcSetGeometryOccludedFunction(g, quadric ? &quadricOccludedCallback : &occludedCallback);
  rtcCommitGeometry(g);
  return g;
}

KernelRay hostObjectRay(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d,
                        double tnear, double tfar, double roundoff, double orgError,
                        bool deferFloatTerm) {
  return objectRay(data, o, d, tnear, tfar, roundoff, orgError, deferFloatTerm);
}

}  // namespace algray
