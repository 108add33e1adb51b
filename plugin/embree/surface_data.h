#pragma once
// The adapter's private state of one surface geometry, and the Embree-free kernel that
// walks the roots of one ray through one cell. Shared by surface_geometry.cpp (set-up),
// the kernel (surface_intersect.cpp, ray_roots.cpp, self_root.cpp, ray_settle.cpp), the
// quadric path (quadric_path.h) and embree_bridge.cpp (the callback ABI).
#include "algray/embree.h"
#include "algray/horner_form.h"
#include "algray/taylor.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <vector>

namespace algray {

// |v| per component. (glm::abs is x >= 0 ? x : -x, a compare and a blend each; std::abs
// clears the sign bit: 50 of the 1175 instructions of a primary ray at the sphere.)
inline glm::dvec3 absv(const glm::dvec3& v) {
  return {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
}

// One Embree primitive: an object-space box (a cell, or the box of the whole clip region)
// and its padded world-space bounds.
struct SurfaceCell {
  glm::dvec3 lo{0.0}, hi{0.0};
  RTCBounds bounds{};
};

// An ellipsoid's tight cell (boundedQuadricBox, quadric_path.cpp): the object-space box
// lo..hi holds every root the intersector can report for a ray whose origin error is at
// most orgError and whose origin lies within distance of the clip centre.
struct QuadricBox {
  glm::dvec3 lo{0.0}, hi{0.0};
  // The ellipsoid's own box (f <= 0 up to rounding, without the padding for float origins
  // that lo, hi carry): the object's size (SurfaceData::objectRadius).
  glm::dvec3 surfaceLo{0.0}, surfaceHi{0.0};
  double orgError = -1, distance = -1;
  // A ball holding the same points (ballRadius2 its padded squared radius): a ray the box
  // covers that passes outside it has no root to report (quadricSpan's early rejection).
  glm::dvec3 ballCentre{0.0};
  double ballRadius2 = std::numeric_limits<double>::infinity();
  // A float ray with a deferred origin error (KernelRay::orgErrorDeferred) and no host
  // part (orgError 0) has its whole bound within orgError when |o - centre|^2 is at most
  // this (0: never; quadricSpan, set by boundedQuadricBox).
  double coveredNear2 = 0;
};

// A degree-2 surface as f(x) = x^T A x + b . x + c (A symmetric), for the quadric path of
// the kernel (ray_roots.cpp): restriction, self-root test and normal in closed form.
struct QuadricForm {
  glm::dmat3 a{0.0};
  glm::dvec3 b{0.0};
  double c = 0;
  glm::dmat3 absA{0.0};  // |A|, |b| entrywise, for the error bounds
  glm::dvec3 absB{0.0};
  // A diagonal (no mixed terms: spheres, axis-aligned ellipsoids, cylinders, cones,
  // paraboloids...): A v and |A| v as three products, the same values as the full
  // products (which only add exact zeros to them) but a fifth of the work.
  bool diagonal = false;
  glm::dvec3 diagA{0.0}, absDiagA{0.0};
  // Diagonal with every entry >= +0 (spheres, ellipsoids, cylinders): then |v|^T |A| |v| =
  // v^T A v bit for bit (each term |v_i| (|a_i| |v_i|) is v_i (a_i v_i), rounding being
  // symmetric in sign; no -0 entry, whose terms would be -0), so the error bounds of
  // evalQuadric and restrictQuadricRay take those sums from the values (measured: ~16 of
  // the ~100 floating-point operations of a restriction).
  bool nonNegDiagonal = false;
  // With that, b = 0 (both zeros): the terms of b are zeros added to values >= +0 (or, for
  // the value, to v^T A v >= +0: +0 + -0 = +0), which change nothing (the gradient keeps
  // its + b, which turns a -0 component into +0).
  bool nonNegCentred = false;
  // A = I (a sphere about the origin, up to its constant): A v is v (1 v_i = v_i exactly).
  bool unitA = false;
  // A v and |A| v; kDiagonal (only when diagonal) takes the three products.
  template <bool kDiagonal = false>
  glm::dvec3 mulA(const glm::dvec3& v) const {
    if constexpr (kDiagonal) return diagA * v;
    return a * v;
  }
  template <bool kDiagonal = false>
  glm::dvec3 mulAbsA(const glm::dvec3& v) const {
    if constexpr (kDiagonal) return absDiagA * v;
    return absA * v;
  }
  // grad f(x) = 2 A x + b (the same values as evalQuadric's).
  glm::dvec3 gradient(const glm::dvec3& x) const {
    return 2.0 * (unitA ? x : diagonal ? mulA<true>(x) : mulA(x)) + b;
  }
  static QuadricForm fromPolynomial(const Polynomial& f);
};

struct SurfaceData {
  // The description the kernels work with: the host's, with the clip region widened
  // (widenedClip, surface_geometry.cpp).
  SurfaceDesc desc;
  // The host's description as given, for SurfaceGeometry::desc() (a host cloning a
  // surface from desc() would otherwise widen its clip region twice).
  SurfaceDesc given;
  std::optional<QuadricForm> quadric;  // set when desc.polynomial has degree 2 exactly
  // The quadric path clips rays to cells.front(): the one cell is smaller than the clip
  // region (an ellipsoid's own box, boundedQuadricBox; or a cell the build shrank).
  bool quadricCellClip = false;
  QuadricBox quadricBox;        // the tight cell, when the one cell is an ellipsoid's box
  bool packetSimd = false;      // usesQuadricPacket: packets take quadric_packet.cpp
  double quadricMoveBound = 0;  // see restrictQuadricRay's second division
  // f, grad f and the bound at a point (self-root rule, polish), precompiled from
  // desc.polynomial.
  HornerForm horner;
  // desc.transform = [a | b]: world p = a x + b; x = aInv (p - b); normals by aInvT.
  glm::dmat3 a{1.0}, aInv{1.0}, aInvT{1.0};
  glm::dvec3 b{0.0};
  bool identity = true;
  // Centre and radius of a ball holding the clip region (object space): the frame for
  // re-centring and the scale every relative tolerance of the adapter refers to.
  glm::dvec3 centre{0.0};
  double radius = 1.0;
  double selfRootRadius2 = 1.0;  // (radius (1 + 2^-9))^2: see restrictQuadricRay
  // The radius about centre of a ball holding every point of the surface in the clip region
  // (at most radius; objectRadiusOf, surface_geometry.cpp): the object's size.
  double objectRadius = 1.0;
  // The scale of the scene a host's hit point comes from: the clip radius, but at most 2^13
  // object radii (kSceneObjects, surface_geometry.cpp). It sizes a float origin's assumed
  // uncertainty (floatOriginError, originRootMatters) and the normal's search beside a hit
  // (hit_normal.cpp). Not the clip radius alone: a unit sphere clipped to a ball of radius
  // 1e7 gave every float origin in the ball an uncertainty of 9.5, so a camera 5 away took
  // itself for a point of the sphere and the self-root rule removed the sphere
  // (algray-render drew nothing from clip radius 3e6 on; the audit of session 51). Not the
  // object's radius alone: that assumed cameras within ~8 object radii, and rays leaving a
  // unit sphere clipped to a ball of radius 100, hit points of a camera 455 away (4.55 clip
  // radii, algray-render's quick view), met their own origin (the review of session 51).
  double sceneRadius = 1.0;
  double floatOriginNear2 = 0.0;  // (256 radius)^2 (0: unused): see surelyOutsideClipBall
  std::vector<SurfaceCell> cells;
  // The cells' grid (they are one level of a regular subdivision of the box around the
  // clip region): box corner, size and cells per axis, and the cell of each grid key.
  // Empty when there is one cell or the cells are not a regular grid.
  glm::dvec3 gridLo{0.0}, gridSize{1.0}, gridN{1.0};
  std::unordered_map<std::uint64_t, unsigned> cellOfKey;
  RTCGeometry geometry = nullptr;
  std::uint64_t id = 0;  // unique per process: keys the per-thread origin cache
  mutable std::atomic<unsigned long long> errors{0};
  // A ball holding the clip region in world space (the double channel's far origins):
  // a centre and a radius rounded up.
  glm::dvec3 worldCentre{0.0};
  double worldRadius = 1.0;
  // The gradient's rounding noise (hit_normal.cpp): f with |coefficients| for gradientNoise,
  // its factor gamma(4m + 8), and the hits' slope test (slopeClear; 0: off).
  HornerForm absHorner;
  double gradientGamma = 0;
  double hitSlopeNoise = 0;
  double hitPointNoise = 0;  // 2^10 times a bound of |hess f| (row sums) over the clip ball
  // B_k: |d/dv c_k| <= B_k |d|_inf^k |v|_inf over the clip ball, c_k = D^k f [d^k] / k! the
  // k-th Taylor coefficient along d (inf where it overflows): the self-root rule's first
  // test of whether c_k is zero within the origin's uncertainty (multipleRootWindow).
  std::array<double, kMaxDegree + 1> coefficientMove{};
  // 4 times |hess f| as sampled over the clip box (inf: none measured; both unset for a
  // quadric, whose self-root rule is quadric_path.cpp's).
  double sampledHessian = 0;
};

// A ray in the surface's object space.
struct KernelRay {
  glm::dvec3 org{0.0};
  glm::dvec3 dir{0.0};
  double tnear = 0;
  double tfar = 0;
  // Relative uncertainty of the origin coordinates (unit roundoff of the precision the
  // host stored them in) and an absolute bound given by the host (RayD::orgError).
  double orgRoundoff = kUnitRoundoff;
  double orgError = 0;
  // The float ray Embree traverses with (geometry space), when it differs from this one
  // (the double channel): a root is owned by a cell that Embree can reach.
  bool hasTraversalRay = false;
  // orgError lacks the float origin's term floatOriginError (the bridge's float rays into
  // the generic walk and the quadric path, which add it only where a test needs it,
  // wholeOrgError; its square root cost every primary ray, see ray_roots.cpp's
  // restrict).
  bool orgErrorDeferred = false;
  // A double ray whose host stated orgError > 0 (objectRay; the origin window of
  // deriveRayRoots and quadricLane: orgError above is always > 0 for a transformed
  // surface). (Beside the other flags, in their padding: KernelRay is copied per ray.)
  bool hostBound = false;
  // A transformed surface's orgError in two parts: W, the world-space bound objectRay maps
  // through |A^-1|_F (the host's bound, a float origin's rounding: world lengths), and the
  // object-space rest (without a deferred float term). The self-root rule weighs W along
  // the gradient and the ray instead (originMove, selfRootWindow). 0, 0: the identity.
  double orgErrorWorld = 0, orgErrorObject = 0;
  std::uint64_t trace = 0;  // the double channel's IntersectContext::trace (0: none)
  glm::dvec3 travOrg{0.0}, travDir{0.0};
};

// A host's ray (world space; roundoff: the unit roundoff of its precision, orgError the
// host's bound) in data's object space, as the bridge forms it for the kernels (its
// objectRay, kept static there: measured, an external objectRay cost the quadric path's
// single rays a quarter of their speed in copies of the returned ray). For tests; the
// packet lanes of quadric_packet.cpp repeat it for float rays.
// deferFloatTerm: as the bridge's float rays, with orgErrorDeferred.
KernelRay hostObjectRay(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d,
                        double tnear, double tfar, double roundoff, double orgError,
                        bool deferFloatTerm = false);

// The term a float ray's orgError gets for its origin's own rounding (objectRay,
// embree_bridge.cpp): 16 u_float (|o - c| + R_s) for its object-space origin o, roundoff
// its unit roundoff, R_s the scene's radius (SurfaceData::sceneRadius): a hit point of a
// ray that started within a few such radii. One expression for the bridge and the walk's
// deferred form (bit for bit).
inline double floatOriginError(const SurfaceData& data, const glm::dvec3& o, double roundoff) {
  return 16.0 * roundoff * (glm::length(o - data.centre) + data.sceneRadius);
}

// A ray's whole orgError (with its deferred term added, KernelRay::orgErrorDeferred).
inline double wholeOrgError(const SurfaceData& data, const KernelRay& ray) {
  return ray.orgErrorDeferred ? ray.orgError + floatOriginError(data, ray.org, ray.orgRoundoff)
                              : ray.orgError;
}

// The object-space rest of a ray's whole orgError (KernelRay::orgErrorObject, with a
// deferred float term added).
inline double objectOrgError(const SurfaceData& data, const KernelRay& ray) {
  return ray.orgErrorDeferred
             ? ray.orgErrorObject + floatOriginError(data, ray.org, ray.orgRoundoff)
             : ray.orgErrorObject;
}

// Whether originOutsideClipBall holds for a float ray whose orgError lacks its
// floatOriginError (orgErrorDeferred), known without that term's square root (oc2:
// |o - centre|^2): the origin lies beyond selfRootRadius2 but within 256 R of the centre
// (floatOriginNear2), so with u_float <= 2^-24 and a host part at most 2^-13 R the whole
// bound is at most 2^-13 R + 2^-20 (257 R) (1 + 4 u) < 2^-11 R. (0: a radius outside
// [2^-400, 2^400], where the scalings might round: the term is then computed.)
inline bool surelyOutsideClipBall(const SurfaceData& data, double oc2, const KernelRay& ray) {
  return oc2 > data.selfRootRadius2 && oc2 <= data.floatOriginNear2 && ray.orgRoundoff <= 0x1p-24 &&
         ray.orgError <= 0x1p-13 * data.radius;
}

// A candidate root handed to the acceptance callback (the host filter).
struct KernelHit {
  double t = 0;
  glm::dvec3 point{0.0};     // object space
  glm::dvec3 gradient{0.0};  // object space; zero for occlusion queries
};

// ---- The normal at a closest hit (hit_normal.cpp) ----------------------------------------
// A bound of the rounding error of each component of grad f as HornerForm::evaluate (or
// QuadricForm::gradient) computes it at p: gamma(4m + 8) sum |c| e_i |p|^(e - e_i) over the
// monomials c p^e, the gradient of f's |coefficients| at |p|. Horner's derivative
// recurrences err by gamma(2n) times that sum in one variable (Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., Sec. 5.1); the nested scheme takes at most
// 2(i + j + k) + 4 operations per term. (A detector's bound: it decides where the normal
// is looked for beside the hit.)
inline glm::dvec3 gradientNoise(const SurfaceData& data, const glm::dvec3& p) {
  return data.gradientGamma * data.absHorner.evaluate(absv(p)).gradient;
}
// grad f at a hit found beside it where the hit's slope along the ray, grad f . d, is not
// clear (hit_normal.cpp: a multiple surface h^k = 0, a singular point, a ray grazing the
// surface); else `gradient` itself.
glm::dvec3 gradientBesideNoise(const SurfaceData& data, const glm::dvec3& dir,
                               const glm::dvec3& point, const glm::dvec3& gradient,
                               double pointError);
// A bound of the rounding of a hit point o + t d as computed (per component, max norm):
// gamma(2) (|o| + |t d|). From far away it dwarfs the gradient's own noise: a point of a
// double surface 1e6 radii along a ray lands up to 2e-10 radii to either side of it, where
// grad f = 2 h q grad h is clear of its noise and points away from the ray on the far side.
inline double hitPointError(const glm::dvec3& org, const glm::dvec3& dir, double t) {
  const glm::dvec3 o = absv(org), d = absv(dir);
  return gamma(2) * (std::max({o.x, o.y, o.z}) + std::abs(t) * std::max({d.x, d.y, d.z}));
}
// Whether the slope grad f . d at a hit exceeds 2^10 times its noise, bounded over the
// whole clip ball (hitSlopeNoise, a constant per surface: measured, a bound at the hit
// point itself cost the sphere's primary rays 5 %), plus what the point's own rounding
// `pointError` can move it by (hitPointNoise: at most (m - 1) / (2m + 4) of the first term
// for a point rounded by 2u R, a ray from within the clip ball, and (|o| + |t d|) / R times
// that from farther; only hits whose slope is that close to zero take gradientBesideNoise:
// speed_report's primary rays 0.96-1.01x, within its noise, session 42).
inline bool slopeClear(const SurfaceData& data, const glm::dvec3& dir, const glm::dvec3& gradient,
                       double pointError) {
  const double l1 = std::abs(dir.x) + std::abs(dir.y) + std::abs(dir.z);
  return std::abs(glm::dot(gradient, dir)) >
         (data.hitSlopeNoise + data.hitPointNoise * pointError) * l1;
}
// The gradient a closest hit reports as its normal (object space): `gradient`, computed at
// the hit, where the slope is clear (every ordinary hit), else gradientBesideNoise.
inline glm::dvec3 hitGradient(const SurfaceData& data, const glm::dvec3& dir,
                              const glm::dvec3& point, const glm::dvec3& gradient,
                              double pointError) {
  if (slopeClear(data, dir, gradient, pointError)) [[likely]]
    return gradient;
  return gradientBesideNoise(data, dir, point, gradient, pointError);
}

// Returns true to accept the candidate (stop), false to ask for the next root.
using AcceptFn = bool (*)(void* user, const KernelHit& hit);

// Walks the roots of f(o + t d) in increasing t inside cell `cell`, restricted to the
// open interval (tnear, tfar), and offers each to accept(). Returns whether one was
// accepted. Never throws for non-finite input (no roots); may throw algray::Error or
// std::bad_alloc, which the bridge catches.
bool walkRoots(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
               AcceptFn accept, void* user);

// u, v of a hit point as documented in algray/embree.h.
void surfaceUV(const SurfaceData& data, const glm::dvec3& point, double& u, double& v);
// The same for Embree's float u, v: within 2e-10 of them, at a third of the cost.
void surfaceUVFloat(const SurfaceData& data, const glm::dvec3& point, float& u, float& v);
// Embree's float u of a u in [0, 1): the cast rounds a u within 2^-25 of 1 (the seam's
// far side, y -> 0-) up to 1.0f, which a host indexing a texture by u * width reads one
// past the end of; the largest float below 1 instead.
inline float floatU(double u) { return std::min(static_cast<float>(u), 0x1.fffffep-1f); }
// surfaceUVFloat's 1 / (2 pi) and 1 / pi, rounded.
inline constexpr double kInvTwoPi = 0.15915494309189535, kInvPi = 0.31830988618379069;
// Its atan on [0, 1]: atan(t) = t p(t^2), p of degree 9 with these coefficients (the fit
// is described at atanUnit, surface_intersect.cpp; the packet lanes use it too).
inline constexpr double kAtanPoly[10] = {
    0.99999998406654822,   -0.33333194338035299,  0.19996618767948782,  -0.14248359660926879,
    0.10881981041904727,   -0.082220750117259683, 0.055134709912894257, -0.028572750129062584,
    0.0096020026957349888, -0.0015154920071548067};

// Every surface's float bounds lie within +-kEmbreeReach (checkEmbreeRange): Embree drops
// boxes beyond FLT_LARGE (1.844e18), and the double channel moves far ray origins to the
// cube of 1.5e18 (makeRayHit), which must lie before every surface.
inline constexpr double kEmbreeReach = 1e18;

// Whether an origin lies outside the clip ball by 2^-9 of its radius (selfRootRadius2),
// known to 2^-11 of it: a root at the origin then lies outside every span the ray has
// (which starts beyond that margin), so the self-root rule has nothing to remove. Shared
// by the generic walk and the quadric path (the packet lanes repeat it in vector form).
// (oc2 = dot(o - data.centre, o - data.centre), for callers that have it.)
inline bool originOutsideClipBall(const SurfaceData& data, double oc2, double orgError) {
  return oc2 > data.selfRootRadius2 && orgError <= 0x1p-11 * data.radius;
}
inline bool originOutsideClipBall(const SurfaceData& data, const glm::dvec3& o, double orgError) {
  const glm::dvec3 oc = o - data.centre;
  return originOutsideClipBall(data, glm::dot(oc, oc), orgError);
}

// How far the origin may lie from the point it stands for: the bound plus its coordinates'
// own rounding (orgRoundoff |o|_1). (The self-root rule's distance; orgError: the ray's
// whole bound.)
inline double originDistance(const KernelRay& ray, double orgError) {
  const glm::dvec3& o = ray.org;
  return orgError + ray.orgRoundoff * (std::abs(o.x) + std::abs(o.y) + std::abs(o.z));
}

// After the self-root rule divided out the root at an origin judged on the surface, the
// ray parameter below which a root is still that origin's own: within the origin's
// uncertainty (orgError plus the rounding of its coordinates), twice over. Near a singular
// point the line through an uncertain origin meets the surface again within that
// distance (a float ray leaving a cone's apex found the apex again at t = 3e-8..5e-8 on
// half of its directions; Barth's and Cayley's nodes alike), which no coefficient test
// can tell from the origin. pbrt-v4 offsets a spawned ray's origin by its error bound for
// the same reason (Sec. 6.8.6); a legitimate hit that close to the origin is
// indistinguishable from it.
// (orgError: the ray's whole bound, for a ray whose orgError is deferred.)
//
// A transformed surface's world part W of the bound (KernelRay::orgErrorWorld) is a ball in
// world space, where t is the same: the window takes it over the world direction A d,
// 2 W / |A d|, and the object-space rest over d, whichever of that and the isotropic
// window is smaller (both hold). Through |A^-1|_F alone, a float ray leaving a flattened
// object 1e4 from the world origin (diag(1, 1, 1e-3)) had a window of five radii over the
// object-space |d| and skipped the object's far side (tests/embree_transform_test.cpp).
// (A d rounds to d_world within a relative O(kappa(A) u), well below the 2^-20 added.)
inline double selfRootDistance(const KernelRay& ray, double orgError) {
  return 2.0 * originDistance(ray, orgError);
}
// (Out of line, as the other transformed-surface parts: the rule's common path stays small.)
[[gnu::noinline]] inline double worldSelfRootWindow(const SurfaceData& data, const KernelRay& ray,
                                                    double isotropic) {
  const glm::dvec3 worldDir = data.a * ray.dir;
  const double world = 2.0 * ray.orgErrorWorld / std::sqrt(glm::dot(worldDir, worldDir));
  const double rest =
      selfRootDistance(ray, objectOrgError(data, ray)) / std::sqrt(glm::dot(ray.dir, ray.dir));
  return std::min(isotropic, (1.0 + 0x1p-20) * (world + rest));
}
inline double selfRootWindow(const SurfaceData& data, const KernelRay& ray, double orgError) {
  const double isotropic = selfRootDistance(ray, orgError) / std::sqrt(glm::dot(ray.dir, ray.dir));
  if (ray.orgErrorWorld > 0.0) [[unlikely]]
    return worldSelfRootWindow(data, ray, isotropic);
  return isotropic;
}
// Whether a root s >= 0 lies within that window, without its root and division (the
// quadric path's shadow rays, where most first roots lie far beyond it: measured, the
// window computed for every such ray cost the sphere's shadow rays ~10 %).
inline bool withinSelfRootWindow(const SurfaceData& data, const KernelRay& ray, double s,
                                 double orgError) {
  if (ray.orgErrorWorld > 0.0) [[unlikely]]
    return s <= selfRootWindow(data, ray, orgError);
  const double dist = selfRootDistance(ray, orgError);
  return s * s * glm::dot(ray.dir, ray.dir) <= dist * dist;
}

// The axis-aligned box of a clip region (a sphere's bounding box, or the box itself).
inline void clipRegionBox(const ClipRegion& clip, glm::dvec3& lo, glm::dvec3& hi) {
  if (const auto* s = std::get_if<ClipSphere>(&clip)) {
    lo = s->center - glm::dvec3(s->radius);
    hi = s->center + glm::dvec3(s->radius);
  } else {
    lo = std::get<ClipBox>(clip).lo;
    hi = std::get<ClipBox>(clip).hi;
  }
}

// ---- Small helpers shared by the kernels -------------------------------------------
inline bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// |v| without overflow or underflow of the squares (a gradient of a surface with
// coefficients like 1e200 is ~1e200; its square is not a double).
inline double safeLength(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0.0) || !std::isfinite(m)) return m;
  return m * glm::length(v / m);
}

// How far the origin's uncertainty (orgError, the ray's whole bound) can move f there, for
// the self-root rule: |grad f| orgError (gradLength: |grad f|). For a transformed surface
// the world part W of the bound is a ball in world space, an ellipsoid A^-1 B(W) in object
// space, over which f moves by at most |A^-T grad f| W (grad f . A^-1 v = A^-T grad f . v);
// the rest is isotropic. Taken through |A^-1|_F alone, float origins near a flattened object
// 1e4 from the world origin (diag(1, 1, 1e-3)) were spread five radii along its thin axis,
// and the rule put origins four radii off the surface on it: their hit was divided out
// (tests/embree_transform_test.cpp). The smaller of the two bounds (both hold); 2^-20 for
// the rounding of A^-T grad f and of the sum.
[[gnu::noinline]] inline double worldOriginMove(const SurfaceData& data, const KernelRay& ray,
                                                const glm::dvec3& gradient, double gradLength,
                                                double isotropic) {
  const double world = safeLength(data.aInvT * gradient) * ray.orgErrorWorld;
  return std::min(isotropic, (1.0 + 0x1p-20) * (world + gradLength * objectOrgError(data, ray)));
}
inline double originMove(const SurfaceData& data, const KernelRay& ray, const glm::dvec3& gradient,
                         double gradLength, double orgError) {
  const double isotropic = gradLength * orgError;
  if (ray.orgErrorWorld > 0.0) [[unlikely]]
    return worldOriginMove(data, ray, gradient, gradLength, isotropic);
  return isotropic;
}
// What the origin's whole uncertainty moves a quantity with that gradient at the origin by:
// the rounding of its coordinates (orgRoundoff |o_i|) plus originMove (the self-root rule's
// tests of a cluster's coefficients, multipleRootWindow and the quadric path's).
inline double originUncertaintyMove(const SurfaceData& data, const KernelRay& ray,
                                    const glm::dvec3& gradient, double orgError) {
  const double rounding = ray.orgRoundoff * glm::dot(absv(gradient), absv(ray.org));
  return orgError != 0.0
             ? rounding + originMove(data, ray, gradient, safeLength(gradient), orgError)
             : rounding;
}

// Slab test (Kay & Kajiya), written so that a zero direction component keeps the ray
// inside or outside the slab instead of producing 0 * inf = NaN. With widen = true both
// ends of each slab are widened by 2 gamma(3) of their magnitude (the subtraction and the
// product round once each; pbrt-v4 Sec. 6.8.7 widens the far end): adjacent cells then
// overlap by rounding, so a root on a shared face is never lost between them.
// A subnormal d_i below 2^-1024 is not zero, though its reciprocal overflows: the ray
// crosses the slab's faces at finite (face - o_i) / d_i when o_i is within a few d_i of
// one, so it divides (two roundings, within the widening). With 1 / d_i = inf the slab
// was all or nothing: a ray from x = -1e-310 along (1e-310, 1, 0) never entered the box
// x >= 0, one from x = 2e-310 along (-1e-310, 1, 0) never left it. (Under DAZ, as in
// Embree's worker threads, such a d_i reads as 0: the zero branch, consistently.)
inline bool clipToBox(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& o,
                      const glm::dvec3& d, double& t0, double& t1, bool widen = false) {
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (o[i] < lo[i] || o[i] > hi[i]) return false;
      continue;
    }
    const double inv = 1.0 / d[i];
    double ta, tb;
    if (std::isinf(inv)) [[unlikely]] {
      ta = (lo[i] - o[i]) / d[i];
      tb = (hi[i] - o[i]) / d[i];
    } else {
      ta = (lo[i] - o[i]) * inv;
      tb = (hi[i] - o[i]) * inv;
    }
    if (ta > tb) std::swap(ta, tb);
    if (widen) {
      ta -= 2.0 * gamma(3) * std::abs(ta);
      tb += 2.0 * gamma(3) * std::abs(tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

// Sphere by the closest point of the line to the centre (pbrt-v4, Sec. 6.8.1: the chord
// half-length from R^2 - |q|^2 avoids the cancellation of the textbook quadratic when
// the origin is far away; near origins take the shorter textbook form, see below).
// tc: the parameter of that closest point; it equals
// closestParameter(o, d, s.center) bit for bit (fl(c - o) = -fl(o - c), and the dot and
// product negate exactly). With 1 / dd from inverseSquaredLength (taylor.h), tc may be
// off by delta <= 2^-40 |tc|: |q|^2 grows by delta^2 dd only, so the chord keeps its
// length and moves by delta, a shift of the clip boundary far below a float origin's
// own rounding.
// terms, if given, receives |o - c|^2 and, when the chord takes the closest-point form,
// |q|^2 (else q2 is left as it was): the quadric path's cell and ball tests repeat that
// arithmetic (quadricSpan, meetsQuadricBall).
struct ChordTerms {
  double oc2, q2;
};
inline bool clipToSphere(const ClipSphere& s, const glm::dvec3& o, const glm::dvec3& d, double& t0,
                         double& t1, double& tc, ChordTerms* terms = nullptr) {
  const double dd = glm::dot(d, d);
  if (!(dd > 0.0)) return false;
  const double inv = inverseSquaredLength(dd);
  const glm::dvec3 oc = o - s.center;
  const double b = glm::dot(oc, d), r2 = s.radius * s.radius, oc2 = glm::dot(oc, oc);
  if (terms) terms->oc2 = oc2;
  tc = -b * inv;
  // From an origin within 2 R of the centre (a ray leaving a surface inside), Lagrange's
  // h^2 = R^2 - |oc|^2 + b^2 / dd has no cancellation beyond its terms' 4 R^2 and a
  // shorter dependency chain to the root (measured on shadow rays); from farther, the
  // closest point q.
  double h2;
  if (oc2 <= 4.0 * r2) {
    h2 = (r2 - oc2) + b * b * inv;
  } else {
    const glm::dvec3 q = oc + tc * d;
    const double qq = glm::dot(q, q);
    if (terms) terms->q2 = qq;
    h2 = r2 - qq;
  }
  if (!(h2 >= 0.0)) return false;
  const double dt = std::sqrt(h2 * inv);
  t0 = std::max(t0, tc - dt);
  t1 = std::min(t1, tc + dt);
  return t0 <= t1;
}

// The ray's span (t0, t1) inside the clip region (every cell shares it); false if empty.
// Inline: out of line (in surface_intersect.cpp) it returned t0, t1 through memory, and
// the walk then built the pair (t0, t1) for its per-thread record from two 8-byte
// stores with one 16-byte load, a store-forwarding stall on every ray (perf: 19 % of
// walkRootsOf's samples on the Barth sextic).
inline bool clipRegionSpan(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d,
                           double& t0, double& t1) {
  t0 = -std::numeric_limits<double>::infinity();
  t1 = std::numeric_limits<double>::infinity();
  double tc;
  if (const auto* s = std::get_if<ClipSphere>(&data.desc.clip))
    return clipToSphere(*s, o, d, t0, t1, tc);
  const auto& b = std::get<ClipBox>(data.desc.clip);
  return clipToBox(b.lo, b.hi, o, d, t0, t1);
}

// Whether the self-root rule's division by s instead of by the origin's root r ~ -c0 / c1
// (ray_roots.cpp, divideByOriginRoot; quadric_path.cpp, originRootApart) would move the
// ray's other roots by more than its resolution, 16 roundings of |o|_1 + R_s: |r| |d|_1
// beyond that. For a float ray that is the uncertainty its channel gives every origin
// (README), for a double ray 2^-49 of the scale. Below it, g / s stays: on a float shadow
// ray c0 clears double's rounding whenever the float origin is off the surface, and the
// division by r on all of them cost the gallery's float shadow rays 10-25 % (speed_report,
// session 46), for moves within a few float roundings of the scene.
// (Written as the packet kernel computes it, quadric_packet_group.inc: the same bits.)
// oSum, dSum: |o|_1 and |d|_1 (summed x, y, z in that order).
inline bool originRootMatters(const SurfaceData& data, const KernelRay& ray, double c0, double c1,
                              double oSum, double dSum) {
  return std::abs(c0) * dSum > 16.0 * ray.orgRoundoff * (oSum + data.sceneRadius) * std::abs(c1);
}
inline bool originRootMatters(const SurfaceData& data, const KernelRay& ray, double c0, double c1) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  return originRootMatters(data, ray, c0, c1, std::abs(o.x) + std::abs(o.y) + std::abs(o.z),
                           std::abs(d.x) + std::abs(d.y) + std::abs(d.z));
}

// The self-root rule's division by s (ray_roots.cpp): g(0) = 0 is removed from
// g = sum c_i s^i (error bounds err_i). Once: a new constant term that is zero only within
// its bound is not set to zero and divided out again (a ray tangent at its origin, an
// origin at a singular point), as it was until session 43: that perturbed g by c_1 s far
// from the origin, which split the far side's double root of a squared sphere into a
// complex pair (a ray leaving it inwards from a point rounded off it missed the far side).
// The roots left near the origin lie within multipleRootWindow (ray_roots.cpp).
template <class Array>
void deflateAtZero(int& degree, Array& c, Array& err) {
  for (int i = 0; i < degree; ++i) {
    c[i] = c[i + 1];
    err[i] = err[i + 1];
  }
  c[degree] = err[degree] = 0.0;
  --degree;
}

}  // namespace algray
