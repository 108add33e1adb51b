// BSDF sampling is consistent with evaluation, and the models conserve energy:
// Monte Carlo estimates compared with closed forms.
#include "material.h"
#include "sampling.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
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

// Diffuse and conductor are reflection-only models: a BRDF is defined on wo's hemisphere,
// and both f and the pdf are zero for wi below the surface (a shading normal apart from
// the geometric one can put a light sample there).
TEST(Bsdf, ReflectionModelsAreZeroBelowTheSurface) {
  for (MaterialType type : {MaterialType::Diffuse, MaterialType::Conductor}) {
    Material m;
    m.type = type;
    const glm::dvec3 wo = direction(0.6, 0.2);
    for (const glm::dvec3& wi :
         {direction(-0.3, 2.0), direction(-0.9, 0.5), glm::dvec3(-wo.x, -wo.y, -wo.z)}) {
      EXPECT_EQ(evalBsdf(m, glm::dvec3(0.8), wo, wi), glm::dvec3(0.0)) << static_cast<int>(type);
      EXPECT_EQ(pdfBsdf(m, wo, wi), 0.0) << static_cast<int>(type);
    }
  }
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

// Walter et al. (EGSR 2007) in their own variables: D(m) = alpha^2 / (pi cos^4(theta_m)
// (alpha^2 + tan^2(theta_m))^2) (Eq. 33), G1(v) = 2 / (1 + sqrt(1 + alpha^2 tan^2(theta_v)))
// (Eq. 34), f = F G D / (4 |i.n| |o.n|) (Eq. 20), with Schlick's F = F0 + (1 - F0)
// (1 - i.m)^5 and alpha = roughness^2. Two configurations fix every factor: the mirror
// pair (m = n: D = 1 / (pi alpha^2), F at i.m = cos(theta)) and the retro pair (i = o = m:
// F = F0, D at theta_m = theta).
TEST(Bsdf, ConductorMatchesWaltersClosedForm) {
  const glm::dvec3 f0(0.9, 0.5, 0.2);
  for (double roughness : {0.3, 0.7})
    for (double theta : {0.2, 0.8, 1.3}) {
      Material metal;
      metal.type = MaterialType::Conductor;
      metal.roughness = roughness;
      const double alpha = roughness * roughness, c = std::cos(theta), t = std::tan(theta);
      const double g1 = 2 / (1 + std::sqrt(1 + alpha * alpha * t * t));
      const glm::dvec3 wo = direction(c, 0.4);
      // Mirror pair: m = n.
      const glm::dvec3 mirror(-wo.x, -wo.y, wo.z);
      const glm::dvec3 fresnel = f0 + (1.0 - f0) * std::pow(1 - c, 5);
      const glm::dvec3 fMirror = fresnel * g1 * g1 / (kPi * alpha * alpha * 4 * c * c);
      // Retro pair: m = o = i.
      const double dRetro =
          alpha * alpha / (kPi * std::pow(c, 4) * std::pow(alpha * alpha + t * t, 2));
      const glm::dvec3 fRetro = f0 * g1 * g1 * dRetro / (4 * c * c);
      const glm::dvec3 mirrorValue = evalBsdf(metal, f0, wo, mirror);
      const glm::dvec3 retroValue = evalBsdf(metal, f0, wo, wo);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(mirrorValue[k], fMirror[k], 1e-9 * fMirror[k]) << roughness << " " << theta;
        EXPECT_NEAR(retroValue[k], fRetro[k], 1e-9 * fRetro[k]) << roughness << " " << theta;
      }
    }
}

// Unbiasedness of BSDF sampling: the mean sample weight estimates the directional albedo,
// int f cos d omega, only if the directions are drawn with the density pdfBsdf reports
// (weights are computed from that pdf, so SampleWeightIsFCosOverPdf does not see a sampler
// drawing another density). Compared with the sampler-free quadrature; the tolerance is 6
// standard errors of the mean from the weights' own sample variance, plus the quadrature's
// error (midpoint rule, 400^2 cells: well below 1e-3 for these lobes).
TEST(Bsdf, ConductorSamplingEstimatesTheAlbedoWithoutBias) {
  Rng rng(11, 12);
  for (double roughness : {0.4, 0.8})
    for (double phi : {0.0, 1.7})
      for (double c : {0.3, 0.9}) {
        Material metal;
        metal.type = MaterialType::Conductor;
        metal.roughness = roughness;
        const glm::dvec3 wo = direction(c, phi);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
          auto s = sampleBsdf(metal, glm::dvec3(1.0), wo, true, rng.uniform(), rng.uniform2());
          const double w = s ? s->weight.r : 0.0;  // a failed sample contributes nothing
          sum += w, sum2 += w * w;
        }
        const double mean = sum / n, variance = (sum2 / n - mean * mean) * n / (n - 1);
        const double reference = albedoByQuadrature(metal, wo);
        EXPECT_NEAR(mean, reference, 6 * std::sqrt(variance / n) + 1e-3)
            << roughness << " " << phi << " " << c;
      }
}

// Smooth glass at oblique incidence: the reflected and the refracted ray lie in the plane of
// incidence, on the far side of the normal from wo: reflection (-x, -y, z); refraction at
// sin(theta_t) = sin(theta_i) / eta. Weights: a reflection keeps the radiance (F / F); the
// refracted one is scaled by 1 / eta^2, eta = n_far / n_wo, since L / n^2 is conserved
// across the interface (Veach's thesis Sec. 5.2; (1 - F) cancels its selection
// probability), and tinted by the colour.
TEST(Bsdf, GlassScattersInThePlaneOfIncidenceWithRadianceScaling) {
  const glm::dvec3 tint(0.9, 0.8, 0.7);
  Material glass;
  glass.type = MaterialType::Dielectric;
  glass.color = tint;
  glass.ior = 1.5;
  const double thetaI = 0.6, phi = 2.2;
  const glm::dvec3 wo = direction(std::cos(thetaI), phi);
  for (const bool frontFace : {true, false}) {
    const double eta = frontFace ? 1.5 : 1 / 1.5;  // from inside: 1 / 1.5, below critical
    auto r = sampleBsdf(glass, tint, wo, frontFace, 0.0, {0.5, 0.5});
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->specular);
    EXPECT_NEAR(glm::length(r->wi - glm::dvec3(-wo.x, -wo.y, wo.z)), 0.0, 1e-12);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(r->weight[k], 1.0);
    auto t = sampleBsdf(glass, tint, wo, frontFace, 1 - 1e-9, {0.5, 0.5});
    ASSERT_TRUE(t);
    EXPECT_TRUE(t->specular);
    const double sinT = std::sin(thetaI) / eta;
    const glm::dvec3 expected(-sinT * std::cos(phi), -sinT * std::sin(phi),
                              -std::sqrt(1 - sinT * sinT));
    EXPECT_NEAR(glm::length(t->wi - expected), 0.0, 1e-12) << frontFace;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(t->weight[k], tint[k] / (eta * eta), 1e-12) << frontFace;
  }
}

// Fresnel's equations in the angles (Hecht, Optics, Ch. 4): R_s = sin^2(i - t) /
// sin^2(i + t), R_p = tan^2(i - t) / tan^2(i + t), R = (R_s + R_p) / 2 for unpolarised
// light, with R_p = 0 at Brewster's angle atan(n). The sampler reflects exactly when
// u1 < R. From inside (n = 1 / 1.5) beyond the critical angle asin(1 / 1.5) = 0.7297
// everything is reflected.
TEST(Bsdf, GlassReflectsWithFresnelsReflectance) {
  Material glass;
  glass.type = MaterialType::Dielectric;
  glass.ior = 1.5;
  auto reflects = [&](double thetaI, bool frontFace, double u1) {
    auto s = sampleBsdf(glass, glm::dvec3(1.0), direction(std::cos(thetaI), 0.3), frontFace, u1,
                        {0.5, 0.5});
    return s && s->wi.z > 0;
  };
  for (const bool frontFace : {true, false})
    for (double thetaI : {0.3, std::atan(frontFace ? 1.5 : 1 / 1.5), 0.6, 1.2}) {
      const double eta = frontFace ? 1.5 : 1 / 1.5;
      const double sinT = std::sin(thetaI) / eta;
      if (sinT >= 1) {  // total internal reflection
        EXPECT_TRUE(reflects(thetaI, frontFace, 1 - 1e-9)) << thetaI;
        continue;
      }
      const double thetaT = std::asin(sinT);
      const double rs = std::pow(std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT), 2);
      const double rp = std::pow(std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT), 2);
      const double reflectance = 0.5 * (rs + rp);
      EXPECT_TRUE(reflects(thetaI, frontFace, reflectance - 1e-9)) << frontFace << " " << thetaI;
      EXPECT_FALSE(reflects(thetaI, frontFace, reflectance + 1e-9)) << frontFace << " " << thetaI;
    }
}

// ---- Warps and weights of sampling.h ---------------------------------------------------

// Pearson's chi-square statistic of `counts` against equal expected counts; under the null
// hypothesis it has mean k - 1 and standard deviation sqrt(2 (k - 1)) for k cells, so a
// bound of mean + 6 standard deviations rejects a correct sampler with negligible
// probability while a wrong density (cells off by 10 %, 1000 samples each) exceeds it
// many times over.
double chiSquare(const std::vector<int>& counts, double expected) {
  double chi2 = 0;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}
double chiSquareBound(size_t cells) {
  const double dof = static_cast<double>(cells) - 1;
  return dof + 6 * std::sqrt(2 * dof);
}

// Malley's method: the cosine-weighted hemisphere projects to the uniform unit disk (pdf
// cos/pi on the hemisphere is 1/pi per unit of projected area). Cells of equal area: rings
// equal in r^2 by sectors equal in azimuth. The directions are unit vectors.
TEST(Sampling, CosineHemisphereProjectsUniformlyOntoTheDisk) {
  const int rings = 8, sectors = 16, perCell = 1000;
  std::vector<int> counts(rings * sectors, 0);
  Rng rng(3, 4);
  for (int i = 0; i < rings * sectors * perCell; ++i) {
    const glm::dvec3 w = sampleCosineHemisphere(rng.uniform2());
    ASSERT_NEAR(glm::length(w), 1.0, 1e-12) << i;
    ASSERT_GE(w.z, 0.0) << i;
    const double r2 = w.x * w.x + w.y * w.y, phi = std::atan2(w.y, w.x) + kPi;
    const int ring = std::min(static_cast<int>(r2 * rings), rings - 1);
    const int sector = std::min(static_cast<int>(phi / (2 * kPi) * sectors), sectors - 1);
    ++counts[ring * sectors + sector];
  }
  EXPECT_LT(chiSquare(counts, perCell), chiSquareBound(counts.size()));
}

// Archimedes: bands of equal height on the unit sphere have equal area, so uniform
// directions fall equally into cells of equal z-width and equal azimuth; the density is
// 1 / (area of the unit sphere) = 1 / (4 pi).
TEST(Sampling, UniformSphereCoversEqualAreasEqually) {
  EXPECT_DOUBLE_EQ(kUniformSpherePdf * 4 * kPi, 1.0);
  const int bands = 8, sectors = 16, perCell = 1000;
  std::vector<int> counts(bands * sectors, 0);
  Rng rng(5, 6);
  for (int i = 0; i < bands * sectors * perCell; ++i) {
    const glm::dvec3 w = sampleUniformSphere(rng.uniform2());
    ASSERT_NEAR(glm::length(w), 1.0, 1e-12) << i;
    const double phi = std::atan2(w.y, w.x) + kPi;
    const int band = std::clamp(static_cast<int>((w.z + 1) / 2 * bands), 0, bands - 1);
    const int sector = std::min(static_cast<int>(phi / (2 * kPi) * sectors), sectors - 1);
    ++counts[band * sectors + sector];
  }
  EXPECT_LT(chiSquare(counts, perCell), chiSquareBound(counts.size()));
}

// Barycentrics (b1, b2) as the point b1 (1, 0) + b2 (0, 1) of the right triangle: uniform
// means equal counts in its n^2 congruent sub-triangles (a grid of squares of side 1/n,
// each cut by its anti-diagonal).
TEST(Sampling, UniformTriangleCoversEqualAreasEqually) {
  const int n = 8, perCell = 1000;
  std::vector<int> counts(2 * n * n, 0);  // [square][lower or upper half]; n^2 of them used
  Rng rng(7, 8);
  for (int k = 0; k < n * n * perCell; ++k) {
    const glm::dvec2 b = sampleUniformTriangle(rng.uniform2());
    ASSERT_GE(b.x, 0.0);
    ASSERT_GE(b.y, 0.0);
    ASSERT_LE(b.x + b.y, 1.0 + 1e-15);
    const int i = std::min(static_cast<int>(b.x * n), n - 1);
    const int j = std::min(static_cast<int>(b.y * n), n - 1);
    const bool upper = (b.x * n - i) + (b.y * n - j) > 1;
    ++counts[2 * (j * n + i) + upper];
  }
  std::vector<int> used;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      used.push_back(counts[2 * (j * n + i)]);
      if (i + j < n - 1) used.push_back(counts[2 * (j * n + i) + 1]);
    }
  ASSERT_EQ(used.size(), static_cast<size_t>(n * n));
  EXPECT_LT(chiSquare(used, perCell), chiSquareBound(used.size()));
}

// Veach's power heuristic, beta = 2 (thesis Sec. 9.2.4): w_a = a^2 / (a^2 + b^2), so the two
// weights of a pair sum to 1, w(1, 2) = 1/5 (the balance heuristic's would be 1/3), and a
// Dirac density (infinite pdf) takes all the weight.
TEST(Sampling, PowerHeuristicClosedForms) {
  EXPECT_DOUBLE_EQ(powerHeuristic(1.0, 2.0), 0.2);
  EXPECT_DOUBLE_EQ(powerHeuristic(2.0, 1.0), 0.8);
  EXPECT_DOUBLE_EQ(powerHeuristic(3.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(powerHeuristic(0.0, 0.0), 0.0);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_DOUBLE_EQ(powerHeuristic(inf, 5.0), 1.0);
  EXPECT_DOUBLE_EQ(powerHeuristic(5.0, inf), 0.0);
}

// Duff et al.'s basis: s, t, n orthonormal and right-handed (s x t = n) for normals of
// either hemisphere, including the poles where the construction switches sign; toWorld
// inverts toLocal.
TEST(Sampling, FrameIsAnOrthonormalRightHandedBasis) {
  for (const glm::dvec3& d :
       {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(0.3, -0.5, 0.8),
        glm::dvec3(-0.6, 0.2, -0.7), glm::dvec3(1, 0, 0), glm::dvec3(0.1, 0.9, -1e-3)}) {
    const glm::dvec3 n = glm::normalize(d);
    const Frame f(n);
    EXPECT_NEAR(glm::length(f.s), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(f.t), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.s, f.t), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.s, n), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(f.t, n), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::cross(f.s, f.t) - n), 0.0, 1e-12);
    const glm::dvec3 v(0.2, -0.4, 0.7);
    EXPECT_NEAR(glm::length(f.toWorld(f.toLocal(v)) - v), 0.0, 1e-12);
    EXPECT_NEAR(f.toLocal(n).z, 1.0, 1e-12);
  }
}

// Rng::uniform is uniform on [0, 1): mean 1/2 and variance 1/12. The mean of N draws lies
// within 6 sigma / sqrt(N) of 1/2 unless the generator is biased; each of the 53 bits is
// set half of the time (tested on the top ones, where a shifted or lost bit shows).
TEST(Sampling, RngUniformHasTheUnitIntervalsMoments) {
  Rng rng(9, 10);
  const int n = 1 << 20;
  double sum = 0, sum2 = 0;
  std::vector<int> bits(8, 0);
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u, sum2 += u * u;
    for (int b = 0; b < 8; ++b) bits[b] += static_cast<int>(std::ldexp(u, b + 1)) & 1;
  }
  const double sigma = std::sqrt(1.0 / 12);
  EXPECT_NEAR(sum / n, 0.5, 6 * sigma / std::sqrt(n));
  // Var(u^2) = 1/5 - 1/9 = 4/45 around E[u^2] = 1/3.
  EXPECT_NEAR(sum2 / n, 1.0 / 3, 6 * std::sqrt(4.0 / 45) / std::sqrt(n));
  for (int b = 0; b < 8; ++b) EXPECT_NEAR(bits[b], n / 2, 6 * std::sqrt(n / 4.0)) << "bit " << b;
}

}  // namespace
}  // namespace algray::render
