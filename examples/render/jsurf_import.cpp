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

#include <algray/jsurf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <cmath>
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

}  // namespace

SceneDesc jsurfScene(const std::filesystem::path& path) {
  JsurfFile f = JsurfFile::read(path);
  SceneDesc scene;
  scene.name = path.filename().string();

  // ---- Surface and its placement -----------------------------------------------------
  SurfaceItem s;
  s.label = path.string();
  s.polynomial = f.polynomial();
  double scale = std::pow(10.0, f.getNumber("scale_factor", 0.0));
  glm::dmat4 rotation(1.0);
  if (f.has("rotation_matrix")) rotation = rowMajor(f.getNumbers("rotation_matrix", 16));
  glm::dmat4 cameraTransform = glm::translate(glm::dmat4(1.0), {0, 0, -1});
  if (f.has("camera_transform")) cameraTransform = rowMajor(f.getNumbers("camera_transform", 16));
  // World = SURFER's world; surface = scale * rotation * world. The clip sphere (unit in
  // clipping space) has radius `scale` in surface space.
  glm::dmat4 worldToSurface = glm::scale(glm::dmat4(1.0), glm::dvec3(scale)) * rotation;
  if (glm::determinant(glm::dmat3(worldToSurface)) == 0)
    throw Error(path.string() + ":" + std::to_string(f.lineOf("rotation_matrix")) + ": singular rotation_matrix");
  // Inverting the 3x3 part keeps the last row exactly (0, 0, 0, 1).
  s.transform = glm::dmat4(glm::inverse(glm::dmat3(worldToSurface)));
  s.clip = ClipSphere{glm::dvec3(0.0), scale};

  // ---- Materials -------------------------------------------------------------------------
  auto material = [&](const std::string& side) {
    Material m;
    double kd = f.getNumber(side + "_material_diffuse_intensity", 0.8);
    m.color = vec3Of(f, side + "_material_color", glm::dvec3(0.8)) * kd;
    return m;
  };
  s.material = scene.addMaterial(material("front"));
  s.backMaterial = scene.addMaterial(material("back"));
  double kd = f.getNumber("front_material_diffuse_intensity", 0.8);
  double ka = f.getNumber("front_material_ambient_intensity", 0.4);
  scene.environment.color = glm::dvec3(kd > 0 ? ka / kd : ka);
  scene.surfaces.push_back(std::move(s));

  // ---- Camera: SURFER's camera at the origin of camera space, looking down -z ---------
  glm::dmat4 cameraToWorld = glm::inverse(cameraTransform);
  glm::dvec3 eye(cameraToWorld * glm::dvec4(0, 0, 0, 1));
  glm::dvec3 forward = glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 0, -1, 0)));
  glm::dvec3 up = glm::normalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 1, 0, 0)));
  scene.camera.position = eye;
  scene.camera.lookAt = eye + forward;
  scene.camera.up = up;
  std::string type = f.get("camera_type").value_or("ORTHOGRAPHIC_CAMERA");
  if (type == "PERSPECTIVE_CAMERA") {
    scene.camera.type = CameraDesc::Type::Perspective;
    scene.camera.fovY = f.getNumber("camera_fov_y", 60.0);
  } else {
    scene.camera.type = CameraDesc::Type::Orthographic;
    scene.camera.height = f.getNumber("camera_height", 2.0);
  }

  // ---- Lights (camera space, far away) -------------------------------------------------
  for (int i = 0; i < 8; ++i) {
    std::string n = std::to_string(i);
    if (f.get("light_status_" + n).value_or("OFF") != "ON") continue;
    glm::dvec3 pos = vec3Of(f, "light_position_" + n, glm::dvec3(0.0));
    if (pos == glm::dvec3(0.0)) continue;
    glm::dvec3 dirWorld(cameraToWorld * glm::dvec4(glm::normalize(pos), 0.0));
    glm::dvec3 color = vec3Of(f, "light_color_" + n, glm::dvec3(1.0));
    double intensity = f.getNumber("light_intensity_" + n, 1.0);
    scene.directionalLights.push_back({dirWorld, color * (intensity * 3.14159265358979323846)});
  }
  scene.hasBackground = true;
  scene.background = vec3Of(f, "background_color", glm::dvec3(1.0));
  scene.settings.width = 512;
  scene.settings.height = 512;
  scene.settings.spp = 4;
  scene.settings.integrator = IntegratorType::Direct;
  scene.settings.toneMap = ToneMap::Clamp;
  return scene;
}

}  // namespace algray::render
