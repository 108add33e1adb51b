#include "integrator.h"

#include "value_checks.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace algray::render {

namespace {

// Shadow rays stop short of the sampled light point by this fraction of the distance,
// so that they do not report the emitter itself (pbrt-v4's ShadowEpsilon); on an emitter
// by no more than 1e-3 of its triangle's size (see shadowed).
constexpr double kShadowEpsilon = 1e-4;

struct Shading {
  Frame frame{glm::dvec3(0, 0, 1)};
  glm::dvec3 ngFacing{0.0};  // geometric normal flipped towards wo
  glm::dvec3 woLocal{0.0};
  bool frontFace = true;
};

// Two-sided shading: normals are flipped towards wo; when the interpolated shading
// normal disagrees with the geometric one about wo's side, the geometric frame is used.
Shading makeShading(const Hit& hit, const glm::dvec3& wo) {
  Shading s;
  s.frontFace = glm::dot(hit.ng, wo) > 0;
  s.ngFacing = s.frontFace ? hit.ng : -hit.ng;
  glm::dvec3 n = s.frontFace ? hit.ns : -hit.ns;
  s.frame = Frame(n);
  s.woLocal = s.frame.toLocal(wo);
  if (s.woLocal.z <= 0) {
    s.frame = Frame(s.ngFacing);
    s.woLocal = s.frame.toLocal(wo);
  }
  s.woLocal.z = std::max(s.woLocal.z, 1e-12);  // grazing: keep wo in the upper hemisphere
  return s;
}

void fillAov(SampleAov& aov, const Hit& hit, const Shading& sh, const Material& m) {
  aov.depth = hit.t;
  aov.normal = sh.frame.n;
  aov.albedo = m.type == MaterialType::Emissive ? m.emission : m.albedo(hit.uv, hit.latLongUv);
  aov.id = hit.geomID + 1.0;
}

// Shadow ray towards a light sample, stopping a gap short of it. It aims from the spawned
// origin at the sampled point itself: the light was sampled from hit.p, and a mesh's
// origin is pushed off it (64 float ulps of the triangle's coordinates), so a ray along
// ls.wi for ls.distance from there ended past an area light by up to that push, beyond
// the gap on a large floor (half-size 100 under a light 2 above: every sample blocked by
// the light itself, the floor black).
// The gap: a sample of an emitter's far side must be blocked by its near side; stopping
// 1e-4 of the distance short, a sphere light smaller than that (radius 1e-4 at distance 3)
// let every far-side sample through and shone twice as bright as the point light of its
// power. So the gap is at most 1e-3 of the sampled triangle's size, and at least 2^-20 of
// the coordinates, well above the error of Embree's float triangles (~1e-7 of them), so
// that the ray does not find the sampled triangle itself. Convex emitters smaller than
// that floor return no far-side samples at all (Scene::sampleLight).
bool shadowed(const Scene& scene, const Hit& hit, const LightSample& ls, RayCounter& counter) {
  glm::dvec3 org = scene.spawnOrigin(hit, ls.wi);
  if (!std::isfinite(ls.distance))
    return scene.occluded(org, ls.wi, 0.0, std::numeric_limits<double>::infinity(), counter);
  const glm::dvec3 target = hit.p + ls.distance * ls.wi;
  const glm::dvec3 toTarget = target - org;
  const double distance = glm::length(toTarget);
  if (!(distance > 0)) return false;
  const glm::dvec3 dir = toTarget / distance;
  double gap = kShadowEpsilon * distance;
  if (ls.extent > 0) {
    const glm::dvec3 a = glm::abs(org), b = glm::abs(target);
    const double coordinates = std::max({a.x, a.y, a.z, b.x, b.y, b.z});
    gap = std::max(std::min(gap, 1e-3 * ls.extent), 0x1p-20 * coordinates);
  }
  return scene.occluded(org, dir, 0.0, std::max(distance - gap, 0.0), counter);
}

// Light sample contribution f * L * |cos| / pdf, MIS-weighted against BSDF sampling.
glm::dvec3 estimateDirect(const Scene& scene, const Hit& hit, const Shading& sh, const Material& m,
                          const glm::dvec3& albedo, const LightSample& ls, bool mis,
                          RayCounter& counter) {
  if (glm::dot(ls.wi, sh.ngFacing) <= 0) return glm::dvec3(0.0);  // reflection only
  glm::dvec3 wiL = sh.frame.toLocal(ls.wi);
  glm::dvec3 f = evalBsdf(m, albedo, sh.woLocal, wiL) * std::abs(wiL.z);
  if (f == glm::dvec3(0.0) || ls.radiance == glm::dvec3(0.0) || !(ls.pdf > 0))
    return glm::dvec3(0.0);
  if (shadowed(scene, hit, ls, counter)) return glm::dvec3(0.0);
  double w = 1.0;
  if (mis && !ls.delta) w = powerHeuristic(ls.pdf, pdfBsdf(m, sh.woLocal, wiL));
  return f * ls.radiance * (w / ls.pdf);
}

double maxComponent(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// Firefly clamp for contributions of paths with at least one bounce.
glm::dvec3 clampPath(const glm::dvec3& c, int depth, double limit) {
  double m = maxComponent(c);
  return limit > 0 && depth > 0 && m > limit ? c * (limit / m) : c;
}

}  // namespace

glm::dvec3 tracePath(const Scene& scene, const CameraRay& cameraRay, Rng& rng, SampleAov& aov,
                     RayCounter& counter) {
  const int maxDepth = scene.desc().settings.maxDepth;
  const double limit = scene.desc().settings.clampIndirect;
  glm::dvec3 L(0.0), beta(1.0);
  glm::dvec3 org = cameraRay.org, dir = cameraRay.dir;
  bool specularBounce = false;
  bool specularChain = true;  // every vertex so far a specular bounce (SampleAov::seenThrough)
  double prevPdf = 0;
  glm::dvec3 prevP(0.0);
  for (int depth = 0;; ++depth) {
    std::optional<Hit> hit = scene.intersect(org, dir, 0.0, counter);
    // ---- Escaped: environment, MIS-weighted against its light sampling -------------
    if (!hit) {
      glm::dvec3 le = depth == 0 ? scene.background(dir) : scene.environment(dir);
      double w = 1.0;
      if (depth > 0 && !specularBounce && scene.environmentPdf() > 0)
        w = powerHeuristic(prevPdf, scene.environmentPdf());
      L += clampPath(beta * le * w, depth, limit);
      break;
    }
    glm::dvec3 wo = -dir;
    Shading sh = makeShading(*hit, wo);
    const Material& m = scene.material(*hit, sh.frontFace);
    if (depth == 0) fillAov(aov, *hit, sh, m);
    if (specularChain && !m.isSpecular() && aov.seenThrough == 0) aov.seenThrough = hit->geomID + 1;
    // ---- Emitters: black BSDF, end of the path --------------------------------------
    if (m.type == MaterialType::Emissive) {
      double w = 1.0;
      if (depth > 0 && !specularBounce) {
        double lp = scene.lightPdf(prevP, *hit);
        if (lp > 0) w = powerHeuristic(prevPdf, lp);
      }
      L += clampPath(beta * m.emission * w, depth, limit);
      break;
    }
    if (depth >= maxDepth) break;
    glm::dvec3 albedo = m.albedo(hit->uv, hit->latLongUv);
    // ---- Next-event estimation --------------------------------------------------------
    if (!m.isSpecular()) {
      for (int light = 0; light < scene.lightCount(); ++light) {
        glm::dvec2 u = rng.uniform2();
        if (auto ls = scene.sampleLight(light, hit->p, u))
          L += clampPath(beta * estimateDirect(scene, *hit, sh, m, albedo, *ls, true, counter),
                         depth, limit);
      }
    }
    // ---- BSDF sampling for the next vertex ------------------------------------------
    double u1 = rng.uniform();
    glm::dvec2 u2 = rng.uniform2();
    auto bs = sampleBsdf(m, albedo, sh.woLocal, sh.frontFace, u1, u2);
    if (!bs) break;
    glm::dvec3 wi = sh.frame.toWorld(bs->wi);
    // A reflection lobe must leave on wo's side of the true surface (shading normals
    // may say otherwise near silhouettes).
    if (!bs->specular && glm::dot(wi, sh.ngFacing) <= 0) break;
    beta *= bs->weight;
    specularBounce = bs->specular;
    specularChain = specularChain && bs->specular;
    prevPdf = bs->pdf;
    prevP = hit->p;
    org = scene.spawnOrigin(*hit, wi);
    dir = wi;
    // ---- Russian roulette (pbrt-v4 Sec. 13.4.3) --------------------------------------
    if (depth >= 3) {
      double q = std::max(0.05, 1.0 - maxComponent(beta));
      if (rng.uniform() < q) break;
      beta /= 1.0 - q;
    }
    if (!(maxComponent(beta) > 0)) break;
  }
  return L;
}

glm::dvec3 traceDirect(const Scene& scene, const CameraRay& cameraRay, Rng& rng, SampleAov& aov,
                       RayCounter& counter) {
  const SceneDesc& desc = scene.desc();
  glm::dvec3 beta(1.0);
  glm::dvec3 org = cameraRay.org, dir = cameraRay.dir;
  for (int depth = 0; depth <= desc.settings.maxDepth; ++depth) {
    std::optional<Hit> hit = scene.intersect(org, dir, 0.0, counter);
    if (!hit) return beta * (depth == 0 ? scene.background(dir) : scene.environment(dir));
    glm::dvec3 wo = -dir;
    Shading sh = makeShading(*hit, wo);
    const Material& m = scene.material(*hit, sh.frontFace);
    if (depth == 0) fillAov(aov, *hit, sh, m);
    if (!m.isSpecular() && aov.seenThrough == 0) aov.seenThrough = hit->geomID + 1;
    if (m.type == MaterialType::Emissive) return beta * m.emission;
    glm::dvec3 albedo = m.albedo(hit->uv, hit->latLongUv);
    if (m.isSpecular()) {  // follow the glass
      auto bs = sampleBsdf(m, albedo, sh.woLocal, sh.frontFace, rng.uniform(), rng.uniform2());
      if (!bs) return glm::dvec3(0.0);
      beta *= bs->weight;
      dir = sh.frame.toWorld(bs->wi);
      org = scene.spawnOrigin(*hit, dir);
      continue;
    }
    glm::dvec3 L(0.0);
    // Every light once (point and directional: hard shadows; area: one sample), except
    // the environment, which is added below as ambient light.
    for (int light = 0; light < scene.lightCount(); ++light) {
      if (scene.isEnvironmentLight(light)) continue;
      glm::dvec2 u = rng.uniform2();
      if (auto ls = scene.sampleLight(light, hit->p, u))
        L += estimateDirect(scene, *hit, sh, m, albedo, *ls, false, counter);
    }
    // Ambient: the environment's mean radiance (colour times the image's solid-angle mean)
    // reflected without shadowing; exact for a constant environment and an unoccluded
    // diffuse surface. The colour alone made an image environment's ambient light that of
    // an image of ones.
    L += albedo * scene.environmentMean();
    return beta * L;
  }
  return glm::dvec3(0.0);
}

// jsurf's Shader.shade for the side the viewer sees (RenderingTask.shade: the front
// material where the normal faces the view vector, else the back one with the normal
// negated): the ambient colour, and for every light that is ON with L = normalize(light
// position - hit point) and n.L > 0 the diffuse term n.L x colour x kd x light colour x
// intensity and Blinn-Phong's specular term max(0, n.h)^shininess x ks x light colour x
// intensity, h = normalize(L + view); the sum clamped to 1 (Color3f.clampMax). jsurf works
// in camera space; the import carries the lights' positions to the world, where the same
// differences and dot products hold (the camera is a rotation, a translation and a uniform
// scale). No shadow rays: jsurf has none. A miss is the background colour.
glm::dvec3 traceSurfer(const Scene& scene, const CameraRay& cameraRay, Rng& /*rng*/, SampleAov& aov,
                       RayCounter& counter) {
  const std::optional<Hit> hit = scene.intersect(cameraRay.org, cameraRay.dir, 0.0, counter);
  if (!hit) return scene.background(cameraRay.dir);
  const SurferShading& surfer = *scene.desc().surfer;
  const glm::dvec3 view = -cameraRay.dir;
  const Shading sh = makeShading(*hit, view);
  fillAov(aov, *hit, sh, scene.material(*hit, sh.frontFace));
  const SurferMaterial& m = sh.frontFace ? surfer.front : surfer.back;
  const glm::dvec3 n = sh.frontFace ? hit->ns : -hit->ns;
  glm::dvec3 color = m.ambient;
  for (const SurferLight& light : surfer.lights) {
    const std::optional<glm::dvec3> l = safeNormalize(light.position - hit->p);
    if (!l) continue;  // a light exactly at the hit point: jsurf's NaN adds nothing either
    const double lambert = glm::dot(n, *l);
    if (!(lambert > 0)) continue;
    color += lambert * m.diffuse * light.color;
    const std::optional<glm::dvec3> h = safeNormalize(*l + view);
    const double nh = h ? std::max(0.0, glm::dot(n, *h)) : 0.0;
    color += std::pow(nh, m.shininess) * m.specular * light.color;
  }
  return glm::min(color, glm::dvec3(1.0));
}

}  // namespace algray::render
