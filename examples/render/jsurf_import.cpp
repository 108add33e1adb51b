// SURFER/jsurf import. What the keys mean, from jsurf's renderer (IMAGINARY/jsurf,
// rendering/cpu/RayCreator.java and clipping/ClipToSphere.java; Stussak 2008):
//  * camera space -> clipping space by rotation_matrix (4x4, row-major) after the inverse
//    camera_transform; the visible region is the unit sphere of clipping space;
//  * surface space = clipping space scaled by 10^scale_factor (the zoom slider is
//    logarithmic: negative factors occur in the gallery files);
//  * shading is Phong with ambient/diffuse/specular intensities; lights are given in
//    camera space, about 100 units away, so they act as directional lights.
// We map Phong's diffuse term kd * I * cos onto a Lambertian BRDF (albedo / pi) lit by a
// directional light of irradiance pi * I, and the ambient term onto a constant
// environment (an unoccluded diffuse surface reflects albedo * environment).
#include "scene_builders.h"
#include "value_checks.h"

#include <algray/jsurf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <cmath>
#include <optional>
#include <string>

namespace algray::render {

namespace {

glm::dmat4 rowMajor(const std::vector<double>& v) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = v[r * 4 + c];
  return m;
}

glm::dvec3 vec3Of(const JsurfFile& f, const std::string& key, glm::dvec3 fallback) {
  if (!f.has(key)) return fallback;
  std::vector<double> v = f.getNumbers(key, 3);
  return {v[0], v[1], v[2]};
}

// Errors at the line of the key they are about (the tool contract: file:line).
[[noreturn]] void fail(const JsurfFile& f, const std::string& key, const std::string& message) {
  throw Error(f.name() + ":" + std::to_string(f.lineOf(key)) + ": " + key + ": " + message);
}

// A colour (or colour times intensity) the float image can hold: finite in float and not
// negative, else inf or negative pixels with exit code 0.
glm::dvec3 colorOf(const JsurfFile& f, const std::string& key, glm::dvec3 fallback) {
  const glm::dvec3 c = vec3Of(f, key, fallback);
  if (!isFloatColor(c)) fail(f, key, "colour components must be in [0, 3.4e38]");
  return c;
}
double nonNegative(const JsurfFile& f, const std::string& key, double fallback) {
  const double v = f.getNumber(key, fallback);
  if (!(v >= 0)) fail(f, key, "must not be negative");
  return v;
}

// A 3x3 part that is not singular relative to its own scale (|det| against the product of
// the column lengths, as the plugin judges transforms) and whose determinant is a double.
bool wellConditioned(const glm::dmat3& a) {
  const double hadamard = glm::length(a[0]) * glm::length(a[1]) * glm::length(a[2]);
  const double det = std::abs(glm::determinant(a));
  return std::isfinite(hadamard) && std::isfinite(det) && det > 64.0 * 0x1p-53 * hadamard;
}

}  // namespace

SceneDesc jsurfScene(const std::filesystem::path& path) {
  std::error_code ec;
  // An ifstream opens a directory and reads nothing ("no surface_equation").
  if (std::filesystem::is_directory(path, ec))
    throw Error(path.string() + ": is a directory, not a .jsurf file");
  JsurfFile f = JsurfFile::read(path);
  SceneDesc scene;
  scene.name = path.filename().string();

  // ---- Surface and its placement -----------------------------------------------------
  SurfaceItem s;
  // Errors the plugin raises when Scene builds the surface point at the equation's line.
  s.label = path.string() + ":" + std::to_string(f.lineOf("surface_equation")) + ": surface";
  s.polynomial = f.polynomial();
  // 10^scale_factor is the surface's size in view units; the transform's determinant is
  // its cube, which must stay a normal double for the plugin (beyond +-100 it overflowed
  // to "singular rotation_matrix" at line 0, or to an infinite clip radius).
  const double scaleFactor = f.getNumber("scale_factor", 0.0);
  if (!(std::abs(scaleFactor) <= 100))
    fail(f, "scale_factor", "must be in [-100, 100] (10^scale_factor is the zoom)");
  const double scale = std::pow(10.0, scaleFactor);
  glm::dmat4 rotation(1.0);
  if (f.has("rotation_matrix")) {
    rotation = rowMajor(f.getNumbers("rotation_matrix", 16));
    // Only its 3x3 part is used (SURFER rotates about the clip sphere's centre): a
    // translation or a projective row was dropped without a word.
    if (rotation[3] != glm::dvec4(0, 0, 0, 1) || rotation[0][3] != 0 || rotation[1][3] != 0 ||
        rotation[2][3] != 0)
      fail(f, "rotation_matrix",
           "must be a 3x3 rotation in a 4x4 matrix (last column and last row 0 0 0 1)");
    if (!wellConditioned(glm::dmat3(rotation)))
      fail(f, "rotation_matrix", "singular (or out of range) matrix");
  }
  glm::dmat4 cameraTransform = glm::translate(glm::dmat4(1.0), {0, 0, -1});
  if (f.has("camera_transform")) {
    cameraTransform = rowMajor(f.getNumbers("camera_transform", 16));
    if (cameraTransform[0][3] != 0 || cameraTransform[1][3] != 0 || cameraTransform[2][3] != 0 ||
        cameraTransform[3][3] != 1)
      fail(f, "camera_transform", "the matrix must be affine (last row 0 0 0 1), not projective");
    if (!wellConditioned(glm::dmat3(cameraTransform)))
      fail(f, "camera_transform", "singular (or out of range) matrix");
  }
  // World = SURFER's world; surface = scale * rotation * world. The clip sphere (unit in
  // clipping space) has radius `scale` in surface space.
  glm::dmat4 worldToSurface = glm::scale(glm::dmat4(1.0), glm::dvec3(scale)) * rotation;
  // Inverting the 3x3 part keeps the last row exactly (0, 0, 0, 1).
  s.transform = glm::dmat4(glm::inverse(glm::dmat3(worldToSurface)));
  s.clip = ClipSphere{glm::dvec3(0.0), scale};

  // ---- Materials -------------------------------------------------------------------------
  auto material = [&](const std::string& side) {
    Material m;
    const std::string kdKey = side + "_material_diffuse_intensity";
    double kd = nonNegative(f, kdKey, 0.8);
    m.color = colorOf(f, side + "_material_color", glm::dvec3(0.8)) * kd;
    if (!isFloatColor(m.color)) fail(f, kdKey, "colour times intensity beyond 3.4e38");
    return m;
  };
  s.material = scene.addMaterial(material("front"));
  s.backMaterial = scene.addMaterial(material("back"));
  double kd = nonNegative(f, "front_material_diffuse_intensity", 0.8);
  double ka = nonNegative(f, "front_material_ambient_intensity", 0.4);
  scene.environment.color = glm::dvec3(kd > 0 ? ka / kd : ka);
  if (!isFloatColor(scene.environment.color))
    fail(f, "front_material_ambient_intensity", "ambient / diffuse intensity beyond 3.4e38");
  scene.surfaces.push_back(std::move(s));

  // ---- Camera: SURFER's camera at the origin of camera space, looking down -z ---------
  glm::dmat4 cameraToWorld = glm::inverse(cameraTransform);
  glm::dvec3 eye(cameraToWorld * glm::dvec4(0, 0, 0, 1));
  const std::optional<glm::dvec3> forward =
      safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 0, -1, 0)));
  const std::optional<glm::dvec3> up =
      safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 1, 0, 0)));
  if (!withinCoordinateRange(eye) || !forward || !up)
    fail(f, "camera_transform", "puts the camera beyond 1e17 (Embree's float rays reach 1.8e18)");
  scene.camera.position = eye;
  scene.camera.lookAt = eye + *forward;
  scene.camera.up = *up;
  std::string type = f.get("camera_type").value_or("ORTHOGRAPHIC_CAMERA");
  if (type == "PERSPECTIVE_CAMERA") {
    scene.camera.type = CameraDesc::Type::Perspective;
    scene.camera.fovY = f.getNumber("camera_fov_y", 60.0);
    if (!(scene.camera.fovY > 0 && scene.camera.fovY < 180))
      fail(f, "camera_fov_y", "must be in (0, 180) degrees");
  } else if (type == "ORTHOGRAPHIC_CAMERA") {
    scene.camera.type = CameraDesc::Type::Orthographic;
    scene.camera.height = f.getNumber("camera_height", 2.0);
    if (!(scene.camera.height > 0)) fail(f, "camera_height", "must be positive");
    if (!withinCoordinateRange(scene.camera.height))
      fail(f, "camera_height",
           "beyond 1e17, outside the range Embree's float rays can trace (1.8e18)");
  } else {
    fail(f, "camera_type", "'" + type + "' is not ORTHOGRAPHIC_CAMERA or PERSPECTIVE_CAMERA");
  }

  // ---- Lights (camera space, far away) -------------------------------------------------
  for (int i = 0; i < 8; ++i) {
    std::string n = std::to_string(i);
    // Colour and intensity are checked for every light, on or off: a bad value is bad input.
    glm::dvec3 color = colorOf(f, "light_color_" + n, glm::dvec3(1.0));
    double intensity = nonNegative(f, "light_intensity_" + n, 1.0);
    const glm::dvec3 irradiance = color * (intensity * 3.14159265358979323846);
    if (!isFloatColor(irradiance))
      fail(f, "light_intensity_" + n, "colour times intensity beyond 3.4e38");
    if (f.get("light_status_" + n).value_or("OFF") != "ON") continue;
    glm::dvec3 pos = vec3Of(f, "light_position_" + n, glm::dvec3(0.0));
    if (pos == glm::dvec3(0.0)) continue;
    // safeNormalize: glm::normalize of 1e-200 or 1e308 components gave NaN rays.
    const std::optional<glm::dvec3> toLight = safeNormalize(pos);
    const std::optional<glm::dvec3> dirWorld =
        toLight ? safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(*toLight, 0.0)))
                : std::nullopt;
    if (!dirWorld) fail(f, "light_position_" + n, "no direction can be taken from this position");
    scene.directionalLights.push_back({*dirWorld, irradiance});
  }
  scene.hasBackground = true;
  scene.background = colorOf(f, "background_color", glm::dvec3(1.0));
  scene.settings.width = 512;
  scene.settings.height = 512;
  scene.settings.spp = 4;
  scene.settings.integrator = IntegratorType::Direct;
  scene.settings.toneMap = ToneMap::Clamp;
  return scene;
}

}  // namespace algray::render
