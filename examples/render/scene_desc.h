#pragma once
// A scene as plain data, before anything is built: what the JSON loader, the jsurf
// importer, the default scene and quick mode produce, and what Scene builds into Embree.
#include "camera.h"
#include "material.h"
#include "mesh.h"

#include <algray/embree.h>
#include <algray/polynomial.h>

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace algray::render {

// Surfer: jsurf's own shading of the first hit (SceneDesc::surfer; .jsurf scenes only).
enum class IntegratorType { Path, Direct, Surfer };
// None: the values are display values already (the Surfer integrator's, as jsurf writes
// them): 8-bit files get round(255 * clamp(v)), no tone curve and no sRGB transfer curve.
enum class ToneMap { Aces, Clamp, None };

struct RenderSettings {
  int width = 640;
  int height = 400;
  int spp = 64;
  int maxDepth = 8;  // path vertices after the camera; Russian roulette from depth 3
  IntegratorType integrator = IntegratorType::Path;
  std::uint64_t seed = 0;
  int threads = 0;        // 0 = all cores
  double exposure = 0.0;  // stops, applied before tone mapping (PNG only)
  // Path tracer: largest contribution of one indirect light path (0 = no clamp). Biased,
  // but removes the caustic fireflies a few samples per pixel cannot average out.
  double clampIndirect = 0.0;
  ToneMap toneMap = ToneMap::Aces;
};

struct SurfaceItem {
  std::string label;  // where it came from, for messages
  Polynomial polynomial;
  ClipRegion clip = ClipSphere{};
  glm::dmat4 transform{1.0};  // object to world
  int material = 0;
  int backMaterial = -1;  // -1: same as material; back = where the gradient points away
};

struct MeshItem {
  std::string label;
  MeshData mesh;  // object space
  glm::dmat4 transform{1.0};
  int material = 0;
  int backMaterial = -1;
};

struct PointLight {
  glm::dvec3 position{0.0};
  glm::dvec3 intensity{1.0};  // radiant intensity, W/sr per channel
};
struct DirectionalLight {
  glm::dvec3 direction{0, 0, 1};  // towards the light
  glm::dvec3 irradiance{1.0};     // on a surface facing the light
};

struct EnvironmentDesc {
  glm::dvec3 color{0.0};  // constant radiance
  std::string image;      // optional lat-long image (z up), multiplies color
  double rotation = 0.0;  // degrees about z
};

// jsurf's Phong shading (IMAGINARY/jsurf rendering/cpu/Shader.java, LightProducts.java,
// CPUAlgebraicSurfaceRenderer.collectDrawCallStaticData), for IntegratorType::Surfer.
struct SurferMaterial {
  glm::dvec3 ambient{0.0};  // the side's colour x the FRONT material's ambient intensity
  glm::dvec3 diffuse{0.0};  // colour x diffuse intensity
  double specular = 0.0;    // specular intensity (the highlight has the light's colour)
  double shininess = 1.0;
};
struct SurferLight {
  glm::dvec3 position{0.0};  // world (jsurf's camera-space position carried to the world)
  glm::dvec3 color{1.0};     // colour x intensity
};
struct SurferShading {
  SurferMaterial front, back;
  std::vector<SurferLight> lights;  // those that are ON
};

struct SceneDesc {
  std::string name = "scene";
  RenderSettings settings;
  CameraDesc camera;
  std::vector<Material> materials;
  std::vector<SurfaceItem> surfaces;
  std::vector<MeshItem> meshes;
  std::vector<PointLight> pointLights;
  std::vector<DirectionalLight> directionalLights;
  EnvironmentDesc environment;
  // What camera rays that miss everything see; unset = the environment itself.
  bool hasBackground = false;
  glm::dvec3 background{0.0};
  // Set by the .jsurf import: what IntegratorType::Surfer shades every surface with.
  std::optional<SurferShading> surfer;

  int addMaterial(const Material& m) {
    materials.push_back(m);
    return static_cast<int>(materials.size()) - 1;
  }
};

}  // namespace algray::render
