// algray-minimal: a plain Embree 3 scene with a triangle mesh (a floor quad) and one
// algebraic surface (a torus from its equation), then a few rays and their hits.
#include <algray/embree.h>
#include <algray/parser.h>

#include <embree3/rtcore.h>

#include <cstdio>
#include <limits>

// The scene and its rays. The surface (a SurfaceGeometry) lives in this function's scope,
// so it is destroyed after the scene that uses it and before main releases the device.
void traceScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);

  // ---- The host's own geometry: a floor quad at z = -0.5 ---------------------------------
  RTCGeometry floor = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(floor, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
  const float verts[12] = {-4, -4, -0.5f, 4, -4, -0.5f, 4, 4, -0.5f, -4, 4, -0.5f};
  for (int i = 0; i < 12; ++i) v[i] = verts[i];
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      floor, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2));
  const unsigned tris[6] = {0, 1, 2, 0, 2, 3};
  for (int i = 0; i < 6; ++i) idx[i] = tris[i];
  rtcCommitGeometry(floor);
  const unsigned floorID = rtcAttachGeometry(scene, floor);
  rtcReleaseGeometry(floor);

  // ---- The algebraic surface: five lines ---------------------------------------------------
  algray::SurfaceDesc desc;
  desc.polynomial = algray::parsePolynomial("(x^2+y^2+z^2+R^2-r^2)^2 - 4*R^2*(x^2+y^2)",
                                            {.parameters = {{"R", 1.0}, {"r", 0.4}}});
  desc.clip = algray::ClipSphere{{0, 0, 0}, 1.5};
  algray::SurfaceGeometry torus(device, desc);
  const unsigned torusID = rtcAttachGeometry(scene, torus.geometry());
  rtcCommitScene(scene);

  // ---- A few rays --------------------------------------------------------------------------
  const float rays[][6] = {
      {-3, 0, 0, 1, 0, 0},  // along the x axis: the torus' outer wall at x = -1.4
      {0, 0, 3, 0, 0, -1},  // down the axis: through the hole onto the floor
      {1, 0, 3, 0, 0, -1},  // down onto the tube's top at (1, 0, 0.4)
      {3, 3, 3, 0, 0, -1},  // beside everything: the floor
      {3, 3, 3, 1, 0, 0},   // into the void
  };
  for (const auto& r : rays) {
    RTCRayHit rh{};
    rh.ray.org_x = r[0], rh.ray.org_y = r[1], rh.ray.org_z = r[2];
    rh.ray.dir_x = r[3], rh.ray.dir_y = r[4], rh.ray.dir_z = r[5];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;  // Embree's rule for every ray (instancing)
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene, &context, &rh);
    const char* what = rh.hit.geomID == torusID   ? "torus"
                       : rh.hit.geomID == floorID ? "floor"
                                                  : "nothing";
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
      std::printf("ray (%g %g %g) -> (%g %g %g): miss\n", r[0], r[1], r[2], r[3], r[4], r[5]);
      continue;
    }
    std::printf("ray (%g %g %g) -> (%g %g %g): %s at t = %.6g, Ng = (%.3g %.3g %.3g)\n", r[0], r[1],
                r[2], r[3], r[4], r[5], what, rh.ray.tfar, rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  }

  rtcReleaseScene(scene);
}

int main() {
  RTCDevice device = rtcNewDevice(nullptr);
  traceScene(device);
  rtcReleaseDevice(device);
  return 0;
}
