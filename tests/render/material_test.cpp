// BSDF sampling is consistent with evaluation, and the models conserve energy:
// Monte Carlo estimates compared with closed forms.
#include "material.h"
#include "sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace algray::render {
namespace {

glm::dvec3 direction(double cosTheta, double phi) {
  double s = std::sqrt(1 - cosTheta * cosTheta);
  return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

// The ambient light of an image environment: Texture::latLongMean against brute-force
// quadrature of lookupLatLong() over the sphere (midpoint rule in theta and phi with the sin(theta)
// weight; lookup is piecewise linear, so the rule's error is O(1/n^2), here below 1e-6),
// on an image whose rows and columns all differ (rows clamped at the zenith and nadir).
TEST(EnvironmentImage, LatLongMeanIsTheSolidAngleMeanOfTheLookup) {
  const int w = 5, h = 3;
  std::vector<glm::vec3> texels;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      texels.emplace_back(0.1f * static_cast<float>(i + 1) + static_cast<float>(j * j),
                          static_cast<float>((i * 7 + j * 3) % 5), 0.25f * static_cast<float>(j));
  const Texture texture(w, h, texels);
  const int nTheta = 3000, nPhi = 600;
  glm::dvec3 sum(0.0);
  double weight = 0;
  for (int a = 0; a < nTheta; ++a) {
    const double theta = (a + 0.5) * kPi / nTheta;
    for (int b = 0; b < nPhi; ++b) {
      const double u = (b + 0.5) / nPhi;  // u = 0.5 + phi / 2pi covers the circle once
      sum += std::sin(theta) * texture.lookupLatLong({u, 1.0 - theta / kPi});
      weight += std::sin(theta);
    }
  }
  const glm::dvec3 reference = sum / weight;
  const glm::dvec3 mean = texture.latLongMean();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], reference[k], 1e-6) << k;
}

TEST(Bsdf, SampleWeightIsFCosOverPdf) {
  Rng rng(1, 2);
  for (MaterialType type : {MaterialType::Diffuse, MaterialType::Conductor}) {
    Material m;
    m.type = type;
    m.roughness = 0.4;
    glm::dvec3 albedo(0.7, 0.5, 0.3);
    for (int i = 0; i < 500; ++i) {
      glm::dvec3 wo = direction(0.1 + 0.9 * rng.uniform(), 6.28 * rng.uniform());
      auto s = sampleBsdf(m, albedo, wo, true, rng.uniform(), rng.uniform2());
      if (!s) continue;
      glm::dvec3 f = evalBsdf(m, albedo, wo, s->wi);
      double pdf = pdfBsdf(m, wo, s->wi);
      EXPECT_NEAR(s->pdf, pdf, 1e-9 * pdf);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(s->weight[k], f[k] * s->wi.z / pdf, 1e-9 * (1 + s->weight[k]));
    }
  }
}

// Directional albedo by uniform hemisphere integration (independent of the sampler).
double albedoByQuadrature(const Material& m, const glm::dvec3& wo) {
  const int n = 400;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double cosTheta = (i + 0.5) / n, phi = 2 * kPi * (j + 0.5) / n;
      glm::dvec3 wi = direction(cosTheta, phi);
      sum += evalBsdf(m, glm::dvec3(1.0), wo, wi).r * cosTheta;
    }
  return sum * 2 * kPi / (n * double(n));  // d omega = d cos d phi
}

TEST(Bsdf, DiffuseAlbedoIsOneAndConductorAtMostOne) {
  Material diffuse;
  diffuse.color = glm::dvec3(1.0);
  EXPECT_NEAR(albedoByQuadrature(diffuse, direction(0.7, 0.3)), 1.0, 1e-3);
  Material metal;
  metal.type = MaterialType::Conductor;
  metal.roughness = 0.6;
  for (double c : {0.2, 0.6, 1.0}) {
    double a = albedoByQuadrature(metal, direction(c, 0.0));
    EXPECT_LE(a, 1.0 + 1e-3);
    EXPECT_GT(a, 0.6);  // white F0 and rough: most energy reflected
  }
}

TEST(Bsdf, ConductorPdfIntegratesToAtMostOne) {
  Material metal;
  metal.type = MaterialType::Conductor;
  metal.roughness = 0.5;
  glm::dvec3 wo = direction(0.8, 1.0);
  const int n = 400;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      sum += pdfBsdf(metal, wo, direction((i + 0.5) / n, 2 * kPi * (j + 0.5) / n));
  double integral = sum * 2 * kPi / (n * double(n));
  EXPECT_LE(integral, 1.0 + 1e-2);
  EXPECT_GT(integral, 0.9);
}

TEST(Bsdf, GlassFollowsSnellAndFresnel) {
  Material glass;
  glass.type = MaterialType::Dielectric;
  glass.color = glm::dvec3(1.0);
  glass.ior = 1.5;
  glm::dvec3 wo = direction(std::cos(0.5), 0.0);
  // u1 = 0.999: refraction; sin(theta_t) = sin(theta_i) / 1.5 (Snell).
  auto t = sampleBsdf(glass, glm::dvec3(1.0), wo, true, 0.999, {0.5, 0.5});
  ASSERT_TRUE(t);
  EXPECT_LT(t->wi.z, 0);
  EXPECT_NEAR(std::sqrt(1 - t->wi.z * t->wi.z), std::sin(0.5) / 1.5, 1e-12);
  // Normal incidence: reflectance ((n-1)/(n+1))^2 = 0.04: u1 = 0.039 reflects, 0.041 refracts.
  glm::dvec3 up(0, 0, 1);
  EXPECT_GT(sampleBsdf(glass, glm::dvec3(1.0), up, true, 0.039, {0, 0})->wi.z, 0);
  EXPECT_LT(sampleBsdf(glass, glm::dvec3(1.0), up, true, 0.041, {0, 0})->wi.z, 0);
}

}  // namespace
}  // namespace algray::render
