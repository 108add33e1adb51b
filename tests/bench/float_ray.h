#pragma once
// The float ray a host without algray's double channel traces: the double ray rounded to
// float as it stands (no re-centring of far origins, which only makeRayHit does). Shared
// by the benchmarks that trace plain float rays (intersector_report, cells_bench).
#include "algray/embree.h"

namespace algray::bench {

inline RTCRayHit plainFloatRay(const RayD& ray) {
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(ray.org.x);
  rh.ray.org_y = static_cast<float>(ray.org.y);
  rh.ray.org_z = static_cast<float>(ray.org.z);
  rh.ray.dir_x = static_cast<float>(ray.dir.x);
  rh.ray.dir_y = static_cast<float>(ray.dir.y);
  rh.ray.dir_z = static_cast<float>(ray.dir.z);
  rh.ray.tnear = static_cast<float>(ray.tnear);
  rh.ray.tfar = static_cast<float>(ray.tfar);
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace algray::bench
