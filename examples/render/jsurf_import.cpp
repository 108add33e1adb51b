// SURFER/jsurf import. What the keys mean, from jsurf's renderer (IMAGINARY/jsurf,
// rendering/cpu/RayCreator.java and clipping/ClipToSphere.java; Stussak 2008) and its
// loader (util/FileFormat.java):
//  * camera space -> clipping space by M = transform_matrix * rotation_matrix (4x4,
//    row-major, each the identity when absent) after the inverse camera_transform; the
//    visible region is the unit sphere of clipping space;
//  * surface space = N clipping space, N = surface_transform_matrix * 10^scale_factor (the
//    zoom slider is logarithmic: negative factors occur in the gallery files). jsurf itself
//    saves the products as transform_matrix and surface_transform_matrix (no rotation_matrix
//    or scale_factor); SURFER writes the two factors, and since it saves through jsurf's
//    FileFormat.save also the products, which SURFER's own loader ignores (as we do: a file
//    with rotation_matrix or scale_factor is a SURFER file, see jsurfScene);
//  * shading is Phong with ambient/diffuse/specular intensities (rendering/cpu/Shader.java);
//    lights are points given in camera space. The Surfer integrator (integrator.cpp) is
//    that shading; for path and direct we map Phong's diffuse term kd * I * cos onto a
//    Lambertian BRDF (albedo / pi) lit by a directional light of irradiance pi * I (the
//    gallery's lights are about 100 units away), and the ambient term onto a constant
//    environment (an unoccluded diffuse surface reflects albedo * environment).
#include "sampling.h"
#include "scene_builders.h"
#include "value_checks.h"

#include <algray/jsurf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
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

// A 4x4 key that must be affine with a well-conditioned 3x3 part (row-major, as jsurf's
// BasicIO writes a Matrix4d); the identity when absent.
glm::dmat4 affineKey(const JsurfFile& f, const std::string& key) {
  if (!f.has(key)) return glm::dmat4(1.0);
  const glm::dmat4 m = rowMajor(f.getNumbers(key, 16));
  if (m[0][3] != 0 || m[1][3] != 0 || m[2][3] != 0 || m[3][3] != 1)
    fail(f, key, "the matrix must be affine (last row 0 0 0 1), not projective");
  if (!wellConditioned(glm::dmat3(m))) fail(f, key, "singular (or out of range) matrix");
  return m;
}

// The inverse of an affine matrix with its last row exactly (0, 0, 0, 1).
glm::dmat4 affineInverse(const glm::dmat4& m) {
  const glm::dmat3 inv = glm::inverse(glm::dmat3(m));
  glm::dmat4 r(inv);
  r[3] = glm::dvec4(-(inv * glm::dvec3(m[3])), 1.0);
  return r;
}

// The uniform scale k of a 3x3 part k Q with Q a rotation (orthogonal, det +1), or nothing:
// columns of equal length, pairwise orthogonal, right-handed, to a relative 1e-6 (SURFER
// writes matrices as floats, 8 to 9 digits; such a shear is far below a pixel).
std::optional<double> similarityScale(const glm::dmat3& a) {
  const double k2 = glm::dot(a[0], a[0]);
  constexpr double kTol = 1e-6;
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(glm::dot(a[i], a[i]) - k2) <= kTol * k2)) return std::nullopt;
    if (!(std::abs(glm::dot(a[i], a[(i + 1) % 3])) <= kTol * k2)) return std::nullopt;
  }
  if (!(glm::determinant(a) > 0)) return std::nullopt;
  return std::sqrt(k2);
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
  // A SURFER file (it has rotation_matrix or scale_factor) is read as SURFER reads it, not
  // as jsurf does: SURFER's RenderArea.load() takes the view from rotation_matrix and
  // scale_factor alone, and its store() writes them beside jsurf's FileFormat.save keys,
  // transform_matrix = R and surface_transform_matrix = 10^s I: applying both pairs, as
  // jsurf's FileFormat.load does, rotated such a file twice and zoomed it 10^(2s).
  // SURFER also replaces the camera (RenderArea.setOptimalCameraDistance: the eye on +z
  // at 1, or at 1 / sin(fov / 2) for a perspective camera, looking at the origin, up +y),
  // so camera_transform is ignored there too; type, height and fov_y are read.
  const bool surferFile = f.has("rotation_matrix") || f.has("scale_factor");
  const std::string type = f.get("camera_type").value_or("ORTHOGRAPHIC_CAMERA");
  double fovY = 60.0;  // jsurf's Camera default
  if (type == "PERSPECTIVE_CAMERA") {
    fovY = f.getNumber("camera_fov_y", 60.0);
    if (!(fovY > 0 && fovY < 180)) fail(f, "camera_fov_y", "must be in (0, 180) degrees");
  } else if (type != "ORTHOGRAPHIC_CAMERA") {
    fail(f, "camera_type", "'" + type + "' is not ORTHOGRAPHIC_CAMERA or PERSPECTIVE_CAMERA");
  }
  const double surferDistance =
      type == "PERSPECTIVE_CAMERA" ? 1.0 / std::sin(fovY / 2 * kPi / 180) : 1.0;
  glm::dmat4 cameraTransform = glm::translate(glm::dmat4(1.0), {0, 0, -surferDistance});
  if (!surferFile && f.has("camera_transform")) cameraTransform = affineKey(f, "camera_transform");
  const glm::dmat4 viewTransform = surferFile ? glm::dmat4(1.0) : affineKey(f, "transform_matrix");
  const glm::dmat4 surfaceTransform =
      surferFile ? glm::dmat4(1.0) : affineKey(f, "surface_transform_matrix");
  // World = SURFER's world (camera space through the inverse camera_transform); clipping =
  // M world, M = transform_matrix * rotation_matrix; surface = N clipping, N =
  // surface_transform_matrix * scale (jsurf's FileFormat.load: transform.mul(rotation),
  // surface_transform.mul(scale)). These keys were ignored (a rendering as without them).
  if (surfaceTransform == glm::dmat4(1.0)) {
    // N = scale: the clip sphere (unit in clipping space) has radius `scale` in surface
    // space, and the polynomial stays exactly as written.
    s.transform =
        affineInverse(glm::scale(glm::dmat4(1.0), glm::dvec3(scale)) * viewTransform * rotation);
    s.clip = ClipSphere{glm::dvec3(0.0), scale};
  } else {
    // Any other N maps the clip sphere to an ellipsoid of surface space: the object space
    // is clipping space instead, with the polynomial f(N p).
    const glm::dmat4 n = surfaceTransform * glm::scale(glm::dmat4(1.0), glm::dvec3(scale));
    s.polynomial = s.polynomial.composeAffine(glm::dmat3(n), glm::dvec3(n[3]));
    s.transform = affineInverse(viewTransform * rotation);
    s.clip = ClipSphere{glm::dvec3(0.0), 1.0};
  }

  // ---- Materials -------------------------------------------------------------------------
  // jsurf's Material.loadProperties reads color, ambient_intensity, diffuse_intensity,
  // specular_intensity and shininess, each defaulting to Material()'s value: 0.5 grey, 0.1,
  // 0.23232, 0.9, 1. (23 gallery files spell the key specular_iIntensity, which jsurf does
  // not read: their highlights have the default 0.9, and so have ours.)
  struct Side {
    glm::dvec3 color;
    double ka, kd, ks, shininess;
  };
  auto side = [&](const std::string& prefix) {
    Side m;
    m.color = colorOf(f, prefix + "color", glm::dvec3(0.5));
    m.ka = nonNegative(f, prefix + "ambient_intensity", 0.1);
    m.kd = nonNegative(f, prefix + "diffuse_intensity", 0.23232);
    m.ks = nonNegative(f, prefix + "specular_intensity", 0.9);
    m.shininess = nonNegative(f, prefix + "shininess", 1.0);
    if (!isFloatColor(m.color * m.kd))
      fail(f, prefix + "diffuse_intensity", "colour times intensity beyond 3.4e38");
    return m;
  };
  const Side front = side("front_material_"), back = side("back_material_");
  // The Surfer integrator's model, as collectDrawCallStaticData builds it: both sides'
  // ambient colours take the FRONT ambient intensity.
  SurferShading surfer;
  surfer.front = {front.color * front.ka, front.color * front.kd, front.ks, front.shininess};
  surfer.back = {back.color * front.ka, back.color * back.kd, back.ks, back.shininess};
  if (!isFloatColor(surfer.back.ambient) || !isFloatColor(surfer.front.ambient))
    fail(f, "front_material_ambient_intensity", "colour times intensity beyond 3.4e38");
  // Path and direct: Phong's diffuse term kd * I * cos as a Lambertian BRDF of albedo
  // colour * kd, the ambient term as a constant environment ka / kd (approximations: no
  // highlight, and no ambient light where kd is 0).
  Material frontMaterial, backMaterial;
  frontMaterial.color = front.color * front.kd;
  backMaterial.color = back.color * back.kd;
  s.material = scene.addMaterial(frontMaterial);
  s.backMaterial = scene.addMaterial(backMaterial);
  scene.environment.color = glm::dvec3(front.kd > 0 ? front.ka / front.kd : front.ka);
  if (!isFloatColor(scene.environment.color))
    fail(f, "front_material_ambient_intensity", "ambient / diffuse intensity beyond 3.4e38");
  scene.surfaces.push_back(std::move(s));

  // ---- Camera: SURFER's camera at the origin of camera space, looking down -z ---------
  // A scale k in camera_transform scales the view by 1/k (jsurf's ray creators span the
  // view in camera space); a shear, a non-uniform scale or a mirror cannot be a camera
  // here (it was reduced to the eye and two axes, the view's size and shape lost).
  const std::optional<double> cameraScale = similarityScale(glm::dmat3(cameraTransform));
  if (!cameraScale)
    fail(f, "camera_transform",
         "only a rotation, a uniform scale and a translation are supported (no shear, "
         "non-uniform scale or mirror)");
  glm::dmat4 cameraToWorld = glm::inverse(cameraTransform);
  glm::dvec3 eye(cameraToWorld * glm::dvec4(0, 0, 0, 1));
  const std::optional<glm::dvec3> forward =
      safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 0, -1, 0)));
  const std::optional<glm::dvec3> up =
      safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(0, 1, 0, 0)));
  if (!withinCoordinateRange(eye) || !forward || !up)
    fail(f, "camera_transform", "puts the camera beyond 1e17 (Embree's float rays reach 1.8e18)");
  scene.camera.position = eye;
  // A step along forward that survives eye's rounding: eye + forward equalled eye from
  // |eye| = 2^53 on ("position and look_at must differ", exit 1, no line).
  const double reach = std::max({1.0, std::abs(eye.x), std::abs(eye.y), std::abs(eye.z)});
  scene.camera.lookAt = eye + std::max(1.0, 0x1p-20 * reach) * *forward;
  scene.camera.up = *up;
  // SURFER's view is square; in a portrait image camera_height (or the fov) spans the width,
  // so the clip sphere is whole there too (it was cut off at both sides).
  scene.camera.fitShorterSide = true;
  if (type == "PERSPECTIVE_CAMERA") {
    scene.camera.type = CameraDesc::Type::Perspective;
    scene.camera.fovY = fovY;
  } else {
    scene.camera.type = CameraDesc::Type::Orthographic;
    scene.camera.height = f.getNumber("camera_height", 2.0);
    if (!(scene.camera.height > 0)) fail(f, "camera_height", "must be positive");
    scene.camera.height /= *cameraScale;
    if (!(scene.camera.height > 0))
      fail(f, "camera_height", "divided by camera_transform's scale, underflows to 0");
    if (!withinCoordinateRange(scene.camera.height))
      fail(f, "camera_height",
           "beyond 1e17, outside the range Embree's float rays can trace (1.8e18)");
  }

  // ---- Lights (camera space) -------------------------------------------------------------
  // jsurf's Shader lights a hit point from the light's camera-space position (direction =
  // position - hit point), so a light at 0 0 0 sits at the eye. The Surfer integrator takes
  // the positions as they are; path and direct see lights about 100 units away as
  // directional ones, and one at 0 0 0 as a light towards the eye (+z of camera space).
  for (int i = 0; i < 8; ++i) {
    std::string n = std::to_string(i);
    // Colour and intensity are checked for every light, on or off: a bad value is bad input.
    glm::dvec3 color = colorOf(f, "light_color_" + n, glm::dvec3(1.0));
    double intensity = nonNegative(f, "light_intensity_" + n, 1.0);
    const glm::dvec3 irradiance = color * (intensity * kPi);
    if (!isFloatColor(irradiance))
      fail(f, "light_intensity_" + n, "colour times intensity beyond 3.4e38");
    // ON or OFF, as camera_type's values are checked ("MAYBE" rendered the light off).
    const std::string status = f.get("light_status_" + n).value_or("OFF");
    if (status != "ON" && status != "OFF")
      fail(f, "light_status_" + n, "'" + status + "' is not ON or OFF");
    if (status != "ON") continue;
    const glm::dvec3 pos = vec3Of(f, "light_position_" + n, glm::dvec3(0.0));
    // A light farther than 1e12 is brought in along its direction to 1e12 (its direction
    // from any point of the view changes by less than 1e-11): 1e308 overflowed to inf.
    const double far = std::max({std::abs(pos.x), std::abs(pos.y), std::abs(pos.z)});
    const glm::dvec3 near = far > 1e12 ? pos * (1e12 / far) : pos;
    surfer.lights.push_back({glm::dvec3(cameraToWorld * glm::dvec4(near, 1.0)), color * intensity});
    // safeNormalize: glm::normalize of 1e-200 or 1e308 components gave NaN rays.
    const std::optional<glm::dvec3> toLight =
        pos == glm::dvec3(0.0) ? glm::dvec3(0, 0, 1) : safeNormalize(pos);
    const std::optional<glm::dvec3> dirWorld =
        toLight ? safeNormalize(glm::dvec3(cameraToWorld * glm::dvec4(*toLight, 0.0)))
                : std::nullopt;
    if (!dirWorld) fail(f, "light_position_" + n, "no direction can be taken from this position");
    scene.directionalLights.push_back({*dirWorld, irradiance});
  }
  scene.surfer = std::move(surfer);
  scene.hasBackground = true;
  scene.background = colorOf(f, "background_color", glm::dvec3(1.0));
  scene.settings.width = 512;
  scene.settings.height = 512;
  scene.settings.spp = 4;
  // SURFER's look: jsurf's shading, written as jsurf writes its pixels.
  scene.settings.integrator = IntegratorType::Surfer;
  scene.settings.toneMap = ToneMap::None;
  return scene;
}

}  // namespace algray::render
