#pragma once
// Light transport for one camera ray.
//  * path: unidirectional path tracing with next-event estimation and multiple
//    importance sampling (power heuristic) between light and BSDF sampling, Russian
//    roulette after three bounces (Veach's thesis, Ch. 9-10; pbrt-v4 Sec. 13.4).
//  * direct: first hit only, every point/directional light with a hard shadow ray, one
//    sample per area light, the environment as unshadowed ambient light; specular
//    (glass) surfaces are followed. Quick previews and the POV-Ray comparison.
//  * surfer: jsurf's shading of the first hit (IMAGINARY/jsurf rendering/cpu/Shader.java
//    and RenderingTask.shade), not light transport: display values for ToneMap::None.
#include "sampling.h"
#include "scene.h"

namespace algray::render {

// First-hit data for the extra image channels (AOVs).
struct SampleAov {
  double depth = 0;        // distance to the first hit, 0 when nothing is hit
  glm::dvec3 normal{0.0};  // shading normal facing the camera
  glm::dvec3 albedo{0.0};
  double id = 0;  // geomID + 1, 0 for the background
  // geomID + 1 of the first hit that is not glass along the camera ray's chain of specular
  // (glass) bounces, 0 if none: a surface seen through glass is seen, though never the
  // first hit (render.cpp's "no camera ray hit it" warning).
  unsigned seenThrough = 0;
};

glm::dvec3 tracePath(const Scene& scene, const CameraRay& ray, Rng& rng, SampleAov& aov,
                     RayCounter& counter);
glm::dvec3 traceSurfer(const Scene& scene, const CameraRay& ray, Rng& rng, SampleAov& aov,
                       RayCounter& counter);
glm::dvec3 traceDirect(const Scene& scene, const CameraRay& ray, Rng& rng, SampleAov& aov,
                       RayCounter& counter);

}  // namespace algray::render
