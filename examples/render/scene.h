#pragma once
// A built scene: one Embree scene holding triangle meshes and algebraic surfaces
// (algray::SurfaceGeometry, exactly as any host attaches user geometry), the material
// of every geometry and the light tables used for next-event estimation.
#include "scene_desc.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace algray::render {

struct Hit {
  double t = 0;
  glm::dvec3 p{0.0};
  glm::dvec3 ng{0.0};  // unit geometric normal as stored (not flipped towards the ray)
  glm::dvec3 ns{0.0};  // unit shading normal, same hemisphere as ng
  glm::dvec2 uv{0.0};
  bool latLongUv = false;  // uv are lat-long coordinates (a surface's, the icosphere's)
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = RTC_INVALID_GEOMETRY_ID;
  bool isSurface = false;  // algebraic surface: rays leave exactly from p
  double offset = 0;       // triangles: how far to push spawned origins along ng
};

struct RayCounter {
  std::uint64_t rays = 0;
};

// A sampled point on a light, as seen from a shading point.
struct LightSample {
  glm::dvec3 wi{0.0};        // unit direction towards the light
  double distance = 0;       // infinity for directional and environment lights
  glm::dvec3 radiance{0.0};  // incident radiance (or irradiance-like for delta lights)
  double pdf = 0;            // solid-angle pdf; 1 for delta lights
  bool delta = false;        // point or directional: no MIS
  bool isSurface = false;    // sample lies on geometry that is an algebraic surface
  double extent = 0;         // an emitter's size there (its triangle's); 0 for none
};

class Scene {
 public:
  // Throws std::runtime_error (or algray::Error from the plugin) with the item's label.
  explicit Scene(const SceneDesc& desc);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const SceneDesc& desc() const { return desc_; }

  std::optional<Hit> intersect(const glm::dvec3& org, const glm::dvec3& dir, double tnear,
                               RayCounter& counter) const;
  bool occluded(const glm::dvec3& org, const glm::dvec3& dir, double tnear, double tfar,
                RayCounter& counter) const;
  // Origin for a ray leaving `hit` in direction dir: the hit itself on algebraic surfaces
  // (the plugin excludes the self-root), pushed off along ng on triangles (pbrt-v4
  // Sec. 6.8.6).
  glm::dvec3 spawnOrigin(const Hit& hit, const glm::dvec3& dir) const;

  const Material& material(const Hit& hit, bool frontFace) const;
  glm::dvec3 environment(const glm::dvec3& dir) const;
  // environment(dir) averaged over all directions (computed once, when the scene is built):
  // the colour times the image's solid-angle mean; a rotation does not change it.
  glm::dvec3 environmentMean() const { return envMean_; }
  glm::dvec3 background(const glm::dvec3& dir) const;

  // Next-event estimation samples every light of the table once per vertex (few lights:
  // better than choosing one, which leaves dark pixels at low sample counts).
  int lightCount() const;
  bool isEnvironmentLight(int light) const { return light == envLight_; }
  std::optional<LightSample> sampleLight(int light, const glm::dvec3& p, glm::dvec2 u) const;
  // Solid-angle pdf with which sampleLight picks the direction from p to `hit` (on an
  // emitter); 0 when the emitter is not in the light table.
  double lightPdf(const glm::dvec3& p, const Hit& hit) const;
  // Same for a ray that escaped to the environment.
  double environmentPdf() const;
  // The world point the scene is built and rendered about: the centre of the geometry's
  // bounds where the scene lies more than 16 times its own size from the world origin,
  // else 0. desc() is the described scene moved by -frameOrigin() (camera, point lights,
  // meshes and surfaces), so hit points, spawned rays and Embree's float coordinates are
  // relative to the scene's size, not to its distance from the world origin (a unit sphere
  // on a floor moved 1e5 away cast shadows 0.38 off: mesh hits pushed spawned origins 64
  // float ulps of 1e5 off the floor; from 1e8 most pixels were wrong).
  const glm::dvec3& frameOrigin() const { return frameOrigin_; }
  // The labels of the algebraic surfaces with no point in their clip region (the plugin's
  // range bounds proved every cell empty: SurfaceGeometry::primitiveCount() is 0), so
  // that a tool can say why they are not in the picture.
  const std::vector<std::string>& emptySurfaces() const { return emptySurfaces_; }
  // "LABEL: why" for each surface that is rounding noise through much of its clip region
  // (rounding_noise.h).
  const std::vector<std::string>& noisySurfaces() const { return noisySurfaces_; }
  // The other algebraic surfaces (geometry ID and label), for a tool to tell which of them
  // no camera ray saw (RenderStats::seen).
  struct DrawnSurface {
    unsigned geomID;
    std::string label;
  };
  const std::vector<DrawnSurface>& drawnSurfaces() const { return drawnSurfaces_; }

 private:
  struct Geom;
  struct Light;
  void build();             // the constructor's work
  void moveToFrame();       // chooses frameOrigin_ and moves desc_ by it
  void release() noexcept;  // the destructor's, also when build() throws
  SceneDesc desc_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<std::unique_ptr<Geom>> geoms_;  // indexed by geomID
  std::vector<Light> lights_;
  std::vector<int> geomLight_;  // geomID -> light index or -1
  int envLight_ = -1;
  std::shared_ptr<const Texture> envImage_;
  glm::dvec3 envMean_{0.0};
  glm::dvec3 frameOrigin_{0.0};
  std::vector<std::string> emptySurfaces_;
  std::vector<std::string> noisySurfaces_;
  std::vector<DrawnSurface> drawnSurfaces_;
};

}  // namespace algray::render
