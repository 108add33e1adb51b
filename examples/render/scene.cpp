#include "scene.h"

#include "rounding_noise.h"
#include "sampling.h"
#include "value_checks.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>

namespace algray::render {

struct Scene::Geom {
  bool isSurface = false;
  bool surfaceUv = false;  // the surface's hits carry the plugin's u, v (a textured material)
  int material = 0;
  int backMaterial = -1;
  MeshData mesh;  // world space (triangles only)
  std::unique_ptr<SurfaceGeometry> surface;
};

struct Scene::Light {
  enum class Type { Point, Directional, Mesh, Environment } type;
  int index = 0;            // point/directional list index or geomID
  std::vector<double> cdf;  // mesh: cumulative triangle areas
  double area = 0;
  glm::dvec3 emission{0.0};
  // Mesh of a convex solid (MeshData::convexClosed): a point of its vertices' convex hull
  // and the squared radius of a ball about it holding every vertex; 0 for other meshes.
  glm::dvec3 center{0.0};
  double outsideRadius2 = 0;
};

namespace {

void deviceError(void* userPtr, RTCError code, const char* str) {
  auto* message = static_cast<std::string*>(userPtr);
  if (message->empty())
    *message = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (str ? str : "");
}

// Embree keeps this string pointer; one per process is enough for our messages.
std::string gEmbreeError;

constexpr double kFloatEps = 0x1p-24;  // unit roundoff of float (Embree's ray precision)

// Embree's ray.valid(): every component of the float origin and direction within
// +-FLT_LARGE (1.844e18) and tnear, tfar not NaN; a ray outside it aborts the process on
// an assertion inside rtcIntersect1/rtcOccluded1. The loaders keep scenes far inside this
// range (value_checks.h); this is the safety net for whatever still gets here (a NaN
// from a degenerate sample, a film corner of an extreme orthographic camera): such a ray
// sees nothing.
bool embreeAccepts(const RTCRay& ray) {
  constexpr float kLarge = 1.8e18f;
  for (float v : {ray.org_x, ray.org_y, ray.org_z, ray.dir_x, ray.dir_y, ray.dir_z})
    if (!(std::abs(v) <= kLarge)) return false;
  return !std::isnan(ray.tnear) && !std::isnan(ray.tfar);
}

}  // namespace

Scene::Scene(const SceneDesc& desc) : desc_(desc) {
  // A constructor that throws runs no destructor: the Embree objects made so far are
  // released here (a surface the plugin refused leaked the device and scene; LeakSanitizer).
  try {
    build();
  } catch (...) {
    release();
    throw;
  }
}

void Scene::build() {
  if (desc_.settings.integrator == IntegratorType::Surfer && !desc_.surfer)
    throw std::runtime_error(
        "the surfer integrator shades .jsurf scenes only (it needs their jsurf materials)");
  if (desc_.materials.empty()) desc_.addMaterial(Material{});
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("cannot create the Embree device");
  rtcSetDeviceErrorFunction(device_, deviceError, &gEmbreeError);
  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  auto checkMaterial = [&](int m, const std::string& label) {
    if (m < -1 || m >= static_cast<int>(desc_.materials.size()))
      throw std::runtime_error(label + ": material index out of range");
  };

  moveToFrame();

  // ---- Triangle meshes -------------------------------------------------------------
  for (const MeshItem& item : desc_.meshes) {
    checkMaterial(item.material, item.label);
    checkMaterial(item.backMaterial, item.label);
    auto g = std::make_unique<Geom>();
    g->material = item.material;
    g->backMaterial = item.backMaterial;
    g->mesh = item.mesh;
    g->mesh.transform(item.transform);
    g->mesh.validate(item.label);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          g->mesh.positions.size()));
    for (size_t i = 0; i < g->mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(g->mesh.positions[i][k]);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), g->mesh.triangles.size()));
    for (size_t i = 0; i < g->mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = g->mesh.triangles[i][k];
    rtcCommitGeometry(geom);
    unsigned id = rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    if (geoms_.size() <= id) geoms_.resize(id + 1);
    geoms_[id] = std::move(g);
  }

  // ---- Algebraic surfaces: algray user geometry --------------------------------------
  for (const SurfaceItem& item : desc_.surfaces) {
    checkMaterial(item.material, item.label);
    checkMaterial(item.backMaterial, item.label);
    auto g = std::make_unique<Geom>();
    g->isSurface = true;
    g->material = item.material;
    g->backMaterial = item.backMaterial;
    SurfaceDesc sd;
    sd.polynomial = item.polynomial;
    sd.clip = item.clip;
    sd.transform = item.transform;
    // The surface's u, v (its spherical parametrisation) only where a texture reads them:
    // an untextured surface skips the atan2/acos of every hit.
    auto textured = [&](int m) {
      return m >= 0 && desc_.materials[static_cast<size_t>(m)].texture != nullptr;
    };
    sd.options.uv = g->surfaceUv = textured(item.material) || textured(item.backMaterial);
    try {
      g->surface = std::make_unique<SurfaceGeometry>(device_, std::move(sd));
    } catch (const Error& e) {  // the plugin refused the surface: bad input, exit code 2
      throw Error(item.label + ": " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error(item.label + ": " + e.what());
    }
    const bool empty = g->surface->primitiveCount() == 0;
    if (empty) emptySurfaces_.push_back(item.label);
    if (!empty) {
      if (std::string noise = cli::noiseWarning(item.polynomial, item.clip); !noise.empty())
        noisySurfaces_.push_back(item.label + ": " + noise);
    }
    unsigned id = rtcAttachGeometry(scene_, g->surface->geometry());
    if (!empty) drawnSurfaces_.push_back({id, item.label});
    if (geoms_.size() <= id) geoms_.resize(id + 1);
    geoms_[id] = std::move(g);
  }
  rtcCommitScene(scene_);
  if (!gEmbreeError.empty()) {
    std::string message = gEmbreeError;
    gEmbreeError.clear();
    throw std::runtime_error(message);
  }

  // ---- Light table -----------------------------------------------------------------
  geomLight_.assign(geoms_.size(), -1);
  for (size_t i = 0; i < desc_.pointLights.size(); ++i)
    lights_.push_back({Light::Type::Point, static_cast<int>(i), {}, 0, {}});
  for (size_t i = 0; i < desc_.directionalLights.size(); ++i)
    lights_.push_back({Light::Type::Directional, static_cast<int>(i), {}, 0, {}});
  for (size_t id = 0; id < geoms_.size(); ++id) {
    const Geom* g = geoms_[id].get();
    if (!g || g->isSurface) continue;  // emissive algebraic surfaces: found by BSDF rays only
    const Material& m = desc_.materials[g->material];
    if (m.type != MaterialType::Emissive || luminance(m.emission) <= 0) continue;
    Light light{Light::Type::Mesh, static_cast<int>(id), {}, 0, m.emission};
    for (const auto& t : g->mesh.triangles) {
      const auto& p = g->mesh.positions;
      light.area += 0.5 * glm::length(glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]));
      light.cdf.push_back(light.area);
    }
    if (!(light.area > 0)) continue;
    if (g->mesh.convexClosed) {
      for (const glm::dvec3& v : g->mesh.positions) light.center += v;
      light.center /= static_cast<double>(g->mesh.positions.size());
      for (const glm::dvec3& v : g->mesh.positions)
        light.outsideRadius2 =
            std::max(light.outsideRadius2, glm::dot(v - light.center, v - light.center));
    }
    geomLight_[id] = static_cast<int>(lights_.size());
    lights_.push_back(std::move(light));
  }
  if (!desc_.environment.image.empty()) envImage_ = Texture::load(desc_.environment.image);
  envMean_ = desc_.environment.color * (envImage_ ? envImage_->latLongMean() : glm::dvec3(1.0));
  // A constant environment is best found by BSDF sampling alone (cosine sampling is
  // exact importance sampling of it for diffuse surfaces, and glossy lobes only lose to
  // uniform light samples); only an image environment joins next-event estimation.
  if (envImage_ && luminance(desc_.environment.color) > 0) {
    envLight_ = static_cast<int>(lights_.size());
    lights_.push_back({Light::Type::Environment, 0, {}, 0, {}});
  }
}

void Scene::moveToFrame() {
  // ---- Bounds of the geometry: mesh vertices, surfaces' clip regions -----------------
  constexpr double kInf = std::numeric_limits<double>::infinity();
  glm::dvec3 lo(kInf), hi(-kInf);
  auto include = [&](const glm::dmat4& m, const glm::dvec3& p) {
    const glm::dvec3 q(m * glm::dvec4(p, 1.0));
    lo = glm::min(lo, q), hi = glm::max(hi, q);
  };
  for (const MeshItem& item : desc_.meshes)
    for (const glm::dvec3& p : item.mesh.positions) include(item.transform, p);
  for (const SurfaceItem& item : desc_.surfaces) {
    const auto [clipLo, clipHi] = std::visit(
        [](const auto& clip) -> std::pair<glm::dvec3, glm::dvec3> {
          if constexpr (requires { clip.radius; })
            return {clip.center - clip.radius, clip.center + clip.radius};
          else
            return {clip.lo, clip.hi};
        },
        item.clip);
    for (int corner = 0; corner < 8; ++corner)
      include(item.transform, {corner & 1 ? clipHi.x : clipLo.x, corner & 2 ? clipHi.y : clipLo.y,
                               corner & 4 ? clipHi.z : clipLo.z});
  }
  // ---- The frame: the bounds' centre where every point gains 3 bits ------------------
  // About their centre c, the bounds' points p have |p - c| <= sqrt(3) h (h the largest
  // half extent), and |p| >= |c| - sqrt(3) h: from |c| > 16 h on, every point's distance
  // to the frame shrinks 8-fold or more. Nearer, a point near the world origin could lose
  // what the others gain (a small object at the origin beside a floor 1e4 long); such
  // scenes keep their images exactly.
  const glm::dvec3 center = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const double h = std::max({half.x, half.y, half.z});
  if (!std::isfinite(glm::length(center) + h) || !(glm::length(center) > 16.0 * h)) return;
  frameOrigin_ = center;

  // ---- Everything placed in the world moves by -c ---------------------------------
  const glm::dmat4 shift = glm::translate(glm::dmat4(1.0), -center);
  desc_.camera.position -= center;
  desc_.camera.lookAt -= center;
  for (PointLight& light : desc_.pointLights) light.position -= center;
  if (desc_.surfer)
    for (SurferLight& light : desc_.surfer->lights) light.position -= center;
  for (MeshItem& item : desc_.meshes) item.transform = shift * item.transform;
  for (SurfaceItem& item : desc_.surfaces) item.transform = shift * item.transform;
}

Scene::~Scene() { release(); }

void Scene::release() noexcept {
  if (scene_) rtcReleaseScene(scene_);
  scene_ = nullptr;
  geoms_.clear();  // SurfaceGeometry releases its geometry before the device goes
  if (device_) rtcReleaseDevice(device_);
  device_ = nullptr;
}

std::optional<Hit> Scene::intersect(const glm::dvec3& org, const glm::dvec3& dir, double tnear,
                                    RayCounter& counter) const {
  ++counter.rays;
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(org.x);
  rh.ray.org_y = static_cast<float>(org.y);
  rh.ray.org_z = static_cast<float>(org.z);
  rh.ray.dir_x = static_cast<float>(dir.x);
  rh.ray.dir_y = static_cast<float>(dir.y);
  rh.ray.dir_z = static_cast<float>(dir.z);
  rh.ray.tnear = static_cast<float>(tnear);
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  if (!embreeAccepts(rh.ray)) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.geomID >= geoms_.size())
    return std::nullopt;
  const Geom* g = geoms_[rh.hit.geomID].get();
  if (!g) return std::nullopt;

  Hit hit;
  hit.t = rh.ray.tfar;
  hit.geomID = rh.hit.geomID;
  hit.primID = rh.hit.primID;
  glm::dvec3 forg(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
  glm::dvec3 fdir(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
  if (g->isSurface) {
    // The point on the ray Embree traced; the adapter's Ng is the world-space gradient
    // (object gradient through the inverse transpose), i.e. the surface normal.
    hit.isSurface = true;
    hit.p = forg + hit.t * fdir;
    glm::dvec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    double len = glm::length(n);
    hit.ng = len > 0 && std::isfinite(len) ? n / len : -glm::normalize(fdir);
    hit.ns = hit.ng;
    // The plugin's u, v (azimuth / 2pi and polar angle / pi, where a texture asked for
    // them) read as the environment reads a lat-long image, as the icosphere's: the image's
    // centre column at +x and top row at +z (v = 0 read the bottom row at +z, the image
    // upside down, until session 52).
    if (g->surfaceUv) hit.uv = glm::dvec2(rh.hit.u + 0.5, 1.0 - rh.hit.v), hit.latLongUv = true;
    return hit;
  }
  const auto& t = g->mesh.triangles[hit.primID];
  const auto& P = g->mesh.positions;
  double u = rh.hit.u, v = rh.hit.v, w = 1.0 - u - v;
  hit.p = w * P[t[0]] + u * P[t[1]] + v * P[t[2]];
  glm::dvec3 n = glm::cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
  double len = glm::length(n);
  hit.ng = len > 0 ? n / len : -glm::normalize(fdir);
  hit.ns = hit.ng;
  if (!g->mesh.normals.empty()) {
    const auto& N = g->mesh.normals;
    glm::dvec3 ns = w * N[t[0]] + u * N[t[1]] + v * N[t[2]];
    double l = glm::length(ns);
    if (l > 0) hit.ns = glm::dot(ns, hit.ng) < 0 ? -ns / l : ns / l;
  }
  if (!g->mesh.uvs.empty()) {
    const auto& T = g->mesh.uvs;
    hit.uv = w * T[t[0]] + u * T[t[1]] + v * T[t[2]];
    hit.latLongUv = g->mesh.latLongUv;
  }
  // Error bound of the hit point: Embree intersects in float, so the point it found may
  // be off the plane of the triangle by a few float ulps of the vertex magnitude (pbrt-v4
  // Sec. 6.8 bounds this per component; a per-component bound vanishes for vertices with
  // a zero coordinate, e.g. a floor at z = 0, while Embree's t still carries float
  // error). Relative to the largest vertex coordinate, with a margin for the float
  // conversion of the spawned origin.
  double scale = 0;
  for (int k = 0; k < 3; ++k)
    scale = std::max({scale, std::abs(P[t[0]][k]), std::abs(P[t[1]][k]), std::abs(P[t[2]][k])});
  hit.offset = 64.0 * kFloatEps * scale;
  return hit;
}

bool Scene::occluded(const glm::dvec3& org, const glm::dvec3& dir, double tnear, double tfar,
                     RayCounter& counter) const {
  ++counter.rays;
  RTCRay ray{};
  ray.org_x = static_cast<float>(org.x);
  ray.org_y = static_cast<float>(org.y);
  ray.org_z = static_cast<float>(org.z);
  ray.dir_x = static_cast<float>(dir.x);
  ray.dir_y = static_cast<float>(dir.y);
  ray.dir_z = static_cast<float>(dir.z);
  ray.tnear = static_cast<float>(tnear);
  ray.tfar = static_cast<float>(tfar);
  ray.mask = 0xFFFFFFFFu;
  if (!embreeAccepts(ray)) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar = -inf on a hit
}

glm::dvec3 Scene::spawnOrigin(const Hit& hit, const glm::dvec3& dir) const {
  if (hit.isSurface) return hit.p;
  return hit.p + (glm::dot(dir, hit.ng) > 0 ? hit.offset : -hit.offset) * hit.ng;
}

const Material& Scene::material(const Hit& hit, bool frontFace) const {
  const Geom* g = geoms_[hit.geomID].get();
  int m = (!frontFace && g->backMaterial >= 0) ? g->backMaterial : g->material;
  return desc_.materials[m];
}

glm::dvec3 Scene::environment(const glm::dvec3& dir) const {
  glm::dvec3 c = desc_.environment.color;
  if (envImage_) {
    // Lat-long map, z up: u = azimuth, v = 1 at the zenith.
    // Whole turns out first, exactly (fmod is exact): 360 * 2^60 degrees times pi / 180
    // kept none of the fraction of a turn and rendered up to 0.22 off a rotation of 0.
    const double turn = std::fmod(desc_.environment.rotation, 360.0);
    double phi = std::atan2(dir.y, dir.x) - turn * kPi / 180.0;
    double theta = std::acos(std::clamp(dir.z, -1.0, 1.0));
    c *= envImage_->lookupLatLong({0.5 + phi / (2 * kPi), 1.0 - theta / kPi});
  }
  return c;
}

glm::dvec3 Scene::background(const glm::dvec3& dir) const {
  return desc_.hasBackground ? desc_.background : environment(dir);
}

int Scene::lightCount() const { return static_cast<int>(lights_.size()); }

double Scene::environmentPdf() const { return envLight_ < 0 ? 0.0 : kUniformSpherePdf; }

std::optional<LightSample> Scene::sampleLight(int index, const glm::dvec3& p, glm::dvec2 u) const {
  if (index < 0 || index >= lightCount()) return std::nullopt;
  const Light& light = lights_[index];
  const double select = 1.0;
  LightSample s;
  switch (light.type) {
    case Light::Type::Point: {
      const PointLight& pl = desc_.pointLights[light.index];
      glm::dvec3 d = pl.position - p;
      double d2 = glm::dot(d, d);
      if (!(d2 > 0)) return std::nullopt;
      s.distance = std::sqrt(d2);
      s.wi = d / s.distance;
      s.radiance = pl.intensity / d2;
      s.pdf = select;
      s.delta = true;
      return s;
    }
    case Light::Type::Directional: {
      const DirectionalLight& dl = desc_.directionalLights[light.index];
      // The loaders check that the direction normalises; safeNormalize also where a
      // glm::normalize would overflow or underflow (components beyond 1e154 or below 1e-154).
      const std::optional<glm::dvec3> wi = safeNormalize(dl.direction);
      if (!wi) return std::nullopt;
      s.wi = *wi;
      s.distance = std::numeric_limits<double>::infinity();
      s.radiance = dl.irradiance;
      s.pdf = select;
      s.delta = true;
      return s;
    }
    case Light::Type::Mesh: {
      const Geom* g = geoms_[light.index].get();
      // Triangle by area (binary search in the CDF), then a uniform point on it.
      double target = u.x * light.area;
      auto it = std::upper_bound(light.cdf.begin(), light.cdf.end(), target);
      size_t tri = std::min(static_cast<size_t>(it - light.cdf.begin()), light.cdf.size() - 1);
      double lo = tri == 0 ? 0.0 : light.cdf[tri - 1];
      double width = light.cdf[tri] - lo;
      double ux = width > 0 ? std::clamp((target - lo) / width, 0.0, 1.0 - 0x1p-53) : 0.5;
      glm::dvec2 b = sampleUniformTriangle({ux, u.y});
      const auto& t = g->mesh.triangles[tri];
      const auto& P = g->mesh.positions;
      glm::dvec3 q = (1 - b.x - b.y) * P[t[0]] + b.x * P[t[1]] + b.y * P[t[2]];
      glm::dvec3 nl = glm::cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
      double nlLen = glm::length(nl);
      glm::dvec3 d = q - p;
      double d2 = glm::dot(d, d);
      if (!(d2 > 0) || !(nlLen > 0)) return std::nullopt;
      // The far side of a convex emitter, seen from a point outside it (beyond the ball
      // about its vertices), lies behind its near side: q is on a face whose plane has p
      // on the inner side, so the segment from q enters the solid. Such a sample adds
      // nothing, exactly; not tracing it spares a shadow ray, and the shadow ray's gap
      // (integrator.cpp: at least 2^-20 of the coordinates) exceeds an emitter smaller than
      // that, which let far-side samples through (a sphere light of radius 3e-7 shone
      // twice as bright as its point light).
      if (light.outsideRadius2 > 0 &&
          glm::dot(p - light.center, p - light.center) > light.outsideRadius2) {
        const double outward = glm::dot(nl, q - light.center), towardP = glm::dot(nl, p - q);
        if ((outward > 0 && towardP < 0) || (outward < 0 && towardP > 0)) return std::nullopt;
      }
      s.distance = std::sqrt(d2);
      s.wi = d / s.distance;
      double cosL = std::abs(glm::dot(nl / nlLen, s.wi));
      if (!(cosL > 0)) return std::nullopt;
      s.radiance = light.emission;  // two-sided emitter
      s.pdf = select * d2 / (cosL * light.area);
      s.extent = std::sqrt(nlLen);  // ~ the triangle's edge
      return s;
    }
    case Light::Type::Environment: {
      s.wi = sampleUniformSphere(u);
      s.distance = std::numeric_limits<double>::infinity();
      s.radiance = environment(s.wi);
      s.pdf = select * kUniformSpherePdf;
      return s;
    }
  }
  return std::nullopt;
}

double Scene::lightPdf(const glm::dvec3& p, const Hit& hit) const {
  if (hit.geomID >= geomLight_.size() || geomLight_[hit.geomID] < 0) return 0.0;
  const Light& light = lights_[geomLight_[hit.geomID]];
  glm::dvec3 d = hit.p - p;
  double d2 = glm::dot(d, d);
  double cosL = std::abs(glm::dot(hit.ng, d)) / std::sqrt(d2);
  if (!(cosL > 0)) return 0.0;
  return d2 / (cosL * light.area);
}

}  // namespace algray::render
