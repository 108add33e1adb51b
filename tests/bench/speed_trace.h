#pragma once
// The ray loops of tests/bench/speed_report.cpp: a pinhole camera's primary rays and the
// shadow rays from their hits towards a point light, traced through any Embree scene
// (algray surface, native sphere, triangle mesh) on one thread, on all threads
// (tbb::parallel_for over rows) and as 8-ray packets (4x2 pixel tiles, one thread).
// Every loop returns wall seconds of tracing only; the rays are generated before the
// clock starts, so the figure is Embree + geometry, not ray set-up.
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <limits>
#include <vector>

namespace algray::bench {

// ---- Camera ------------------------------------------------------------------------
// Looks at the clip sphere (c, R) from 3 R away along a generic direction (no symmetry
// axis of the gallery surfaces), with a field of view that just frames the sphere
// (half-angle asin(1/3) = 19.5 deg; tan = 0.354, we use 0.37). The light sits 4 R from
// the centre, above and to the right of the camera. Eye and directions are float values
// (what every float host passes to Embree); the double views of them are exact.
struct View {
  int width = 0, height = 0;
  glm::vec3 eye{0.0f};
  glm::vec3 light{0.0f};
  std::vector<glm::vec3> dirs;  // row-major, unit length
};

inline View makeView(const glm::dvec3& c, double r, int width, int height) {
  View v;
  v.width = width;
  v.height = height;
  const glm::dvec3 toEye = glm::normalize(glm::dvec3(1.0, -1.6, 0.9));
  v.eye = glm::vec3(c + 3.0 * r * toEye);
  const glm::dvec3 forward = glm::normalize(c - glm::dvec3(v.eye));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, forward);
  v.light = glm::vec3(c + 4.0 * r * glm::normalize(toEye + 0.6 * right + 0.9 * up));
  const double tanHalf = 0.37, aspect = static_cast<double>(width) / height;
  v.dirs.resize(static_cast<size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double px = (2.0 * (x + 0.5) / width - 1.0) * tanHalf * aspect;
      const double py = (1.0 - 2.0 * (y + 0.5) / height) * tanHalf;
      v.dirs[static_cast<size_t>(y) * width + x] =
          glm::vec3(glm::normalize(forward + px * right + py * up));
    }
  return v;
}

// A shadow ray: from a primary hit towards the light, t in (tnear, 1).
struct ShadowRay {
  glm::vec3 org{0.0f};
  glm::vec3 dir{0.0f};
};

inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Wall seconds, and CPU seconds of the calling thread: on a loaded machine the second
// still measures the work of a one-thread loop (it excludes the time the thread waited
// for a core), so one-thread ratios are also reported per CPU second.
struct Seconds {
  double wall = 0;
  double cpu = 0;
};

inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

class Stopwatch {
 public:
  Stopwatch() : wall_(std::chrono::steady_clock::now()), cpu_(threadCpuSeconds()) {}
  Seconds elapsed() const { return {secondsSince(wall_), threadCpuSeconds() - cpu_}; }

 private:
  std::chrono::steady_clock::time_point wall_;
  double cpu_;
};

// The rows y with (y / 2) % stride == 0 (pairs of rows, so packet tiles stay 4x2): a
// representative subset of the image for surfaces too slow to trace in full -reps times.
inline View subsampleRows(const View& v, int stride) {
  if (stride <= 1) return v;
  View out = v;
  out.dirs.clear();
  out.height = 0;
  for (int y = 0; y < v.height; ++y)
    if ((y / 2) % stride == 0) {
      out.dirs.insert(out.dirs.end(), v.dirs.begin() + static_cast<long>(y) * v.width,
                      v.dirs.begin() + static_cast<long>(y + 1) * v.width);
      ++out.height;
    }
  return out;
}

// ---- Single rays ---------------------------------------------------------------------
inline void setRay(RTCRay& r, const glm::vec3& o, const glm::vec3& d, float tnear, float tfar) {
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.tnear = tnear;
  r.tfar = tfar;
  r.time = 0.0f;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
}

// Primary rays of rows [y0, y1); tfar of each pixel (inf for a miss) into `t`.
inline void primaryRows(RTCScene scene, const View& v, int y0, int y1, float* t) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < v.width; ++x) {
      const size_t i = static_cast<size_t>(y) * v.width + x;
      RTCRayHit rh;
      setRay(rh.ray, v.eye, v.dirs[i], 0.0f, std::numeric_limits<float>::infinity());
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      t[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity()
                                                      : rh.ray.tfar;
    }
}

// Shadow rays [i0, i1); occluded flags into `occ`.
inline void shadowRange(RTCScene scene, const std::vector<ShadowRay>& rays, float tnear, size_t i0,
                        size_t i1, std::uint8_t* occ) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = i0; i < i1; ++i) {
    RTCRay r;
    setRay(r, rays[i].org, rays[i].dir, tnear, 1.0f);
    rtcOccluded1(scene, &context, &r);
    occ[i] = r.tfar < 0.0f;
  }
}

inline Seconds tracePrimary1(RTCScene scene, const View& v, std::vector<float>& t) {
  t.assign(v.dirs.size(), 0.0f);
  const Stopwatch clock;
  primaryRows(scene, v, 0, v.height, t.data());
  return clock.elapsed();
}

inline Seconds tracePrimaryAll(RTCScene scene, const View& v, std::vector<float>& t) {
  t.assign(v.dirs.size(), 0.0f);
  const Stopwatch clock;
  tbb::parallel_for(tbb::blocked_range<int>(0, v.height, 2), [&](const tbb::blocked_range<int>& r) {
    primaryRows(scene, v, r.begin(), r.end(), t.data());
  });
  return clock.elapsed();
}

inline Seconds traceShadow1(RTCScene scene, const std::vector<ShadowRay>& rays, float tnear,
                            std::vector<std::uint8_t>& occ) {
  occ.assign(rays.size(), 0);
  const Stopwatch clock;
  shadowRange(scene, rays, tnear, 0, rays.size(), occ.data());
  return clock.elapsed();
}

inline Seconds traceShadowAll(RTCScene scene, const std::vector<ShadowRay>& rays, float tnear,
                              std::vector<std::uint8_t>& occ) {
  occ.assign(rays.size(), 0);
  const Stopwatch clock;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256),
                    [&](const tbb::blocked_range<size_t>& r) {
                      shadowRange(scene, rays, tnear, r.begin(), r.end(), occ.data());
                    });
  return clock.elapsed();
}

// ---- Packets of 8 --------------------------------------------------------------------
// Primary rays in 4x2 pixel tiles (coherent, as a packet renderer would shoot them);
// edge tiles mask their missing lanes.
inline Seconds tracePrimary8(RTCScene scene, const View& v, std::vector<float>& t) {
  t.assign(v.dirs.size(), 0.0f);
  const Stopwatch clock;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (int y = 0; y < v.height; y += 2)
    for (int x = 0; x < v.width; x += 4) {
      alignas(32) RTCRayHit8 rh;
      alignas(32) int valid[8];
      size_t index[8];
      for (int l = 0; l < 8; ++l) {
        const int px = x + (l & 3), py = y + (l >> 2);
        valid[l] = px < v.width && py < v.height ? -1 : 0;
        index[l] = valid[l] ? static_cast<size_t>(py) * v.width + px : 0;
        const glm::vec3& d = v.dirs[index[l]];
        rh.ray.org_x[l] = v.eye.x;
        rh.ray.org_y[l] = v.eye.y;
        rh.ray.org_z[l] = v.eye.z;
        rh.ray.dir_x[l] = d.x;
        rh.ray.dir_y[l] = d.y;
        rh.ray.dir_z[l] = d.z;
        rh.ray.tnear[l] = 0.0f;
        rh.ray.tfar[l] = std::numeric_limits<float>::infinity();
        rh.ray.time[l] = 0.0f;
        rh.ray.mask[l] = ~0u;
        rh.ray.id[l] = 0;
        rh.ray.flags[l] = 0;
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID[l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect8(valid, scene, &context, &rh);
      for (int l = 0; l < 8; ++l)
        if (valid[l])
          t[index[l]] = rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID
                            ? std::numeric_limits<float>::infinity()
                            : rh.ray.tfar[l];
    }
  return clock.elapsed();
}

// Shadow rays in groups of 8 consecutive primary hits (neighbouring pixels of a row).
inline Seconds traceShadow8(RTCScene scene, const std::vector<ShadowRay>& rays, float tnear,
                            std::vector<std::uint8_t>& occ) {
  occ.assign(rays.size(), 0);
  const Stopwatch clock;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = 0; i < rays.size(); i += 8) {
    alignas(32) RTCRay8 r;
    alignas(32) int valid[8];
    for (int l = 0; l < 8; ++l) {
      const size_t k = i + l;
      valid[l] = k < rays.size() ? -1 : 0;
      const ShadowRay& s = rays[valid[l] ? k : i];
      r.org_x[l] = s.org.x;
      r.org_y[l] = s.org.y;
      r.org_z[l] = s.org.z;
      r.dir_x[l] = s.dir.x;
      r.dir_y[l] = s.dir.y;
      r.dir_z[l] = s.dir.z;
      r.tnear[l] = tnear;
      r.tfar[l] = 1.0f;
      r.time[l] = 0.0f;
      r.mask[l] = ~0u;
      r.id[l] = 0;
      r.flags[l] = 0;
    }
    rtcOccluded8(valid, scene, &context, &r);
    for (int l = 0; l < 8; ++l)
      if (valid[l]) occ[i + l] = r.tfar[l] < 0.0f;
  }
  return clock.elapsed();
}

}  // namespace algray::bench
