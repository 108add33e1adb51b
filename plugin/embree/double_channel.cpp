// The double channel's host side (algray/embree.h): initIntersectContext, makeRayHit and
// fromFloatParameter, which map a double ray (RayD) to the float ray Embree traverses and
// back. The callbacks that read the channel are the bridge's (embree_bridge.cpp).
#include "double_channel.h"
#include "surface_data.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

namespace algray {

namespace {
// Embree's ray.valid() requires |org|, |dir| <= FLT_LARGE (1.8e18) per component, and its
// traversal replaces direction components below 1e-18 by 1e-18 (rcp_safe), so a ray along
// an axis drifts sideways by 1e-18 t: from 1e17 away, enough to pass beside the cells
// the double ray crosses (a torus from 1e17 was missed). A double ray with an origin
// component beyond 2^40 or a direction component beyond 1e17 is therefore handed to
// Embree re-parametrised: the direction scaled to length 2^56 (t_float, and the drift
// with it, stays below ~30) and, for an origin outside the cube |x_i| <= 1.5e18, the
// origin moved along the line to where it enters that cube (never before tnear; a line
// that misses the cube is empty). Every surface lies within 1e18 (checkEmbreeRange,
// surface_geometry.cpp), so no point a ray can hit is skipped. t = shift + (shiftLow + scale *
// t_float). The move is made as the bridge's rebaseFarOrigin's (error-free steps, repeated;
// double_channel.h): one rounded step
// from an origin at 1e150 lands anywhere within 1e134 of the cube's face along the line, also past
// the scene.
// Embree's traversal also replaces every direction component below 1e-18 in magnitude by
// +1e-18 (rcp_safe: the sign is lost), so a ray whose whole direction is that small (a
// scene at the scale of 1e-20) would pass beside the boxes it crosses. Such a direction
// is scaled by a power of two to a largest component in [1, 2): t = scale * t_float,
// exact both ways.
struct FloatMap {
  double shift = 0, shiftLow = 0, scale = 1;
  glm::dvec3 origin{0.0};  // o + (shift + shiftLow) d, when shift != 0
  bool empty = false;
};

// The box a far origin is moved to: the cube, or with the host's scene (its bounds,
// rtcGetSceneBounds) that box widened by its own extent: then the float proxy starts a
// scene's size before the scene instead of 1.5e18 away, and float resolves the scene as
// well as it resolves the scene itself (from the cube, or from a camera 1e9 scene sizes
// away, float's rounding of the proxy's origin, u_float |o|, was larger than small cells:
// the traversal visited other cells than the double ray crosses, and 90 % of a torus's
// hits in cells of depth 3 were lost from 1e9 radii; from 1e6, some rays got a later root).
struct MoveBox {
  glm::dvec3 lo{0.0}, hi{0.0};
};

MoveBox moveBox(const RTCBounds* bounds) {
  constexpr double kCube = 1.5e18;
  static_assert(kCube > kEmbreeReach && kCube < 1.8e18);
  MoveBox box{glm::dvec3(-kCube), glm::dvec3(kCube)};
  if (!bounds) return box;
  const glm::dvec3 lo(bounds->lower_x, bounds->lower_y, bounds->lower_z);
  const glm::dvec3 hi(bounds->upper_x, bounds->upper_y, bounds->upper_z);
  if (!finite(lo) || !finite(hi) || !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z))
    return box;  // empty scene
  const glm::dvec3 pad =
      glm::max(hi - lo, glm::dvec3(0x1p-20 * std::max(glm::length(lo), glm::length(hi))));
  box.lo = glm::max(lo - pad, glm::dvec3(-kCube));
  box.hi = glm::min(hi + pad, glm::dvec3(kCube));
  return box;
}

// Whether o lies farther than 2^12 times the scene's largest extent outside its bounds:
// then float's rounding of the proxy's origin is over 2^-12 of the scene; nearer, the
// float ray is the ray itself. (From the raw bounds: the padded box of moveBox is built
// only for far rays.)
bool farFromScene(const glm::dvec3& o, const RTCBounds* b) {
  constexpr double kSceneFar = 0x1p12;
  const double extent =
      std::max({b->upper_x - b->lower_x, b->upper_y - b->lower_y, b->upper_z - b->lower_z});
  if (!(extent >= 0.0)) return false;  // empty scene (or NaN bounds)
  const double reach = kSceneFar * extent;
  return o.x < b->lower_x - reach || o.x > b->upper_x + reach || o.y < b->lower_y - reach ||
         o.y > b->upper_y + reach || o.z < b->lower_z - reach || o.z > b->upper_z + reach;
}

FloatMap floatMap(const RayD& r, const RTCBounds* bounds) {
  constexpr double kFar = 0x1p40, kBig = 1e17, kTiny = 0x1p-20, kLength = 0x1p56;
  static_assert(kLength < kBig);
  FloatMap m;
  bool big = false;
  for (int i = 0; i < 3; ++i) big = big || std::abs(r.org[i]) > kFar || std::abs(r.dir[i]) > kBig;
  const bool far = bounds && farFromScene(r.org, bounds);
  // A negative tnear asks for hits before the origin, but Embree takes tnear >= 0 only:
  // the float proxy starts at tnear instead (or, for -inf or a start outside the box,
  // where the line enters it from behind), so that Embree visits the cells behind the
  // origin too. With the float tnear clamped to 0 a first hit behind the origin in
  // another cell was lost (a torus in 256 cells, tnear = -3 radii: 15 of 500 rays).
  const bool behind = r.tnear < 0.0;
  const double md = std::max({std::abs(r.dir.x), std::abs(r.dir.y), std::abs(r.dir.z)});
  if (!big && !far && !behind) {
    // A large direction the same way: t = distance / |d| of a hit in a small scene fell
    // below float's range (0 in flush-to-zero threads): rays from a sphere's centre with
    // |d| = 1e10 missed a sphere of radius 1e-30 in the float channel.
    if (md > 0.0 && (md < kTiny || md > 1.0 / kTiny)) m.scale = std::ldexp(1.0, -std::ilogb(md));
    return m;
  }
  // The moves are measured and made along dirN = 2^-e d (its largest component in [1, 2):
  // the same line, exactly) in its parameter tN = 2^e t. |d| itself overflows for
  // components near 1e308 on two or three axes (such rays were refused as having no
  // length, and missed in both channels); arc lengths (along d / |d|) overflowed from
  // origins near 1e308 (a miss in the float channel); and t itself is near 1e-308 where
  // |d| is near 1e308: subnormal, and 0 in Embree's and TBB's flush-to-zero threads (the
  // proxy stopped at the sphere's centre and hit the exit). On dirN's largest axis the
  // entry (box - p) / dirN cannot overflow; an overflow on another axis is an entry beyond
  // that axis's exit, a miss.
  const int e = md > 0.0 && std::isfinite(md) ? std::ilogb(md) : 0;
  const glm::dvec3 dirN(std::ldexp(r.dir.x, -e), std::ldexp(r.dir.y, -e), std::ldexp(r.dir.z, -e));
  const double lenN = safeLength(dirN);
  // Component by component: the sum of finite components overflows from about 0.6e308
  // (an origin at (-1e308, -1e308, -1e308) was refused as non-finite, its ray missed).
  if (!(lenN > 0.0 && std::isfinite(lenN)) || !finite(r.org)) {
    m.empty = true;
    return m;
  }
  m.scale = std::ldexp(kLength / lenN, -e);  // kLength / |d|, exactly as scaled
  const MoveBox box = moveBox(far || behind ? bounds : nullptr);
  glm::dvec3 p = r.org;
  const double size = std::max({box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z});
  for (int move = 0; move < kMaxMoves; ++move) {
    // Parameters tN from p: the part of the line inside the box, from tnear on.
    double a = std::ldexp((r.tnear - m.shift) - m.shiftLow, e),
           b = std::numeric_limits<double>::infinity();
    // An origin inside the box stays (unless tnear > 0, or < 0: behind).
    if (move == 0 && !behind) a = std::max(a, 0.0);
    for (int i = 0; i < 3; ++i) {
      if (dirN[i] == 0.0) {
        if (p[i] < box.lo[i] || p[i] > box.hi[i]) m.empty = true;
        continue;
      }
      double s0 = (box.lo[i] - p[i]) / dirN[i], s1 = (box.hi[i] - p[i]) / dirN[i];
      if (s0 > s1) std::swap(s0, s1);
      a = std::max(a, s0);
      b = std::min(b, s1);
    }
    if (m.empty) return m;
    // Far away each s above carries the rounding of |p| / |dirN_i|, more than the box's
    // width from |p| ~ 2^50 box sizes on: the per-axis entries and exits of a line through
    // the box then round to disagreeing numbers (a > b), and the ray was refused although
    // it crosses the box (random directions through a sphere from 2^66 radii: 14-57 %
    // missed). Within that rounding the crossing is undecided here: move to the nearer end
    // and decide from there, where the numbers are 16 digits smaller.
    if (!(a <= b) && !(a - b <= 0x1p-46 * std::max(std::abs(a), std::abs(b)))) {
      m.empty = true;
      return m;
    }
    a = std::min(a, b);
    if (!std::isfinite(a)) {
      m.empty = true;
      return m;
    }
    // Within 2^-30 of the box's size of the entry (float's rounding of the origin is
    // 2^-24 of it), inside float's range and before every surface. (Back to tnear < 0
    // the first move goes however short: the proxy must not start after tnear.)
    if (!(std::abs(a) * lenN > 0x1p-30 * size) && !(behind && move == 0 && a < 0.0)) break;
    const glm::dvec3 next = pointOnLine(p, dirN, a);
    if (next == p) break;
    p = next;
    addExact(m.shift, m.shiftLow, std::ldexp(a, -e));
  }
  m.origin = p;
  return m;
}

RTCBounds sceneBounds(RTCScene scene) {
  RTCBounds b{};
  rtcGetSceneBounds(scene, &b);
  return b;
}
}  // namespace

namespace {
// A trace id unique in the process: a context may be initialised on one thread and traced
// on another, whose per-thread root records hold ids of its own (with a counter per
// thread, two contexts of one ray made on two threads had the same id, and the second
// trace skipped the roots the first had offered: a far ray through a grid edge missed).
// Each thread takes blocks of 2^20 ids from a global counter, so a trace touches no
// shared cache line.
std::uint64_t nextTraceId() {
  constexpr std::uint64_t kBlock = std::uint64_t{1} << 20;
  static std::atomic<std::uint64_t> nextBlock{1};
  thread_local std::uint64_t next = 0, end = 0;
  if (next == end) {
    next = nextBlock.fetch_add(1, std::memory_order_relaxed) * kBlock;
    end = next + kBlock;
  }
  return next++;
}

void initContext(IntersectContext* context, const RayD* ray, HitD* hit, const RTCBounds* bounds) {
  rtcInitIntersectContext(&context->base);
  context->base.filter = &markerFilter;
  context->ray = ray;
  context->hit = hit;
  context->hostFilter = nullptr;
  const FloatMap m = ray ? floatMap(*ray, bounds) : FloatMap{};
  context->trace = nextTraceId();
  context->floatShift = m.shift;
  context->floatShiftLow = m.shiftLow;
  context->floatScale = m.scale;
  context->floatOrigin = m.origin;
  context->floatEmpty = m.empty;
  if (hit) *hit = HitD{};
}

RTCRayHit floatRayHit(const RayD& r, const FloatMap& m);
}  // namespace

void initIntersectContext(IntersectContext* context, const RayD* ray, HitD* hit) {
  initContext(context, ray, hit, nullptr);
}
void initIntersectContext(IntersectContext* context, const RayD* ray, HitD* hit, RTCScene scene) {
  const RTCBounds b = sceneBounds(scene);
  initContext(context, ray, hit, &b);
}

namespace {
// shift + (shiftLow + scale tFloat); a result below double's normal range (see
// hostParameter) again in long double, rounded once.
double fromFloatParts(double shift, double shiftLow, double scale, double tFloat) {
  const double t = shift + (shiftLow + scale * tFloat);
  if (std::abs(t) >= std::numeric_limits<double>::min() || tFloat == 0.0) return t;
  return static_cast<double>(shift + (shiftLow + static_cast<long double>(scale) * tFloat));
}
double fromFloat(const FloatMap& m, double tFloat) {
  return fromFloatParts(m.shift, m.shiftLow, m.scale, tFloat);
}
}  // namespace

double fromFloatParameter(const RayD& ray, double tFloat) {
  return fromFloat(floatMap(ray, nullptr), tFloat);
}
double fromFloatParameter(const RayD& ray, double tFloat, RTCScene scene) {
  const RTCBounds b = sceneBounds(scene);
  return fromFloat(floatMap(ray, &b), tFloat);
}

double fromFloatParameter(const IntersectContext& context, double tFloat) {
  return fromFloatParts(context.floatShift, context.floatShiftLow, context.floatScale, tFloat);
}

RTCRayHit makeRayHit(const RayD& r) { return floatRayHit(r, floatMap(r, nullptr)); }
RTCRayHit makeRayHit(const RayD& r, RTCScene scene) {
  const RTCBounds b = sceneBounds(scene);
  return floatRayHit(r, floatMap(r, &b));
}
RTCRayHit makeRayHit(const IntersectContext& context) {
  FloatMap m;
  m.shift = context.floatShift;
  m.shiftLow = context.floatShiftLow;
  m.scale = context.floatScale;
  m.origin = context.floatOrigin;
  m.empty = context.floatEmpty;
  return context.ray ? floatRayHit(*context.ray, m) : floatRayHit(RayD{}, FloatMap{});
}

namespace {
RTCRayHit floatRayHit(const RayD& r, const FloatMap& m) {
  constexpr float kInfF = std::numeric_limits<float>::infinity();
  RTCRayHit rh{};
  const glm::dvec3 o = m.shift == 0.0 ? r.org : m.origin;
  const glm::dvec3 d = m.scale == 1.0 ? r.dir : r.dir * m.scale;
  rh.ray.org_x = static_cast<float>(o.x);
  rh.ray.org_y = static_cast<float>(o.y);
  rh.ray.org_z = static_cast<float>(o.z);
  rh.ray.dir_x = static_cast<float>(d.x);
  rh.ray.dir_y = static_cast<float>(d.y);
  rh.ray.dir_z = static_cast<float>(d.z);
  const double tnear = ((r.tnear - m.shift) - m.shiftLow) / m.scale,
               tfar = ((r.tfar - m.shift) - m.shiftLow) / m.scale;
  float tn = static_cast<float>(tnear);
  if (static_cast<double>(tn) > tnear) tn = std::nextafter(tn, -kInfF);
  rh.ray.tnear = std::max(tn, 0.0f);  // Embree requires tnear >= 0
  rh.ray.tfar = roundUp(tfar);
  rh.ray.mask = ~0u;
  rh.ray.time = 0.0f;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
    rh.hit.instID[l] = RTC_INVALID_GEOMETRY_ID;
  // Embree 3 rejects (asserts on) non-finite or huge origins and directions and NaN spans:
  // such a ray (non-finite, or a far line that misses the cube of floatMap, where no
  // surface lies) becomes a valid one with an empty span, which hits nothing. Embree's
  // ray.valid() requires |org|, |dir| <= FLT_LARGE (1.8e18) per component.
  constexpr float kLarge = 1.8e18f;
  auto ok = [](float v) { return std::abs(v) <= kLarge; };
  const bool finiteRay = ok(rh.ray.org_x) && ok(rh.ray.org_y) && ok(rh.ray.org_z) &&
                         ok(rh.ray.dir_x) && ok(rh.ray.dir_y) && ok(rh.ray.dir_z) &&
                         !std::isnan(rh.ray.tnear) && !std::isnan(rh.ray.tfar);
  if (!finiteRay || m.empty) {
    rh.ray.org_x = rh.ray.org_y = rh.ray.org_z = 0.0f;
    rh.ray.dir_x = rh.ray.dir_y = 0.0f;
    rh.ray.dir_z = 1.0f;
    rh.ray.tnear = 1.0f;
    rh.ray.tfar = 0.0f;
  }
  return rh;
}
}  // namespace

}  // namespace algray
