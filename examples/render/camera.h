#pragma once
// Pinhole / thin-lens perspective and orthographic cameras, set up by look-at.
// Thin lens: pbrt-v4 Sec. 5.2.3 (sample the aperture disk, aim at the focal plane).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace algray::render {

struct CameraDesc {
  enum class Type { Perspective, Orthographic } type = Type::Perspective;
  glm::dvec3 position{0.0, -6.0, 2.0};
  glm::dvec3 lookAt{0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double fovY = 40.0;          // degrees, perspective
  double height = 2.0;         // world units, orthographic: vertical extent of the view
  double aperture = 0.0;       // lens radius, 0 = pinhole
  double focusDistance = 0.0;  // 0 = distance to lookAt
  // fovY / height span the image's shorter side instead of its height, so a portrait image
  // sees as much across as a square one (quick mode and .jsurf scenes frame a clip sphere).
  bool fitShorterSide = false;
};

struct CameraRay {
  glm::dvec3 org, dir;  // dir is unit length
};

class Camera {
 public:
  Camera(const CameraDesc& desc, int width, int height);
  // film: pixel coordinates (x right, y down), continuous; lens: [0,1)^2.
  CameraRay generateRay(glm::dvec2 film, glm::dvec2 lens) const;
  const CameraDesc& desc() const { return desc_; }

 private:
  CameraDesc desc_;
  int width_, height_;
  glm::dvec3 forward_, right_, upv_;
  double halfH_, halfW_, focus_;
};

}  // namespace algray::render
