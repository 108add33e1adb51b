#include "camera.h"

#include "sampling.h"
#include "value_checks.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace algray::render {

Camera::Camera(const CameraDesc& desc, int width, int height)
    : desc_(desc), width_(width), height_(height) {
  // safeNormalize: glm::normalize of a difference below ~1e-154 or beyond ~1e154 gives
  // NaN, which then looked like a bad up vector. The loaders report these with a location;
  // this guards the other callers.
  const glm::dvec3 f = desc.lookAt - desc.position;
  const std::optional<glm::dvec3> forward = safeNormalize(f);
  if (!forward) throw std::runtime_error("camera: position and look_at must differ and be finite");
  forward_ = *forward;
  const double dist = glm::length(f);
  const std::optional<glm::dvec3> up = safeNormalize(desc.up);
  if (!up) throw std::runtime_error("camera: up must be a finite non-zero vector");
  const std::optional<glm::dvec3> r = safeNormalize(glm::cross(forward_, *up));
  if (!r || !(glm::length(glm::cross(forward_, *up)) > 1e-9))
    throw std::runtime_error("camera: up must not be parallel to the view direction");
  right_ = *r;
  upv_ = glm::cross(right_, forward_);
  double aspect = static_cast<double>(width) / height;
  if (desc.type == CameraDesc::Type::Perspective) {
    if (!(desc.fovY > 0 && desc.fovY < 180))
      throw std::runtime_error("camera: fov out of (0, 180)");
    halfH_ = std::tan(0.5 * desc.fovY * kPi / 180.0);
  } else {
    if (!(desc.height > 0)) throw std::runtime_error("camera: height must be positive");
    halfH_ = 0.5 * desc.height;
  }
  if (desc.fitShorterSide && aspect < 1) halfH_ /= aspect;
  halfW_ = halfH_ * aspect;
  // dist may overflow for far-apart points; the focus plane then is as far as a double goes.
  focus_ = desc.focusDistance > 0 ? desc.focusDistance
                                  : std::min(dist, std::numeric_limits<double>::max());
}

CameraRay Camera::generateRay(glm::dvec2 film, glm::dvec2 lens) const {
  // Screen coordinates in [-1, 1], y up.
  double sx = 2.0 * film.x / width_ - 1.0;
  double sy = 1.0 - 2.0 * film.y / height_;
  if (desc_.type == CameraDesc::Type::Orthographic) {
    glm::dvec3 org = desc_.position + sx * halfW_ * right_ + sy * halfH_ * upv_;
    return {org, forward_};
  }
  glm::dvec3 dir = forward_ + sx * halfW_ * right_ + sy * halfH_ * upv_;
  if (desc_.aperture <= 0) return {desc_.position, glm::normalize(dir)};
  // Thin lens: every ray through the lens point meets the pinhole ray on the plane of
  // focus at distance focus_ along forward.
  glm::dvec3 pFocus = desc_.position + dir * focus_;  // dir has unit forward component
  glm::dvec2 d = desc_.aperture * sampleUniformDisk(lens);
  glm::dvec3 org = desc_.position + d.x * right_ + d.y * upv_;
  return {org, glm::normalize(pFocus - org)};
}

}  // namespace algray::render
