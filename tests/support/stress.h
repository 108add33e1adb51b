#pragma once
// Helpers of the numerical-stability stress suites (tests/stress_*test.cpp): one surface
// in its own scene, traced through the double-precision side channel, with every hit
// checked for finiteness and for lying inside the ray's interval.
#include "algray/embree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "../embree_test_util.h"
#include "reference.h"

namespace algray::test {

inline constexpr double kInfD = std::numeric_limits<double>::infinity();

inline RayD rayD(glm::dvec3 o, glm::dvec3 d, double tnear = 0.0, double tfar = kInfD) {
  return RayD{o, d, tnear, tfar};
}

inline bool finiteVec(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

class OneSurface {
 public:
  explicit OneSurface(const SurfaceDesc& desc) : scene_(device_) {
    geometry_.emplace(device_, desc);
    scene_.attach(geometry_->geometry());
    scene_.commit();
  }
  ~OneSurface() {
    EXPECT_EQ(geometry_->callbackErrors(), 0u) << "exceptions inside Embree callbacks";
  }
  OneSurface(const OneSurface&) = delete;
  OneSurface& operator=(const OneSurface&) = delete;

  // Closest hit through the double channel; a hit must be finite and inside (tnear, tfar).
  std::optional<HitD> intersect(const RayD& ray, const std::string& what = "") {
    RTCRayHit rh;
    const HitD hit = intersectD(scene_, ray, &rh);
    if (!hit.hit) {
      EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID)
          << what << ": float record without double hit";
      return std::nullopt;
    }
    EXPECT_TRUE(std::isfinite(hit.t) && finiteVec(hit.Ng))
        << what << ": non-finite hit t=" << hit.t;
    EXPECT_TRUE(hit.t > ray.tnear && hit.t < ray.tfar)
        << what << ": hit outside the ray interval, t=" << hit.t;
    EXPECT_TRUE(std::isfinite(rh.ray.tfar)) << what;
    return hit;
  }
  // The plain float path (no double channel): the float hit's t along `ray`.
  std::optional<double> intersectFloat(const RayD& ray, const std::string& what = "") {
    RTCRayHit rh = makeRayHit(ray, scene_);
    rh = intersect1(scene_, rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    EXPECT_TRUE(std::isfinite(rh.ray.tfar) &&
                std::isfinite(rh.hit.Ng_x + rh.hit.Ng_y + rh.hit.Ng_z))
        << what;
    return fromFloatParameter(ray, rh.ray.tfar, scene_);
  }
  // Occlusion through the double channel.
  bool occluded(const RayD& ray) {
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene_);
    RTCRayHit rh = makeRayHit(context);
    const float before = rh.ray.tfar;  // -inf already means "occluded" to Embree
    rtcOccluded1(scene_, &context.base, &rh.ray);
    return before != -std::numeric_limits<float>::infinity() &&
           rh.ray.tfar == -std::numeric_limits<float>::infinity();
  }
  const SurfaceGeometry& geometry() const { return *geometry_; }
  // Installs `filter` as the geometry's intersection and occlusion filter (nullptr: none).
  void setFilter(RTCFilterFunctionN filter) {
    rtcSetGeometryIntersectFilterFunction(geometry_->geometry(), filter);
    rtcSetGeometryOccludedFilterFunction(geometry_->geometry(), filter);
    rtcCommitGeometry(geometry_->geometry());
    scene_.commit();
  }

 private:
  Device device_;
  std::optional<SurfaceGeometry> geometry_;
  Scene scene_;
};

// A double ray from the hit o + t d in direction dir, with pbrt-v4's bound on its origin,
// gamma(3) (|o| + |t d|), as a host computes the hit point; and a ray whose query replaces
// the thread's record (so that the next query of a ray is asked cold).
inline RayD leavingRayD(const glm::dvec3& o, const glm::dvec3& d, double t, const glm::dvec3& dir) {
  RayD ray = rayD(o + t * d, dir);
  ray.orgError = gamma(3) * (glm::length(o) + glm::length(t * d));
  return ray;
}
inline RayD otherRayD(double radius) { return rayD(glm::dvec3(5.0 * radius), glm::dvec3(-1.0)); }

inline SurfaceDesc describe(Polynomial f, double clipRadius, glm::dvec3 centre = glm::dvec3(0.0)) {
  SurfaceDesc desc;
  desc.polynomial = std::move(f);
  desc.clip = ClipSphere{centre, clipRadius};
  return desc;
}

}  // namespace algray::test
