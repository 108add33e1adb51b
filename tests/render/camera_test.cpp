// The camera's rays by trigonometry: which ray goes through a given film point for the
// perspective, orthographic and thin-lens cameras (camera.h).
#include "camera.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace algray::render {
namespace {

void expectNear(glm::dvec3 a, glm::dvec3 b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol) << "x";
  EXPECT_NEAR(a.y, b.y, tol) << "y";
  EXPECT_NEAR(a.z, b.z, tol) << "z";
}

// A camera at the origin looking along +y with +z up: right is cross(forward, up) = +x.
CameraDesc lookingAlongY(CameraDesc::Type type) {
  CameraDesc d;
  d.type = type;
  d.position = glm::dvec3(0.0);
  d.lookAt = {0, 10, 0};
  d.up = {0, 0, 1};
  return d;
}

// fovY = 90 degrees: the half height at unit distance is tan(45 deg) = 1, and a 200 x 100
// image's half width is twice that. Film (150, 25) is half way from the centre to the right
// edge and half way up to the top edge (film y runs down), so the ray is along
// forward + 0.5 * 2 * right + 0.5 * 1 * up = (1, 1, 0.5), length 1.5: (2, 2, 1) / 3.
// The top-left corner (0, 0) looks along (-2, 1, 1) / sqrt(6).
TEST(Camera, PerspectiveRayThroughAPixelByTrigonometry) {
  CameraDesc d = lookingAlongY(CameraDesc::Type::Perspective);
  d.fovY = 90.0;
  const Camera cam(d, 200, 100);
  const CameraRay r = cam.generateRay({150, 25}, {0.5, 0.5});
  expectNear(r.org, glm::dvec3(0.0), 0.0);
  expectNear(r.dir, glm::dvec3(2, 2, 1) / 3.0, 1e-15);
  const CameraRay corner = cam.generateRay({0, 0}, {0.5, 0.5});
  expectNear(corner.dir, glm::dvec3(-2, 1, 1) / std::sqrt(6.0), 1e-15);
  // fovY = 60 degrees: the top-centre ray is 30 degrees above forward:
  // (0, cos 30, sin 30) = (0, sqrt(3) / 2, 1 / 2).
  d.fovY = 60.0;
  const CameraRay top = Camera(d, 200, 100).generateRay({100, 0}, {0.5, 0.5});
  expectNear(top.dir, glm::dvec3(0, std::sqrt(3.0) / 2, 0.5), 1e-15);
}

// Orthographic: height 2 spans z in [-1, 1] at the image plane through the position, the
// 200 x 100 image's width spans x in [-2, 2]; every ray runs along forward. Film (150, 25)
// starts at (0.5 * 2, 0, 0.5 * 1).
TEST(Camera, OrthographicRayThroughAPixelIsParallelAndOffset) {
  CameraDesc d = lookingAlongY(CameraDesc::Type::Orthographic);
  d.height = 2.0;
  const Camera cam(d, 200, 100);
  const CameraRay r = cam.generateRay({150, 25}, {0.5, 0.5});
  expectNear(r.org, {1.0, 0.0, 0.5}, 1e-15);
  expectNear(r.dir, {0, 1, 0}, 0.0);
  const CameraRay corner = cam.generateRay({200, 100}, {0.5, 0.5});
  expectNear(corner.org, {2.0, 0.0, -1.0}, 1e-15);
}

// Thin lens (pbrt-v4 Sec. 5.2.3): the ray starts on the lens disk of radius `aperture` in
// the plane through the position perpendicular to forward, and passes through the point
// where the pinhole ray meets the plane of focus y = focusDistance (here 3, not the
// look-at distance 10). With the set-up of the perspective test the pinhole ray through
// film (150, 25) runs along (1, 1, 0.5), so it meets y = 3 at (3, 3, 1.5). The concentric
// disk map sends the midpoints of the lens square's edges (1, 1/2) and (1/2, 1) to the
// rim at angles 0 and 90 degrees: lens points aperture * right and aperture * up.
TEST(Camera, ThinLensRaysMeetOnThePlaneOfFocus) {
  CameraDesc d = lookingAlongY(CameraDesc::Type::Perspective);
  d.fovY = 90.0;
  d.aperture = 0.5;
  d.focusDistance = 3.0;
  const Camera cam(d, 200, 100);
  const glm::dvec3 focus(3.0, 3.0, 1.5);
  for (const glm::dvec2 lens : {glm::dvec2(0.5, 0.5), glm::dvec2(1.0, 0.5), glm::dvec2(0.5, 1.0),
                                glm::dvec2(0.1, 0.8), glm::dvec2(0.9, 0.3)}) {
    const CameraRay r = cam.generateRay({150, 25}, lens);
    EXPECT_NEAR(r.org.y, 0.0, 1e-15) << "lens point off the lens plane";
    EXPECT_LE(glm::length(r.org), 0.5 + 1e-15);
    EXPECT_NEAR(glm::length(r.dir), 1.0, 1e-15);
    const double t = (focus.y - r.org.y) / r.dir.y;
    expectNear(r.org + t * r.dir, focus, 1e-12);
  }
  expectNear(cam.generateRay({150, 25}, {1.0, 0.5}).org, {0.5, 0, 0}, 1e-15);
  expectNear(cam.generateRay({150, 25}, {0.5, 1.0}).org, {0, 0, 0.5}, 1e-15);
}

}  // namespace
}  // namespace algray::render
