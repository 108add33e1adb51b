#pragma once
// The public Embree API of algray: an algebraic surface as Embree 3 user geometry.
//
//   algray::SurfaceDesc desc;
//   desc.polynomial = algray::parsePolynomial("x^2 + y^2 + z^2 - 1");
//   desc.clip = algray::ClipSphere{{0, 0, 0}, 1.5};
//   algray::SurfaceGeometry sphere(device, desc);      // builds cells, commits
//   rtcAttachGeometry(scene, sphere.geometry());       // host keeps its filters/masks
//
// The SurfaceGeometry must outlive every scene it is attached to (like a host's shared
// vertex buffers). Its Embree user data pointer is the adapter's (Embree 3 hands the
// callbacks no other): a host must not replace it with rtcSetGeometryUserData (the
// callbacks would read the host's data as theirs), and its filters receive it as
// geometryUserPtr; per-geometry host data is found by geomID instead.
// Hits (written only for tnear < t < tfar, after the host's filters):
//   tfar    the ray parameter of the first accepted root;
//   Ng      grad f at the hit, not normalised, in the space the geometry lives in (scaled
//           by a power of two when its size is outside 1e-30..1e30, so that the float
//           keeps its direction; a polynomial whose largest coefficient is outside
//           2^-64..2^64 is scaled by a power of two to [1, 2) first, in both channels)
//           (desc.transform applied: A^-T grad f_object). Inside an Embree instance this is
//           the instanced scene's space, as for every Embree geometry;
//   u, v    0, 0 (as Embree's own sphere writes them) unless SurfaceOptions::uv asks for
//           spherical coordinates of the object-space hit point about the clip centre,
//           u = azimuth atan2(y, x) / 2pi in [0, 1), v = polar angle acos(z / r) / pi in
//           [0, 1]: a texture parametrisation that is seamless except at u = 0;
//   primID  the cell (Embree primitive) of the hit, geomID/instID from Embree.
// Occlusion writes tfar = -inf at the first accepted root and computes no normal.
// Rays leaving the surface need no epsilon: a root at the ray origin (the origin lies
// on the surface within the rounding of its evaluation and of its own coordinates) is
// removed from the ray polynomial (see plugin/embree/ray_roots.cpp).
//
// Double precision: Embree rays are float. A host that wants double-precision rays and
// hits (algray-query, the accuracy benchmarks) passes an algray::IntersectContext to
// rtcIntersect1/rtcOccluded1; the callbacks then read the double ray and write the double
// hit. A plain RTCIntersectContext works as usual. The context is recognised by its
// filter pointer; Embree 3.13 calls (and asserts the scene flag for) a non-null context
// filter on its own geometry types, so every scene holding triangles, curves, ... that an
// algray::IntersectContext reaches must have RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION set:
// the traced scene and each scene it instances, also one of Embree geometries only (it
// sees the instance's context; without the flag Embree 3.13 aborts on its assertion).
// Scenes of algray surfaces only need not.
#include "algray/parser.h"
#include "algray/polynomial.h"
#include "algray/roots.h"

#include <embree3/rtcore.h>
#include <glm/mat4x4.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <variant>

namespace algray {

struct ClipSphere {
  glm::dvec3 center{0.0};
  double radius = 1.0;
};
struct ClipBox {
  glm::dvec3 lo{-1.0};
  glm::dvec3 hi{1.0};
};
using ClipRegion = std::variant<ClipSphere, ClipBox>;

// Switches kept for measurement (tests/bench): the defaults are the fast, accurate path.
struct SurfaceOptions {
  RootOptions roots;
  bool useCells = true;          // split the clip region into cells the surface may cross
  int cellDepth = -1;            // -1: chosen automatically per surface (cells.h), at most
                                 // 4096 cells (the adapter's cap); 0..30: that depth, within
                                 // cells.h's budget (anything else throws)
  bool originCache = false;      // per-thread expansion about the last ray origin (a camera's
                                 // rays then evaluate its homogeneous parts only); off by
                                 // default since the direct restriction of taylor_box.cpp
                                 // got 2x faster: the gallery's primary rays 0.76x-1.00x
                                 // of their rate without it (docs/speed.md, session 22).
                                 // Built on an origin's second ray in a row: rays sharing
                                 // origins a few at a time (depth-of-field groups) build one
                                 // per group (4 a group: Barth sextic 2.4x, Chmutov-16 7.8x
                                 // the instructions of the default; session 54's audit)
  bool recentre = true;          // expand far rays about their closest point to the clip
  bool quadricPath = true;       // degree 1-2: restriction and normal in closed form (a
                                 // plane 0.63x the instructions of the general path)
  bool quadricCallbacks = true;  // degree 1-2 with one cell: dedicated Embree callbacks
                                 // (no per-ray record, cell walk or generic solver frame)
  bool quadricBounds = true;     // an ellipsoid with one cell: the cell and Embree bounds
                                 // are its own padded box, not the clip region's
  bool packetSimd = true;        // quadric callbacks of 4/8/16-ray packets: the active
                                 // lanes' span, restriction and first root in SIMD
  bool uv = false;               // hit u, v as documented above, for a host that textures
                                 // the surface (algray-render turns it on per material);
                                 // off: u = v = 0 and no arc tangents per hit (15 % of a
                                 // sphere's primary ray, README Speed)
  bool singlePrecision = false;  // float solver for the first root (comparison only; the
                                 // restriction and later roots stay double)
};

struct SurfaceDesc {
  Polynomial polynomial;           // object space
  ClipRegion clip = ClipSphere{};  // object space; set it (surfaces are often unbounded):
                                   // the default is the unit sphere about the origin
  glm::dmat4 transform{1.0};       // object to world, affine
  SurfaceOptions options;
};

// Thrown by SurfaceGeometry when the clip region's size in object space, or that size to
// the polynomial's degree, is beyond what the kernels resolve in double. what() ends with
// the remedy through `transform`; problem() is the finding alone, so that a tool whose
// users set the scale some other way (algray-query has no transform) can name its own.
class ScaleError : public Error {
 public:
  ScaleError(const std::string& problem, const std::string& remedy);
  const std::string& problem() const { return problem_; }

 private:
  std::string problem_;
};

struct SurfaceData;  // the adapter's private state (plugin/embree/)

class SurfaceGeometry {
 public:
  // Throws algray::Error on invalid input (zero or non-finite polynomial, empty or
  // non-finite clip region, singular transform), algray::ScaleError on a clip region too
  // large or small for double (above).
  SurfaceGeometry(RTCDevice device, SurfaceDesc desc);
  // From an equation string (parser.h syntax, e.g. "x^2 + y^2 + z^2 = r^2" with r in
  // parse.parameters): throws algray::ParseError with the column on a malformed equation.
  SurfaceGeometry(RTCDevice device, std::string_view equation, ClipRegion clip,
                  const ParseOptions& parse = {}, const glm::dmat4& transform = glm::dmat4(1.0),
                  const SurfaceOptions& options = {});
  ~SurfaceGeometry();
  SurfaceGeometry(SurfaceGeometry&&) noexcept;
  SurfaceGeometry& operator=(SurfaceGeometry&&) noexcept;
  SurfaceGeometry(const SurfaceGeometry&) = delete;
  SurfaceGeometry& operator=(const SurfaceGeometry&) = delete;

  RTCGeometry geometry() const;
  // The cells (cells.h: boxes of the clip region the surface may cross), one Embree
  // primitive each and a hit's primID; 0 when the range bounds prove that no point of the
  // surface lies in the clip region. A surface of one cell registers one more primitive
  // with Embree, empty (a point at a corner of the cell's box, never hit): Embree tests a
  // box only from the BVH node above it, and a lone primitive would have none.
  unsigned primitiveCount() const;
  // The description as given to the constructor (a moved-from geometry's is empty).
  const SurfaceDesc& desc() const;
  // Number of exceptions caught inside Embree callbacks (each one counted as a miss);
  // stays 0 unless something is badly wrong. For tests and diagnostics.
  unsigned long long callbackErrors() const;

 private:
  std::unique_ptr<SurfaceData> data_;
};

// Double-precision side channel for single rays.
// The float RTCRay handed to Embree must be this ray rounded outward (makeRayHit): Embree
// traverses with the float ray, the callbacks solve with the double one. Used only for
// geometries outside instances (inside an instance the float ray is used, since Embree
// transformed it).
struct RayD {
  glm::dvec3 org{0.0};
  glm::dvec3 dir{0.0};
  double tnear = 0;
  double tfar = 0;
  // Optional bound on the distance from org to the point it stands for (pbrt-v4's
  // pError, e.g. gamma_3 (|o| + |t d|) for a point computed as o + t d from a far ray).
  // 0: org is exact up to its own rounding. A ray leaving a surface uses it to recognise
  // its own origin.
  double orgError = 0;
};
// Written by the callbacks of every algray geometry the ray reaches. After
// rtcIntersect1 the HitD is the closest algray hit; it is the scene's closest hit when
// rayhit.hit.geomID == hit.geomID and rayhit.hit.instID[0] == hit.instID[0] (another
// geometry type may have been closer; a geomID alone is ambiguous with instances, whose
// scenes number their geometries from 0 again). A hit inside an instance is solved on
// Embree's float ray (see RayD): its t is mapped to the double ray's parameter
// (fromFloatParameter), Ng is in the instanced scene's space.
struct HitD {
  bool hit = false;
  double t = 0;
  glm::dvec3 Ng{0.0};  // gradient, space as for RTCHit::Ng (not normalised)
  double u = 0, v = 0;
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = RTC_INVALID_GEOMETRY_ID;
  unsigned instID = RTC_INVALID_GEOMETRY_ID;  // as RTCHit::instID[0]
};
struct IntersectContext {
  RTCIntersectContext base;  // first member: Embree sees only this
  const RayD* ray = nullptr;
  HitD* hit = nullptr;
  RTCFilterFunctionN hostFilter = nullptr;  // the host's context filter, chained
  // The float ray of makeRayHit is the double ray re-parametrised when Embree could not
  // take it as it is (see fromFloatParameter): t = floatShift + (floatShiftLow + floatScale
  // * t_float), the shift an unevaluated sum (a far origin moves by many of its own
  // ulps). Set by initIntersectContext from the same ray (and scene).
  double floatShift = 0;
  double floatShiftLow = 0;
  glm::dvec3 floatOrigin{0.0};  // the float ray's origin when floatShift != 0
  bool floatEmpty = false;      // the float ray has an empty span (no point it can hit)
  // Set by initIntersectContext, distinct for each call in the process (a context may be
  // traced on another thread than the one that initialised it): the adapter offers
  // each root of this trace to the host's filters once (several cells may claim a root
  // the float ray passes beside, see surface_intersect.cpp).
  std::uint64_t trace = 0;
  double floatScale = 1;
};
// Initialises base (rtcInitIntersectContext) and marks the context as algray's. A context
// may serve several traces (as Embree's own are reused): the HitD is the running closest
// hit of a trace (it bounds the double ray's far end), so reset it before each one.
void initIntersectContext(IntersectContext* context, const RayD* ray, HitD* hit);
// The same for a ray traced in `scene` (committed): with the scene, a ray from far outside
// it (beyond 4096 times its extent) is handed to Embree starting near the scene's bounds,
// where float resolves the scene's boxes; without it, such a float proxy starts where
// the line enters Embree's range (1.5e18), and from ~1e6 object sizes on Embree may
// traverse boxes beside the ones the double ray crosses (missed or later hits; on a
// surface of one cell too since its box is tested, embree_bridge.cpp: of 4000 rays at a
// cylinder in a clip box from 1e7 sizes away 51 were missed without the scene, none with
// it). Use the scene overloads of initIntersectContext, makeRayHit and fromFloatParameter
// together (they must agree on the float ray).
void initIntersectContext(IntersectContext* context, const RayD* ray, HitD* hit, RTCScene scene);
// The float ray for Embree: origin and direction rounded to nearest, tnear rounded down
// and tfar rounded up (the double interval is re-applied in the callbacks), mask ~0u,
// hit ids invalid.
RTCRayHit makeRayHit(const RayD& ray);
RTCRayHit makeRayHit(const RayD& ray, RTCScene scene);
// The float ray of the context's ray, as initIntersectContext mapped it (with or without
// the scene): the same as makeRayHit(ray[, scene]), without computing the map again.
RTCRayHit makeRayHit(const IntersectContext& context);
// The parameter along `ray` of a parameter of makeRayHit(ray)'s float ray (its tfar after
// rtcIntersect1 without the double channel). The float ray is `ray` itself unless Embree
// could not take it as it is: an origin component beyond 2^40 or a direction component
// beyond 1e17 (origin moved along the line to where it enters Embree's range, or with the
// scene to near the scene's bounds when it is more than 4096 scene extents away;
// direction scaled to length 2^56), a negative tnear (origin moved back to tnear, or for
// -inf to where the line enters the scene's padded bounds, with the scene, or Embree's
// range; Embree takes tnear >= 0 only), or a direction below 2^-20 (scaled by a power of
// two: Embree treats direction components below 1e-18 as +1e-18). A host reading the
// float tfar must map it with this function.
double fromFloatParameter(const RayD& ray, double tFloat);
double fromFloatParameter(const RayD& ray, double tFloat, RTCScene scene);
// The same with the map initIntersectContext stored in the context.
double fromFloatParameter(const IntersectContext& context, double tFloat);

}  // namespace algray
