#pragma once
// The quadric path's declarations (quadric_path.cpp) and its packets (quadric_packet.cpp):
// a surface of degree 1 or 2 with one cell, restricted to a ray in closed form. The
// record of the generic path (ray_roots.h) takes the same restriction for a quadric in
// cells. No Embree types, as in surface_data.h.
#include "surface_data.h"

#include <limits>

namespace algray {

// ---- The quadric path (quadric_path.cpp) ------------------------------------------------
// f(x) = x^T A x + b . x + c at p, with the bound on its rounding and the gradient 2 A p + b
// (Higham, Sec. 3.1: each term of the value is at most 8 roundings deep).
struct QuadricValue {
  double value, error;
  glm::dvec3 gradient;
};
// (Always inlined: GCC kept it out of line, and the call cost shadow rays 3 %, measured.)
// (kNonNegDiagonal, kNonNegCentred, kUnitA: only when q.nonNegDiagonal, q.nonNegCentred,
// q.unitA; the same values.)
template <bool kDiagonal = false, bool kNonNegDiagonal = false, bool kNonNegCentred = false,
          bool kUnitA = false>
[[gnu::always_inline]] inline QuadricValue evalQuadric(const QuadricForm& q, const glm::dvec3& p) {
  const glm::dvec3 ap = kUnitA ? p : q.mulA<kDiagonal>(p), absP = absv(p);
  const double pap = glm::dot(p, ap);
  if constexpr (kNonNegCentred)
    return {pap + q.c, gamma(8) * (pap + std::abs(q.c)), 2.0 * ap + q.b};
  const double sumAbs = (kNonNegDiagonal ? pap : glm::dot(absP, q.mulAbsA<kDiagonal>(absP))) +
                        glm::dot(q.absB, absP) + std::abs(q.c);
  return {pap + glm::dot(q.b, p) + q.c, gamma(8) * sumAbs, 2.0 * ap + q.b};
}

// g(s) = c[0] + c[1] s + c[2] s^2 = f(o + (tShift + s) d), degree <= 2, with a bound on
// the error of each coefficient: the restriction of a quadric to a ray in closed form.
struct QuadricRay {
  int degree = 2;
  // The origin was on the surface and its root divided out. (In degree's padding: at 72
  // bytes instead of 64 the record cost the sphere's single rays a third of their speed,
  // measured; GCC no longer keeps it in registers.)
  bool selfRoot = false;
  double tShift = 0;
  double c[3] = {0, 0, 0};
  double err[3] = {0, 0, 0};
};
static_assert(sizeof(QuadricRay) == 64);
// About the origin when it lies on the surface (the self-root rule: the root at s = 0 is
// divided out), else about the point of [r0, r1] closest to the clip centre. closest: that
// point's parameter closestParameter(o, d, data.centre) when the caller has it (NaN: not).
// oc2: |o - data.centre|^2 as originOutsideClipBall computes it, when the caller has it
// (NaN: not).
void restrictQuadricRay(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                        QuadricRay& g, double closest = std::numeric_limits<double>::quiet_NaN(),
                        double oc2 = std::numeric_limits<double>::quiet_NaN());

// The dedicated path of a quadric with one cell (the bridge registers its callbacks when
// usesQuadricPath): the restriction over the ray's span, clip region and (tnear, tfar)
// at once, and its roots one at a time, with no per-thread record, cell ownership or
// generic solver frame.
bool usesQuadricPath(const SurfaceData& data);
// Whether the one cell's box holds the clip region's box (else quadricCellClip).
bool cellHoldsClipRegion(const SurfaceData& data);
// An ellipsoid's (definite A) object-space box, padded to hold every point the
// intersector can report, intersected with the clip region's box: the tight cell. False
// when f is not a definite quadric (or too ill-conditioned to box safely), or the box
// misses the clip region. Needs desc, the transform fields, centre and radius of data.
bool boundedQuadricBox(const SurfaceData& data, QuadricBox& box);
struct QuadricSpan {
  QuadricRay g;
  double slo = 0, shi = 0;  // the span in s
};
// False when the span is empty or the ray is not finite (no hit).
bool quadricSpan(const SurfaceData& data, const KernelRay& ray, QuadricSpan& q);
// The first root s of q.g in (slo, q.shi] by the rules of firstRoot (algray/roots.h): a
// root within noise of slo is not reported, so slo = the previous root gives the next.
bool quadricRoot(const QuadricSpan& q, double slo, double& s);

// ---- Packets through the quadric path (quadric_packet.cpp) ------------------------------
// The float rays of an rtcIntersect4/8/16 or rtcOccluded4/8/16 call, compacted to the
// lanes the bridge traces, in world space (structure of arrays, padded to a multiple of
// the kernel's vector width). For each, quadricPacket computes what quadricLane would:
// the object-space ray (objectRay of embree_bridge.cpp for a float ray), quadricSpan and
// the first quadricRoot, bit for bit, for the common cases; every other lane is marked
// for the scalar path.
constexpr unsigned kPacketLanes = 16;
struct QuadricPacket {
  enum Status : int { kNone = 0, kRoot = 1, kScalar = 2 };
  unsigned count = 0;
  // In: world-space float rays as doubles.
  alignas(64) double ox[kPacketLanes], oy[kPacketLanes], oz[kPacketLanes];
  alignas(64) double dx[kPacketLanes], dy[kPacketLanes], dz[kPacketLanes];
  alignas(64) double tnear[kPacketLanes], tfar[kPacketLanes];
  // Out: kNone (quadricSpan or quadricRoot found nothing), kRoot (the first root s, with
  // the object-space ray and the span below), kScalar (ask quadricLane).
  alignas(64) int status[kPacketLanes];
  alignas(64) double s[kPacketLanes];
  alignas(64) double kox[kPacketLanes], koy[kPacketLanes], koz[kPacketLanes];
  alignas(64) double kdx[kPacketLanes], kdy[kPacketLanes], kdz[kPacketLanes],
      orgError[kPacketLanes];
  alignas(64) int degree[kPacketLanes];
  alignas(64) double tShift[kPacketLanes], c0[kPacketLanes], c1[kPacketLanes], c2[kPacketLanes];
  alignas(64) double e0[kPacketLanes], e1[kPacketLanes], e2[kPacketLanes], slo[kPacketLanes],
      shi[kPacketLanes];
  // For intersection queries (wantUV): surfaceUVFloat's u, v before the cast to float at
  // the first root's point t = tShift + s, in uvT; NaN where the lanes left it to it.
  bool wantUV = false;
  alignas(64) double u[kPacketLanes], v[kPacketLanes], uvT[kPacketLanes];
  // For intersection queries (wantNormal): Embree's float Ng as the bridge writes it (the
  // world-space gradient at the first root's point, cast to float) in nx, ny, nz, at the
  // t in nT; NaN where the lanes left it to the bridge (a gradient outside float's range).
  bool wantNormal = false;
  alignas(64) double nT[kPacketLanes];
  alignas(64) float nx[kPacketLanes], ny[kPacketLanes], nz[kPacketLanes];
};
// Whether quadricPacket can handle data's rays at all (the quadric path with a clip
// sphere, re-centring on, and SurfaceOptions::packetSimd).
bool usesQuadricPacket(const SurfaceData& data);
void quadricPacket(const SurfaceData& data, QuadricPacket& p) noexcept;

}  // namespace algray
