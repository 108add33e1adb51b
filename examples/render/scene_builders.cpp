#include "scene_builders.h"

#include "sampling.h"
#include "scene.h"
#include "value_checks.h"

#include <algray/gallery.h>
#include <algray/parser.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

namespace algray::render {

namespace {

// What to add to the parser's message when --surface was meant as a gallery name
// ("barth_sextic", "Barth sextic" are found; "barth", "chmutov8" are not): the names close
// to it, or for a single word of three letters or more, all of them.
std::string galleryHint(const std::string& text) {
  const std::string similar = similarGallerySurfacesText(text);
  if (!similar.empty()) return " (or did you mean " + similar + "?)";
  const bool word = text.size() >= 3 && std::all_of(text.begin(), text.end(), [](unsigned char ch) {
                      return std::isalnum(ch) || ch == '-' || ch == '_';
                    });
  return word ? " (nor is it a gallery surface: " + galleryNames() + ")" : "";
}

// A soft grey checkerboard, 8x8 squares, as a texture so the floor shows perspective.
std::shared_ptr<const Texture> checkerTexture(glm::vec3 a, glm::vec3 b) {
  const int n = 64;
  std::vector<glm::vec3> texels(n * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) texels[y * n + x] = ((x / 8 + y / 8) % 2) ? a : b;
  return std::make_shared<Texture>(n, n, std::move(texels));
}

// Object-to-world map that puts a clip sphere of radius r (about the origin) at `center`
// with radius `size`.
glm::dmat4 placeSphere(glm::dvec3 center, double r, double size, double yawDegrees = 0) {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), center);
  m = glm::rotate(m, glm::radians(yawDegrees), glm::dvec3(0, 0, 1));
  return glm::scale(m, glm::dvec3(size / r));
}

// Lowest point of a placed surface, found by tracing a grid of upward rays through its
// clip sphere with algray itself, so that each surface can stand on the floor.
double lowestPoint(const SurfaceItem& item, double radius) {
  SceneDesc probe;
  probe.surfaces.push_back(item);
  Scene scene(probe);
  glm::dvec3 c(item.transform * glm::dvec4(std::get<ClipSphere>(item.clip).center, 1.0));
  RayCounter counter;
  double lowest = c.z;  // nothing hit: keep the centre on the floor
  const int n = 48;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      glm::dvec3 org =
          c + glm::dvec3(radius * (2.0 * i / n - 1.0), radius * (2.0 * j / n - 1.0), -2.0 * radius);
      if (auto hit = scene.intersect(org, {0, 0, 1}, 0.0, counter))
        lowest = std::min(lowest, hit->p.z);
    }
  return lowest;
}

}  // namespace

SceneDesc defaultScene() {
  SceneDesc scene;
  scene.name = "default scene";
  scene.settings.width = 640;
  scene.settings.height = 400;
  scene.settings.spp = 16;  // a few seconds on two cores
  scene.settings.maxDepth = 5;
  scene.settings.clampIndirect = 4.0;
  scene.camera.position = {0.0, -8.2, 3.4};
  scene.camera.lookAt = {0.0, 0.0, 0.75};
  scene.camera.fovY = 33.0;

  // ---- Materials -------------------------------------------------------------------
  Material floor;
  floor.color = glm::dvec3(1.0);
  floor.texture = checkerTexture({0.62f, 0.62f, 0.60f}, {0.42f, 0.42f, 0.41f});
  int floorMat = scene.addMaterial(floor);
  Material gold{MaterialType::Conductor, {1.0, 0.71, 0.29}, 0.5, 1.5, {}, nullptr};
  Material coral{MaterialType::Diffuse, {0.80, 0.25, 0.20}, 0.3, 1.5, {}, nullptr};
  Material teal{MaterialType::Diffuse, {0.12, 0.50, 0.55}, 0.3, 1.5, {}, nullptr};
  Material violet{MaterialType::Diffuse, {0.45, 0.30, 0.70}, 0.3, 1.5, {}, nullptr};
  Material steel{MaterialType::Conductor, {0.75, 0.76, 0.78}, 0.2, 1.5, {}, nullptr};
  std::vector<int> surfaceMats = {scene.addMaterial(gold), scene.addMaterial(coral),
                                  scene.addMaterial(teal), scene.addMaterial(violet)};
  Material back{MaterialType::Diffuse, {0.85, 0.80, 0.55}, 0.3, 1.5, {}, nullptr};
  int backMat = scene.addMaterial(back);
  int sphereMat = scene.addMaterial(steel);

  // ---- Floor and a triangle-mesh object ----------------------------------------------
  MeshItem plane{"default scene: floor", makePlane(40.0, 2.0), glm::dmat4(1.0), floorMat, -1};
  scene.meshes.push_back(plane);
  MeshItem ball{"default scene: icosphere", makeIcosphere(4),
                placeSphere({3.15, 0.6, 0.7}, 1.0, 0.7), sphereMat, -1};
  scene.meshes.push_back(ball);

  // ---- Gallery surfaces of different degrees (whatever the gallery holds of these) ----
  const char* preferred[] = {"clebsch-cubic",  "torus",       "barth-sextic", "chmutov-8",
                             "kummer-quartic", "barth-decic", "cayley-cubic"};
  std::vector<const GallerySurface*> chosen;
  std::set<int> degrees;
  auto tryAdd = [&](const GallerySurface* g) {
    if (!g || chosen.size() >= 3) return;
    int degree = g->build().degree();
    if (degrees.count(degree)) return;
    degrees.insert(degree);
    chosen.push_back(g);
  };
  for (const char* name : preferred) tryAdd(findGallerySurface(name));
  for (const GallerySurface& g : gallery()) tryAdd(&g);
  std::sort(chosen.begin(), chosen.end(),
            [](auto* a, auto* b) { return a->build().degree() < b->build().degree(); });
  const glm::dvec2 spots[] = {{-2.9, 0.0}, {-0.85, 0.5}, {1.15, 0.0}};
  const double yaw[] = {25.0, 0.0, 20.0};
  const double size = 1.05;
  for (size_t i = 0; i < chosen.size(); ++i) {
    const GallerySurface* g = chosen[i];
    SurfaceItem s;
    s.label = "default scene: gallery surface '" + std::string(g->name) + "'";
    s.polynomial = g->build();
    s.clip = ClipSphere{glm::dvec3(0.0), g->clipRadius};
    s.transform = placeSphere({spots[i], 0.0}, g->clipRadius, size, yaw[i]);
    // Stand it on the floor (a hair below, so no light leaks under it).
    double lowest = lowestPoint(s, size);
    s.transform = placeSphere({spots[i], -lowest - 0.002 * size}, g->clipRadius, size, yaw[i]);
    s.material = surfaceMats[i];
    s.backMaterial = i == 0 ? -1 : backMat;
    scene.surfaces.push_back(std::move(s));
  }

  // ---- Light: a warm quad area light above-left, a dim blue sky --------------------------
  Material lamp;
  lamp.type = MaterialType::Emissive;
  lamp.emission = {14.0, 13.0, 11.5};
  int lampMat = scene.addMaterial(lamp);
  MeshItem light{"default scene: area light", makeQuad({-3.5, -3.0, 6.0}, {2.2, 0, 0}, {0, 2.2, 0}),
                 glm::dmat4(1.0), lampMat, -1};
  scene.meshes.push_back(light);
  scene.environment.color = {0.16, 0.19, 0.25};
  return scene;
}

bool evidentlyHasNoRealPoints(const Polynomial& f) {
  const double constant = f.coeff(0, 0, 0);
  if (constant == 0.0) return false;
  for (int n = 1; n <= f.degree(); ++n)
    for (int i = n; i >= 0; --i)
      for (int j = n - i; j >= 0; --j) {
        const int k = n - i - j;
        const double c = f.coeff(i, j, k);
        if (c != 0.0 && ((i | j | k) % 2 != 0 || (c > 0.0) != (constant > 0.0))) return false;
      }
  return true;
}

SceneDesc quickScene(const QuickOptions& options) {
  SceneDesc scene;
  SurfaceItem s;
  double r = options.clipRadius.value_or(0.0);
  if (options.clipRadius && !(r > 0 && std::isfinite(r))) {
    char shown[32];  // %g: std::to_string's %f showed -1e-9 as -0.000000
    std::snprintf(shown, sizeof shown, "%g", r);
    throw Error("--clip-sphere must be a positive number, got " + std::string(shown));
  }
  if (const GallerySurface* g = findGallerySurface(options.surface)) {
    // As a scene file's gallery entry: its parameters are built in, a --param is a mistake.
    if (!options.parameters.empty())
      throw ParameterError(options.parameters.begin()->first,
                           "gallery surface '" + std::string(g->name) + "' takes no parameters");
    s.polynomial = g->build();
    if (!options.clipRadius) r = g->clipRadius;
    s.label = "gallery surface '" + std::string(g->name) + "'" +
              (options.clipRadius ? " in --clip-sphere" : "");
    scene.name = g->name;
  } else {
    ParseOptions po;
    po.parameters = options.parameters;
    po.rejectUnusedParameters = true;
    try {
      s.polynomial = parsePolynomial(options.surface, po);
    } catch (const ParseError& e) {
      std::string hint = galleryHint(options.surface);
      if (hint.empty() && !e.unknownName().empty())
        hint = " (give it a value with --param " + e.unknownName() + "=VALUE)";
      throw e.withHint(hint);
    }
    if (!options.clipRadius) r = 2.0;
    // The library's refusals of the surface may be about the clip sphere's size: name it
    // when the user gave it.
    s.label = options.clipRadius ? "--surface in --clip-sphere" : "--surface";
    scene.name = "surface";
  }
  if (!(r > 0) || !std::isfinite(r)) throw Error("--clip-sphere must be a positive number");
  // The floor (40 r across) and the camera (~5 r away) must stay within what Embree's float
  // rays and triangles resolve (value_checks.h): r = 1e17 lost the floor, r = 1e-20 showed
  // only the floor, both with exit code 0.
  if (!(20.0 * r <= kMaxCoordinate))
    throw Error(
        "--clip-sphere: beyond a radius of 5e15 the quick scene's floor (40 radii across) leaves "
        "Embree's range: scale the scene down");
  if (!(40.0 * r >= kMinMeshExtent))
    throw Error(
        "--clip-sphere: below a radius of 2.5e-17 the quick scene's floor is too small for "
        "Embree's float "
        "triangles: scale the scene up");
  s.clip = ClipSphere{glm::dvec3(0.0), r};
  Material front{MaterialType::Diffuse, {0.85, 0.45, 0.15}, 0.3, 1.5, {}, nullptr};
  Material back{MaterialType::Diffuse, {0.25, 0.45, 0.80}, 0.3, 1.5, {}, nullptr};
  s.material = scene.addMaterial(front);
  s.backMaterial = scene.addMaterial(back);
  scene.surfaces.push_back(std::move(s));
  Material floor{MaterialType::Diffuse, glm::dvec3(0.6), 0.3, 1.5, {}, nullptr};
  MeshItem plane{"floor", makePlane(20.0 * r), glm::translate(glm::dmat4(1.0), {0, 0, -r}),
                 scene.addMaterial(floor), -1};
  scene.meshes.push_back(plane);
  // Camera: the clip sphere fills ~85% of the image's shorter side (framed by the height
  // alone, --width 200 made a 200 x 512 image that cut the surface off at both sides).
  scene.settings.width = options.width.value_or(options.height.value_or(512));
  scene.settings.height = options.height.value_or(options.width.value_or(512));
  scene.settings.spp = 16;
  scene.camera.fovY = 30.0;
  scene.camera.fitShorterSide = true;
  double distance = r / std::sin(0.5 * scene.camera.fovY * kPi / 180.0) / 0.85;
  scene.camera.lookAt = glm::dvec3(0.0);
  scene.camera.position = distance * glm::normalize(glm::dvec3(0.55, -1.0, 0.45));
  scene.directionalLights.push_back({glm::dvec3(-0.4, -0.6, 1.0), glm::dvec3(2.6)});
  scene.environment.color = glm::dvec3(0.25);
  scene.hasBackground = true;
  scene.background = {0.78, 0.82, 0.88};
  scene.settings.toneMap = ToneMap::Clamp;
  return scene;
}

}  // namespace algray::render
