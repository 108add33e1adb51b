#include "pov_export.h"

#include "sampling.h"
#include "value_checks.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

namespace algray::render {

namespace {

constexpr int kPovRayMaxDegree = 35;

std::string vec(const glm::dvec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "<%.17g, %.17g, %.17g>", v.x, v.y, v.z);
  return buf;
}

std::string rgb(const glm::dvec3& c) { return "rgb " + vec(c); }

std::string finish(double ambient) {
  std::ostringstream s;
  s << "finish { ambient " << ambient << " diffuse 1 brilliance 1 specular 0 phong 0 }";
  return s.str();
}

}  // namespace

std::string povrayScene(const SceneDesc& scene, bool sturm) {
  std::ostringstream out;
  out.precision(17);
  const RenderSettings& s = scene.settings;
  const CameraDesc& cam = scene.camera;
  if (cam.type != CameraDesc::Type::Perspective || cam.aperture > 0)
    throw std::runtime_error("POV-Ray export: only pinhole perspective cameras");
  glm::dvec3 env = scene.environment.color;
  if (env.r != env.g || env.g != env.b)
    throw std::runtime_error("POV-Ray export: grey environments only");
  // The ambient light and background below are the colour alone; an image's were lost
  // (exported as if it were all ones).
  if (!scene.environment.image.empty())
    throw std::runtime_error("POV-Ray export: image environments are not exported");
  double aspect = static_cast<double>(s.width) / s.height;
  // POV-Ray's angle is the horizontal one: fovY spans the width itself where a camera fits
  // its shorter side in a portrait image (quick mode; the portrait export cut the surface
  // off at both sides).
  double hfov =
      cam.fitShorterSide && aspect < 1
          ? cam.fovY
          : 2.0 * std::atan(aspect * std::tan(0.5 * cam.fovY * kPi / 180.0)) * 180.0 / kPi;
  out << "// Written by algray-render --export-pov: the same scene as algray's direct "
         "integrator.\n";
  out << "#version 3.7;\n";
  out << "global_settings { assumed_gamma 1.0 ambient_light rgb <1, 1, 1> max_trace_level 5 }\n";
  // POV-Ray is left-handed; a negative `right` makes the picture right-handed like ours.
  // look_at turns up and right about sky but keeps their lengths, whose ratio is the
  // picture's: up is written as a unit vector (a scene built in code with up <0, 0, 3> was
  // exported three times too tall; the loaders normalise it).
  const std::optional<glm::dvec3> up = safeNormalize(cam.up);
  if (!up)
    throw std::runtime_error("POV-Ray export: the camera's up must be a finite non-zero vector");
  out << "camera { perspective location " << vec(cam.position) << " sky " << vec(*up) << " up "
      << vec(*up) << " right <" << -aspect << ", 0, 0> angle " << hfov << " look_at "
      << vec(cam.lookAt) << " }\n";
  out << "background { color " << rgb(scene.hasBackground ? scene.background : env) << " }\n";
  double far = 1e3 * std::max(1.0, glm::length(cam.position - cam.lookAt));
  for (const DirectionalLight& l : scene.directionalLights)
    out << "light_source { " << vec(far * glm::normalize(l.direction)) << " color "
        << rgb(l.irradiance / kPi) << " parallel point_at <0, 0, 0> }\n";
  if (!scene.pointLights.empty())
    throw std::runtime_error("POV-Ray export: point lights are not exported");
  auto texture = [&](int m) {
    const Material& mat = scene.materials.at(m);
    if (mat.type != MaterialType::Diffuse || mat.texture)
      throw std::runtime_error("POV-Ray export: untextured diffuse materials only");
    return "pigment { color " + rgb(mat.color) + " } " + finish(env.r);
  };
  for (const SurfaceItem& item : scene.surfaces) {
    const auto* clip = std::get_if<ClipSphere>(&item.clip);
    if (!clip || item.transform != glm::dmat4(1.0))
      throw std::runtime_error("POV-Ray export: surfaces need a clip sphere and no transform");
    const Polynomial& p = item.polynomial;
    int n = p.degree();
    // POV-Ray's polynomial object stops at its MAX_ORDER ("Order of polynom is out of
    // range" for degrees 36-40, which algray traces).
    if (n > kPovRayMaxDegree)
      throw std::runtime_error("POV-Ray export: POV-Ray's polynomial takes degree <= " +
                               std::to_string(kPovRayMaxDegree) + ", this surface has degree " +
                               std::to_string(n));
    // POV-Ray 3.7's polynomial takes orders 2..35 ("Order of polynom is out of range" for
    // 1); a plane is the order-2 polynomial whose quadratic terms are zero (absent xyz terms
    // are 0), which its solver reduces to the linear equation.
    out << "polynomial { " << std::max(n, 2);
    for (int d = n; d >= 0; --d)
      for (int i = d; i >= 0; --i)
        for (int j = d - i; j >= 0; --j) {
          int k = d - i - j;
          double c = p.coeff(i, j, k);
          if (c != 0) out << ",\n  xyz(" << i << ", " << j << ", " << k << "): " << c;
        }
    out << "\n  " << (sturm ? "sturm\n  " : "") << "clipped_by { sphere { " << vec(clip->center)
        << ", " << clip->radius << " } }\n  bounded_by { clipped_by }\n";
    out << "  texture { " << texture(item.material) << " }\n";
    if (item.backMaterial >= 0)
      out << "  interior_texture { " << texture(item.backMaterial) << " }\n";
    out << "}\n";
  }
  // Meshes as mesh2 in scene space, the same triangles (and vertex normals) as algray's
  // (every 2-triangle mesh was written as an infinite plane through the transform's z
  // axis: a vertical wall became the floor).
  for (const MeshItem& item : scene.meshes) {
    MeshData m = item.mesh;
    m.transform(item.transform);
    out << "mesh2 {\n  vertex_vectors { " << m.positions.size();
    for (const glm::dvec3& v : m.positions) out << ", " << vec(v);
    out << " }\n";
    if (!m.normals.empty()) {
      out << "  normal_vectors { " << m.normals.size();
      for (const glm::dvec3& v : m.normals) out << ", " << vec(v);
      out << " }\n";
    }
    out << "  face_indices { " << m.triangles.size();
    for (const auto& t : m.triangles) out << ", <" << t[0] << ", " << t[1] << ", " << t[2] << ">";
    out << " }\n  texture { " << texture(item.material) << " }\n";
    if (item.backMaterial >= 0)
      out << "  interior_texture { " << texture(item.backMaterial) << " }\n";
    out << "}\n";
  }
  return out.str();
}

}  // namespace algray::render
