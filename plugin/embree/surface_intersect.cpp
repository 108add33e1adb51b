// The kernel of the adapter: one ray, one cell, the roots of f along the ray in order.
// No Embree types here (the bridge converts), so an Embree 4 port reuses it unchanged.
//
// The way of one ray (see ../shared/DESIGN.md):
//   1. clip the ray to the clip region and the cell: span (lo, hi);
//   2. restrict f to the ray, g(s) = f(o + (tShift + s) d) with a rounding bound, once per
//      ray for the whole clip region, shared by the cells the ray visits, with its first
//      root settled on f (ray_roots.h: ray_roots.cpp, self_root.cpp and ray_settle.cpp);
//   3. the roots in the cell's span that the cell owns, in order, offered to the host
//      filter until one is accepted (all of them only when a cell beyond the first root or
//      a host filter needs them);
//   4. Newton polish on f itself and the gradient at the hit point.
#include "ray_roots.h"
#include "surface_data.h"
#include "thread_heap.h"

#include "algray/taylor.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace algray {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Offered roots (double channel) ------------------------------------------------------
// Per surface, ray and trace: the roots (bit i: roots[i] of the ray's record, the same
// list whenever it is rebuilt) offered to the host, and those offered by a shared claim
// (walkRoots). Kept apart from the record, which the cells of other surfaces replace in
// the same trace: masks kept in it were rebuilt empty on each visit back, and a plane's
// orphan root reached an any-hit filter up to 4 times in a scene of three planes. (They
// must never hide another surface's or ray's roots: the key.) One trace has one ray, so an
// entry of another trace or another ray is done with (but for a trace a host filter
// interrupted with rays of its own): a new entry replaces the oldest such one. Where every
// entry is this trace's and ray's (a trace meeting that many surfaces with roots) the table
// grows, up to 4096 entries, beyond which an evicted entry only lets a root be offered again,
// never hides one; the first new trace after that shrinks it back. (With 16 entries and
// round-robin eviction a ray through 17 planes in grids of cells saw a plane's root twice on
// 25 of 96 traces; grown for every new ray of a context the host reused, the table's search
// made later rays up to 45 times slower.)
struct OfferedRoots {
  std::uint64_t id = 0, trace = 0;
  glm::dvec3 org{0.0}, dir{0.0};
  double tnear = 0;
  std::uint64_t offered = 0, shared = 0;
};
// The cell that offered root i (bit i of offered), per entry: apart from the entries, so that
// a new ray's search through them touches only the keys (16 entries in 1.4 KB).
using OfferedBy = std::array<unsigned, 64>;
constexpr size_t kOfferedEntries = 16, kMaxOfferedEntries = 4096;
struct OfferedTable {
  std::vector<OfferedRoots> entries = std::vector<OfferedRoots>(kOfferedEntries);
  std::vector<OfferedBy> offeredBy = std::vector<OfferedBy>(kOfferedEntries);
  size_t next = 0;
  size_t last = 0;  // the entry found last: a ray's roots ask for the same one in a row
};

// An entry of the table and its offering cells, found with one look-up (the cells were
// looked up again through the thread's table for every root offered).
struct OfferedSlot {
  OfferedRoots& roots;
  OfferedBy& offeredBy;
};

OfferedSlot offeredRoots(const SurfaceData& data, const KernelRay& ray) {
  OfferedTable& table = ThreadHeap<OfferedTable>::get();
  auto slot = [&](size_t i) { return OfferedSlot{table.entries[i], table.offeredBy[i]}; };
  auto sameTrace = [&](const OfferedRoots& e) {
    return e.trace == ray.trace && e.org == ray.org && e.dir == ray.dir && e.tnear == ray.tnear;
  };
  std::vector<OfferedRoots>& entries = table.entries;
  if (entries[table.last].id == data.id && sameTrace(entries[table.last])) return slot(table.last);
  bool traceSeen = false;
  for (size_t i = 0; i < entries.size(); ++i) {
    if (entries[i].trace != ray.trace) continue;
    traceSeen = true;
    if (entries[i].id == data.id && sameTrace(entries[i])) {
      table.last = i;
      return slot(i);
    }
  }
  if (!traceSeen && entries.size() > kOfferedEntries) {  // a new trace after a large one
    entries.resize(kOfferedEntries);
    table.offeredBy.resize(kOfferedEntries);
  }
  const size_t n = entries.size();
  table.last = table.next % n;
  bool found = false;
  for (size_t k = 0; k < n && !found; ++k)
    if (!sameTrace(entries[(table.next + k) % n])) {
      table.last = (table.next + k) % n;
      found = true;
    }
  if (!found && n < kMaxOfferedEntries) {
    entries.resize(2 * n);
    table.offeredBy.resize(2 * n);
    table.last = n;
  }
  table.next = table.last + 1;
  OfferedRoots& e = entries[table.last];
  e.id = data.id;
  e.trace = ray.trace;
  e.org = ray.org;
  e.dir = ray.dir;
  e.tnear = ray.tnear;
  e.offered = e.shared = 0;
  return slot(table.last);
}

// ---- Cell ownership ------------------------------------------------------------------------
// Cells are closed boxes rounded outward, so neighbours overlap and a root near a shared
// face lies in several. The host filter must see each root once (an any-hit filter
// accumulating transparency would count it twice), so exactly one cell owns it: the one
// whose nominal grid box contains the root point (half-open, computed from the same root
// value in every cell). A root whose grid box holds no cell (possible only by rounding
// at a face) is owned by every cell that reaches it: a duplicate rather than a loss.
// With the double channel Embree traverses with the float ray, which for a far origin can
// pass beside the owner cell's (padded) box: the owner then never sees the root. So the
// owner keeps a root only if the float ray surely crosses its padded box (shrunk by the
// rounding of Embree's float slab test); otherwise every cell that reaches the root takes
// it (a duplicate in that rare band rather than a loss).
bool surelyReached(const RTCBounds& b, const glm::dvec3& o, const glm::dvec3& d) {
  const glm::dvec3 lo(b.lower_x, b.lower_y, b.lower_z), hi(b.upper_x, b.upper_y, b.upper_z);
  // Embree's own float slab test is off by about u_float (|o| + |box|): beyond the margin.
  const double slack =
      16.0 * 0x1p-24 * (glm::length(o) + glm::length(glm::max(glm::abs(lo), glm::abs(hi))));
  const glm::dvec3 margin(slack);
  double t0 = 0.0, t1 = kInf;
  return clipToBox(lo + margin, hi - margin, o, d, t0, t1) && t0 < t1;
}

// How a cell takes a root: not at all, as its one owner (Embree visits a primitive once
// per trace), or shared with other cells that may take it in the same trace too.
enum class Claim { kNone, kOwner, kShared };

// Whether `cell` takes the root at p. inSpan: p is in the cell's span of the ray. The
// owner takes it wherever the span ends (walkRoots offers it roots just outside the span,
// which rounding puts there). Another cell takes a root outside its span only in the
// double channel, as an orphan: its owner cell is not surely reached by the float ray
// Embree traverses with (origins ~1e6 clip radii away), so the first cell Embree does
// visit reports it. A root whose grid box holds no cell is shared by the cells whose span
// holds it.
Claim claimsRoot(const SurfaceData& data, unsigned cell, const glm::dvec3& p, const KernelRay& ray,
                 bool inSpan) {
  if (data.cells.size() == 1 || data.cellOfKey.empty())
    return inSpan ? Claim::kOwner : Claim::kNone;
  long k[3];
  for (int a = 0; a < 3; ++a) {
    const double x = (p[a] - data.gridLo[a]) / data.gridSize[a] * data.gridN[a];
    k[a] = std::clamp(static_cast<long>(std::floor(x)), 0L, static_cast<long>(data.gridN[a] - 1));
  }
  auto keyOf = [&] { return (static_cast<std::uint64_t>(k[0]) * 65536u + k[1]) * 65536u + k[2]; };
  auto it = data.cellOfKey.find(keyOf());
  // The key rounds: p - gridLo can carry p across a face (x = -1e-20 beside the face x = 0
  // of the box -2..2 got the key of the cell above it), whose span (its own box) does not
  // hold p: a ray parallel to that face on the other side was claimed by no cell, and one
  // from (-1e-20, -5, 0) along +y missed the unit sphere. The cell's own box decides.
  if (it != data.cellOfKey.end()) {
    const SurfaceCell& c = data.cells[it->second];
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      if (p[a] < c.lo[a] && k[a] > 0)
        --k[a], moved = true;
      else if (p[a] > c.hi[a] && k[a] + 1 < static_cast<long>(data.gridN[a]))
        ++k[a], moved = true;
    }
    if (moved) it = data.cellOfKey.find(keyOf());
  }
  if (it == data.cellOfKey.end()) return inSpan ? Claim::kShared : Claim::kNone;
  if (it->second == cell) return Claim::kOwner;  // Embree reached the owner: wherever its span ends
  const bool orphan = ray.hasTraversalRay &&
                      !surelyReached(data.cells[it->second].bounds, ray.travOrg, ray.travDir);
  return orphan ? Claim::kShared : Claim::kNone;
}

}  // namespace

void surfaceUV(const SurfaceData& data, const glm::dvec3& point, double& u, double& v) {
  constexpr double kPi = 3.14159265358979323846;
  const glm::dvec3 r = point - data.centre;
  if (!(std::abs(r.x) + std::abs(r.y) + std::abs(r.z) > 0.0)) {  // the centre, or NaN
    u = v = 0.0;
    return;
  }
  double phi = std::atan2(r.y, r.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  u = std::min(phi / (2.0 * kPi), std::nextafter(1.0, 0.0));
  // The polar angle as atan2(rho, z): acos(z / |r|) loses half the digits near the poles
  // (tests: FloatUvAreTheDoubleOnesToAnUlp).
  v = std::atan2(std::hypot(r.x, r.y), r.z) / kPi;
}

namespace {
// atan(t) for t in [0, 1], from t and t^2, for the float u, v: t p(t^2), p of degree 9
// (least squares at 4000 Chebyshev points of atan(t) / t in t^2, fitted for this file;
// measured max error 9.8e-10 rad over 2e7 random atan2 calls, i.e. 1.6e-10 in u, v
// against float's 6e-8 at 1). Estrin's scheme keeps the dependency chain short (glibc's
// atan2 and acos were 11 % of a quadric primary ray; perf, speed_report's sphere).
double atanUnit(double t, double t2) {
  const auto& c = kAtanPoly;
  const double t4 = t2 * t2, t8 = t4 * t4;
  const double p01 = c[0] + c[1] * t2, p23 = c[2] + c[3] * t2, p45 = c[4] + c[5] * t2,
               p67 = c[6] + c[7] * t2, p89 = c[8] + c[9] * t2;
  return ((p01 + p23 * t4) + ((p45 + p67 * t4) + p89 * t8) * t8) * t;
}
}  // namespace

void surfaceUVFloat(const SurfaceData& data, const glm::dvec3& point, float& u, float& v) {
  constexpr double kPi = 3.14159265358979323846;
  const glm::dvec3 r = point - data.centre;
  const double rho2 = r.x * r.x + r.y * r.y, z2 = r.z * r.z;
  if (!(rho2 + z2 > 0.0) || !std::isfinite(rho2 + z2)) {
    double ud, vd;
    surfaceUV(data, point, ud, vd);
    u = floatU(ud);
    v = static_cast<float>(vd);
    return;
  }
  // The azimuth atan2(y, x) from the octant of |x|, |y| (on the z axis, rho = 0, it is
  // atan2(+-0, x) as for surfaceUV).
  double phi;
  if (rho2 > 0.0) {
    const double ax = std::abs(r.x), ay = std::abs(r.y), t = std::min(ax, ay) / std::max(ax, ay);
    phi = atanUnit(t, t * t);
    if (ay > ax) phi = kPi / 2 - phi;
    if (std::signbit(r.x)) phi = kPi - phi;
    phi = std::copysign(phi, r.y);
  } else {
    phi = std::atan2(r.y, r.x);
  }
  if (phi < 0.0) phi += 2.0 * kPi;
  // The polar angle atan2(rho, z) (acos(z / |r|) without its clamp, and as accurate),
  // from the squares: t^2 = min / max of rho^2, z^2 and its root t side by side, so that
  // no root delays the division (a hit's last latency chain; measured).
  const double t2 = std::min(rho2, z2) / std::max(rho2, z2), t = std::sqrt(t2);
  double theta = atanUnit(t, t2);
  if (rho2 > z2) theta = kPi / 2 - theta;
  if (std::signbit(r.z)) theta = kPi - theta;
  // Products with the rounded 1 / (2 pi) and 1 / pi (one more rounding, far below
  // float's; the quotients' latency came last on a hit's critical path, measured).
  u = floatU(std::min(phi * kInvTwoPi, std::nextafter(1.0, 0.0)));
  v = static_cast<float>(std::min(std::max(theta * kInvPi, 0.0), 1.0));
}

namespace {

// ---- Directions far from the clip radius in length -----------------------------------------
// The restriction's coefficient of s^r scales as |d|^r: with |d| = 2^-k R (R the clip
// radius) the top ones of a degree-m f shrink by 2^-km relative to the others and leave
// double's range from k m ~ 1000 (a direction of length 1e-20 on Chmutov-16: 1e-320, a
// flushed or 10-bit subnormal; missed and spurious hits on 8 % of random rays, both
// channels; long directions overflow alike). When k m exceeds 256 the walk takes the ray
// with its direction scaled by a power of two to a largest component in [R, 2R) and t
// inversely, both exact, and reports each root's t scaled back (exact but for underflow
// or overflow of t itself). (The double channel's bridge rescales lengths beyond 2^+-100
// for the clip's dot products; this one is relative to R and to the degree.)
constexpr int kDirectionExponentBudget = 256;

// The e with max|d_i| 2^-e in [R, 2R) when the walk must rescale d, else 0.
int directionRescale(const SurfaceData& data, const glm::dvec3& d) {
  const double md = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  // The biased exponents, from the bits (no libm call on every ray); md = 0, inf or NaN
  // is walkRoots' own business.
  const auto field = [](double x) {
    return static_cast<int>(std::bit_cast<std::uint64_t>(x) >> 52);
  };
  if (!(md > 0.0) || !std::isfinite(md)) return 0;
  const int k = std::abs(field(md) - field(data.radius));
  if (k * std::max(data.horner.degree(), 1) <= kDirectionExponentBudget) [[likely]]
    return 0;
  return std::ilogb(md) - std::ilogb(data.radius);  // exact for subnormal md too
}

struct RescaledAccept {
  AcceptFn accept;
  void* user;
  int exp;  // host t = 2^exp kernel t
};
bool acceptRescaled(void* user, const KernelHit& hit) {
  const auto& r = *static_cast<const RescaledAccept*>(user);
  KernelHit h = hit;
  h.t = std::ldexp(hit.t, r.exp);
  return r.accept(r.user, h);
}

bool walkRootsOf(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
                 AcceptFn accept, void* user);

}  // namespace

bool walkRoots(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
               AcceptFn accept, void* user) {
  const int e = directionRescale(data, ray.dir);
  if (e == 0) [[likely]]
    return walkRootsOf(data, cell, ray, occlusion, accept, user);
  KernelRay scaled = ray;
  scaled.dir =
      glm::dvec3(std::ldexp(ray.dir.x, -e), std::ldexp(ray.dir.y, -e), std::ldexp(ray.dir.z, -e));
  scaled.tnear = std::ldexp(ray.tnear, e);
  scaled.tfar = std::ldexp(ray.tfar, e);
  RescaledAccept rescaled{accept, user, -e};
  return walkRootsOf(data, cell, scaled, occlusion, &acceptRescaled, &rescaled);
}

namespace {

// Whether tnear or tfar lies within the reach of g's noise about its root s (as in
// occlusionRootCertain, which checks the first root): the walk takes a later root's side
// of the ends from g, and where an end lies within that reach both queries first polish
// it on f up to the region's end, so that they put it where f has it. A host stepping past
// a hit (tnear = its t) and asking whether the next root lies before t (1 + 1e-12) was
// told no on 0.1-0.5 % of the steps through the Chmutov and Sarti surfaces (the next root's
// g, expanded about a point near tnear, placed it up to 1e-8 late); the closest hit, whose
// own polish comes after those tests, lost a later root with tfar just past it (t (1 +
// 1e-12) to t (1 + 1e-9): 18 of 4,462 second roots of the gallery's leaving double rays;
// the review of session 48).
[[gnu::noinline]] bool endWithinReach(const RayRoots& rr, double s, const KernelRay& ray) {
  const double t = rr.g.tShift + s;
  const double h = noiseReach(rr, s, std::abs(s) + std::abs(t)) + floatEndReach(ray, t);
  return !(std::abs(ray.tfar - t) > h && std::abs(t - ray.tnear) > h);  // a NaN reach: polish
}

// The root at t polished on f as the closest hit polishes it: the cell's span and claim
// then decide on the value the hit reports, which is this one (polished once: a second
// polish from its rounded value moved a grazing or ill-conditioned root by ulps up to
// 76,000 of them, so that re-asking with tfar just past the hit lost it; the second review
// of session 48). Up to the region's end, not tfar: f's root may lie past tfar, where a
// polish held to tfar would stop short of it, inside.
[[gnu::noinline, gnu::cold]] KernelHit polishedRoot(const SurfaceData& data, const KernelRay& ray,
                                                    double t, double r0, double r1) {
  KernelHit hit;
  hit.t = t;
  hit.point = ray.org + t * ray.dir;
  polish(data.horner, ray.org, ray.dir, std::max(r0, ray.tnear), r1, r1 - r0, hit);
  return hit;
}

// clipRegionSpan, and closest: closestParameter(o, d, 0) for restrictRecentred when the
// clip region is a sphere centred on the object-space origin (the gallery's), else NaN.
// clipToSphere's tc is that value bit for bit: with the centre 0, o - 0 = o, and
// dot(0 - o, d) is -dot(o, d) exactly but for the sign of a zero sum (0 - o_i is +0 where
// -o_i is -0), so a zero tc is left to closestParameter. It lies in [t0, t1] =
// [tc - dt, tc + dt] (dt >= 0 or NaN, and t0, t1 start unbounded), where the clamp of
// restrictRecentred keeps it.
inline bool regionSpan(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d,
                       double& t0, double& t1, double& closest) {
  closest = std::numeric_limits<double>::quiet_NaN();
  const auto* s = std::get_if<ClipSphere>(&data.desc.clip);
  if (!s) return clipRegionSpan(data, o, d, t0, t1);
  t0 = -kInf;
  t1 = kInf;
  double tc;
  if (!clipToSphere(*s, o, d, t0, t1, tc)) return false;
  if (tc != 0.0 && s->center == glm::dvec3(0.0)) closest = tc;
  return true;
}

bool walkRootsOf(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
                 AcceptFn accept, void* user) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  // ---- Input: non-finite or degenerate rays have no hit (and must not hang) ----------
  // (A deferred orgError, the bridge's, is >= 0 or NaN, and its floatOriginError >= 0
  // for a finite origin: the whole bound passes this test exactly when it does.)
  if (!finite(o) || !finite(d) || std::isnan(ray.tnear) || std::isnan(ray.tfar) ||
      !(ray.orgError >= 0.0))
    return false;
  if (!(glm::dot(d, d) > 0.0) || !(ray.tnear < ray.tfar)) return false;

  // ---- 1. Span: clip region, then the cell (closed, widened for rounding) -------------
  // (closest: the re-centring point from the clip sphere's chord, regionSpan; measured,
  // speed_report one thread, interleaved: Barth sextic primary 2.83 -> 2.85 Mrays/s,
  // Sarti dodecic 0.941 -> 0.952.)
  double r0, r1, closest;
  if (!regionSpan(data, o, d, r0, r1, closest)) return false;
  const SurfaceCell& box = data.cells[cell];
  double c0 = r0, c1 = r1;
  if (!clipToBox(box.lo, box.hi, o, d, c0, c1, true)) return false;
  const double lo = std::max(c0, ray.tnear), hi = std::min(c1, ray.tfar);
  if (!(lo < hi)) return false;

  // ---- 2. Restriction and roots (shared by all cells the ray visits) -------------------
  // The per-thread record (ray_roots.h); occlusion settles a first root on f here where
  // g cannot place it on one side of tnear and tfar (occlusionRootCertain).
  RayRoots* record = &rayRoots(data, ray, r0, r1, closest, occlusion);
  if (occlusion && firstUnsettled(data, *record) && !occlusionRootCertain(*record, ray))
      [[unlikely]]
    settleAfterTnear(data, ray, *record);

  // ---- 3. The cell's roots in order, offered to the host filter -------------------------
  // A root belongs to the cell whose grid box holds its point (claimsRoot), which the
  // span decides only up to rounding: the span is widened by the rounding of its own slab
  // test, relative to t at the face, while the root carries the rounding of the
  // re-centred restriction, relative to tShift, which can lie far beyond a face near the
  // origin (a ray crossing the plane x = 0 on a cell face was claimed by no cell). So
  // roots within `window` of the span go to claimsRoot as well.
  const HornerForm& f = data.horner;
  for (int i = 0;; ++i) {
    RayRoots& rr = *record;
    const double window = 0x1p-20 * (std::abs(rr.g.tShift) + std::abs(lo) + std::abs(hi));
    if (i >= rr.count) {
      if (rr.complete || !(rr.roots[rr.count - 1] < hi + window - rr.g.tShift)) break;
      completeRoots(data, rr);  // the next cells of this ray find the full list here
      if (i >= rr.count) break;
    }
    const RayPolynomial& g = rr.g;
    const double slo = lo - g.tShift, shi = hi - g.tShift;
    double s = rr.roots[i];
    KernelHit polished;
    const bool prepolished = i > 0 && !data.quadric && endWithinReach(rr, s, ray);
    if (prepolished) [[unlikely]] {
      polished = polishedRoot(data, ray, g.tShift + s, r0, r1);
      s = polished.t - g.tShift;
    }
    // Behind an origin on the surface (tnear < 0): the search span kept the window, whose
    // roots are the origin's own (searchSpan).
    if (rr.selfWindow > 0.0 && std::abs(s) <= rr.selfWindow) continue;
    if (rr.originWindow > 0.0 && std::abs(g.tShift + s) <= rr.originWindow) [[unlikely]]
      continue;
    // The solver reports a root within noise of an end of the region's span at that end
    // (roots.h; the start is closed, regionRoots): nothing beyond the region could report
    // it, so it counts there, inside (tnear, tfar) (a triple factor seen through a
    // degree-16 product was within noise over the last 1 % of a ray's span: the root came
    // back as r1 and was dropped).
    // A root that ties tnear or tfar in s is decided in t: s = t - tShift keeps only
    // |tShift|'s ulps, which put a root one double before tfar on tfar's side where |tShift|
    // >> |t| (an origin inside the clip region, tShift the point nearest its centre: 213 of
    // 1,033 gallery hits from 0.3 radii lost at tfar = nextafter(t); the third review of
    // session 48). The polished root's own t where it has one (tShift + (t - tShift) can
    // round back onto tfar).
    const bool rebased = i == 0 && rr.firstRebased;  // completeRoots: report the cache's t
    const double tRoot = prepolished ? polished.t : rebased ? rr.firstT : g.tShift + s;
    const bool inSpan = (s > slo || (s == rr.slo && lo == r0 && r0 > ray.tnear) ||
                         (s == slo && lo == ray.tnear && tRoot > ray.tnear)) &&
                        (s < shi || (s == rr.shi && hi == r1 && r1 < ray.tfar) ||
                         (s == shi && hi == ray.tfar && tRoot < ray.tfar));
    if (!inSpan && !ray.hasTraversalRay && !(s > slo - window && s < shi + window)) {
      if (s >= shi) break;
      continue;
    }
    KernelHit hit;
    hit.t = rebased ? rr.firstT : g.tShift + s;
    hit.point = o + hit.t * d;
    const Claim claim = claimsRoot(data, cell, hit.point, ray, inSpan);
    if (claim == Claim::kNone) {
      if (s >= shi && !ray.hasTraversalRay) break;
      continue;
    }
    // In the double channel the orphan rule of claimsRoot may let several cells take a
    // root (its owner not surely reached by the float ray): each is offered once per
    // trace (an any-hit filter saw a root on a grid edge 7 times from 100 box radii).
    // The owner, visited once per trace, defers only to a shared claim of this trace: the
    // trace id is the context's, and a host tracing the same ray again with the same
    // context got the next root each time (the owner skipped the roots offered before).
    // A cell meets each root once per trace: one meeting a root it offered itself is in the
    // next trace of a context the host reuses (embree.h allows it), whose marks are the last
    // trace's (a root on a grid edge, offered by a shared claim, was skipped by every cell
    // from the second trace on: 26 of 72 such rays missed).
    const std::uint64_t bit = i < 64 ? std::uint64_t{1} << i : 0;
    if (ray.trace != 0) {
      auto [seen, offeredBy] = offeredRoots(data, ray);
      if ((seen.offered & bit) != 0 && offeredBy[i] == cell) seen.offered = seen.shared = 0;
      if (((claim == Claim::kOwner ? seen.shared : seen.offered) & bit) != 0) continue;
    }
    // Polish within the whole span (a root near a cell face may move across it; the
    // owner was decided on the unpolished value), up to the region's end, not tfar, as
    // polishedRoot: held to tfar, a polish stopped short of f's root just past it and
    // reported a point before tfar on no surface (the review of session 48: Chmutov-12, a
    // float ray's later root asked with tfar at its float hit; a labs-septic grazing ray's
    // 1.3e-5 early). A cache root was polished already.
    if (prepolished) [[unlikely]]
      hit = polished;
    else if (i == 0 && rr.firstPolished)
      hit.gradient = rr.firstGradient;
    else if (data.quadric)
      hit.gradient = occlusion ? glm::dvec3(0.0) : data.quadric->gradient(hit.point);
    else if (!occlusion)
      polish(f, o, d, std::max(r0, ray.tnear), r1, r1 - r0, hit);
    if (!(hit.t > ray.tnear && hit.t < ray.tfar)) continue;
    if (tnearsOwnRoot(f, ray, hit.t, r0, r1)) [[unlikely]]
      continue;
    if (!occlusion)
      hit.gradient = hitGradient(data, d, hit.point, hit.gradient, hitPointError(o, d, hit.t));
    if (ray.trace != 0) {
      auto [seen, offeredBy] = offeredRoots(data, ray);
      seen.offered |= bit;
      if (bit != 0) offeredBy[i] = cell;
      if (claim == Claim::kShared) seen.shared |= bit;
    }
    if (accept(user, hit)) return true;
    // The host filter may have traced rays of its own on this thread and so replaced the
    // record: re-derived (the same computation gives the same roots).
    record = &rayRoots(data, ray, r0, r1, closest, occlusion);
  }
  return false;
}

}  // namespace

}  // namespace algray
