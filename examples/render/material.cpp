#include "material.h"

#include "image_backend.h"
#include "image_io.h"
#include "sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace algray::render {

// ---- Textures -------------------------------------------------------------------------

std::shared_ptr<const Texture> Texture::load(const std::string& path) {
  Raster raster;
  std::string error;
  if (!imageBackend().read(path, raster, error))
    throw std::runtime_error(path + ": cannot read texture: " + error);
  int w = raster.width, h = raster.height, nc = raster.channels;
  if (w <= 0 || h <= 0 || nc <= 0) throw std::runtime_error(path + ": empty texture");
  const std::vector<float>& pixels = raster.pixels;
  std::vector<glm::vec3> texels(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < texels.size(); ++i) {
    const float* p = &pixels[i * nc];
    glm::vec3 c = nc >= 3 ? glm::vec3(p[0], p[1], p[2]) : glm::vec3(p[0]);
    // 8/16-bit images are stored sRGB-encoded; float formats (EXR, HDR) are linear already.
    if (raster.encoded) c = glm::vec3(srgbDecode(c.r), srgbDecode(c.g), srgbDecode(c.b));
    // A float image may hold inf, NaN or negative values: as an environment they turned
    // the whole render black (inf * 0 in the estimator) or negative, with exit code 0.
    if (!(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b)) || c.r < 0 || c.g < 0 ||
        c.b < 0)
      throw std::runtime_error(path + ": texel (" + std::to_string(i % static_cast<size_t>(w)) +
                               ", " + std::to_string(i / static_cast<size_t>(w)) +
                               ") is not a finite non-negative colour");
    texels[i] = c;
  }
  return std::make_shared<Texture>(w, h, std::move(texels));
}

Texture::Texture(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {}

glm::dvec3 Texture::lookup(glm::dvec2 uv) const { return bilinear(uv, false); }

glm::dvec3 Texture::lookupLatLong(glm::dvec2 uv) const { return bilinear(uv, true); }

glm::dvec3 Texture::bilinear(glm::dvec2 uv, bool clampRows) const {
  // Image row 0 is the top; v = 0 is the bottom (OBJ convention).
  const double v = clampRows ? std::clamp(uv.y, 0.0, 1.0) : uv.y - std::floor(uv.y);
  double x = (uv.x - std::floor(uv.x)) * width_ - 0.5;
  double y = (1.0 - v) * height_ - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y)) return glm::dvec3(texels_[0]);
  double fx = std::floor(x), fy = std::floor(y);
  double tx = x - fx, ty = y - fy;
  auto at = [&](long i, long j) {
    i = ((i % width_) + width_) % width_;
    j = clampRows ? std::clamp(j, 0L, static_cast<long>(height_) - 1)
                  : ((j % height_) + height_) % height_;
    return glm::dvec3(texels_[static_cast<size_t>(j) * width_ + i]);
  };
  long i = static_cast<long>(fx), j = static_cast<long>(fy);
  return (1 - tx) * (1 - ty) * at(i, j) + tx * (1 - ty) * at(i + 1, j) +
         (1 - tx) * ty * at(i, j + 1) + tx * ty * at(i + 1, j + 1);
}

glm::dvec3 Texture::average() const {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& t : texels_) sum += glm::dvec3(t);
  return sum / static_cast<double>(texels_.size());
}

glm::dvec3 Texture::maximum() const {
  glm::dvec3 m(0.0);
  for (const glm::vec3& t : texels_) m = glm::max(m, glm::dvec3(t));
  return m;
}

glm::dvec3 Texture::latLongMean() const {
  // Bilinear lookup of periodic samples averages over the azimuth to the row's mean (each
  // column's hat function integrates to 1 / width), so the azimuthal mean is the row means
  // interpolated linearly in theta: y = theta h / pi - 0.5, knots theta_j = (j + 0.5) pi / h,
  // rows clamped like lookupLatLong() (row -1 = 0 at the zenith, row h = h - 1 at the nadir).
  // The mean over the sphere is (1/2) int_0^pi L(theta) sin(theta) dtheta; on a knot
  // interval L = R_j + (R_j+1 - R_j) (theta - theta_j) / step, and
  // int (theta - theta_j) sin(theta) = sin(theta) - (theta - theta_j) cos(theta).
  std::vector<glm::dvec3> rows(static_cast<size_t>(height_), glm::dvec3(0.0));
  for (int j = 0; j < height_; ++j) {
    for (int i = 0; i < width_; ++i)
      rows[j] += glm::dvec3(texels_[static_cast<size_t>(j) * width_ + i]);
    rows[j] /= static_cast<double>(width_);
  }
  auto row = [&](int j) { return rows[static_cast<size_t>(std::clamp(j, 0, height_ - 1))]; };
  const double step = kPi / height_;
  glm::dvec3 sum(0.0);
  for (int j = -1; j < height_; ++j) {
    const double knot = (j + 0.5) * step;
    const double a = std::max(knot, 0.0), b = std::min(knot + step, kPi);
    auto slopePart = [&](double t) { return std::sin(t) - (t - knot) * std::cos(t); };
    sum += row(j) * (std::cos(a) - std::cos(b)) +
           (row(j + 1) - row(j)) * ((slopePart(b) - slopePart(a)) / step);
  }
  return 0.5 * sum;
}

// ---- Microfacet helpers (GGX) ---------------------------------------------------------

namespace {

double ggxAlpha(const Material& m) { return std::max(m.roughness * m.roughness, 1e-4); }

// Trowbridge-Reitz normal distribution D(h), Walter et al. Eq. 33.
double ggxD(double cosH, double alpha) {
  double a2 = alpha * alpha;
  double d = cosH * cosH * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}

// Smith's G1 for GGX, Walter et al. Eq. 34 in terms of cos(theta).
double ggxG1(double cosV, double alpha) {
  double c = std::abs(cosV);
  double a2 = alpha * alpha;
  return 2.0 * c / (c + std::sqrt(a2 + (1.0 - a2) * c * c));
}

glm::dvec3 schlick(const glm::dvec3& f0, double cosTheta) {
  double m = std::clamp(1.0 - cosTheta, 0.0, 1.0);
  double m5 = (m * m) * (m * m) * m;
  return f0 + (1.0 - f0) * m5;
}

// Unpolarised Fresnel reflectance of a smooth dielectric interface (pbrt-v4 Eq. 9.6),
// eta = transmitted / incident index, cosI >= 0.
double fresnelDielectric(double cosI, double eta) {
  double sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) return 1.0;  // total internal reflection
  double cosT = std::sqrt(1.0 - sin2T);
  double rPar = (eta * cosI - cosT) / (eta * cosI + cosT);
  double rPerp = (cosI - eta * cosT) / (cosI + eta * cosT);
  return 0.5 * (rPar * rPar + rPerp * rPerp);
}

}  // namespace

// ---- BSDF -----------------------------------------------------------------------------

glm::dvec3 evalBsdf(const Material& m, const glm::dvec3& albedo, const glm::dvec3& wo,
                    const glm::dvec3& wi) {
  if (wi.z <= 0 || wo.z <= 0) return glm::dvec3(0.0);  // reflection only
  switch (m.type) {
    case MaterialType::Diffuse:
      return albedo * kInvPi;
    case MaterialType::Conductor: {
      glm::dvec3 h = wo + wi;
      double len = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
      if (!(len > 0)) return glm::dvec3(0.0);
      h /= len;
      double alpha = ggxAlpha(m);
      double d = ggxD(h.z, alpha);
      double g = ggxG1(wo.z, alpha) * ggxG1(wi.z, alpha);
      return schlick(albedo, std::abs(wi.x * h.x + wi.y * h.y + wi.z * h.z)) * (d * g) /
             (4.0 * wo.z * wi.z);
    }
    default:
      return glm::dvec3(0.0);
  }
}

double pdfBsdf(const Material& m, const glm::dvec3& wo, const glm::dvec3& wi) {
  if (wi.z <= 0 || wo.z <= 0) return 0.0;
  switch (m.type) {
    case MaterialType::Diffuse:
      return wi.z * kInvPi;
    case MaterialType::Conductor: {
      glm::dvec3 h = wo + wi;
      double len = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
      if (!(len > 0)) return 0.0;
      h /= len;
      double woh = wo.x * h.x + wo.y * h.y + wo.z * h.z;
      // Half-vector density D(h) cos(theta_h), changed to wi: Walter et al. Eq. 14.
      return ggxD(h.z, ggxAlpha(m)) * h.z / (4.0 * std::abs(woh));
    }
    default:
      return 0.0;
  }
}

std::optional<BsdfSample> sampleBsdf(const Material& m, const glm::dvec3& albedo,
                                     const glm::dvec3& wo, bool frontFace, double u1,
                                     glm::dvec2 u2) {
  BsdfSample s;
  switch (m.type) {
    case MaterialType::Diffuse: {
      s.wi = sampleCosineHemisphere(u2);
      if (s.wi.z <= 0) return std::nullopt;
      s.pdf = s.wi.z * kInvPi;
      s.weight = albedo;  // (albedo/pi) cos / (cos/pi)
      return s;
    }
    case MaterialType::Conductor: {
      // Sample h from D(h) cos(theta_h): tan^2 theta = alpha^2 u / (1 - u) (Walter Eq. 35).
      double alpha = ggxAlpha(m);
      double cos2 = (1.0 - u2.x) / (1.0 + (alpha * alpha - 1.0) * u2.x);
      double cosH = std::sqrt(std::max(0.0, cos2));
      double sinH = std::sqrt(std::max(0.0, 1.0 - cos2));
      double phi = 2.0 * kPi * u2.y;
      glm::dvec3 h(sinH * std::cos(phi), sinH * std::sin(phi), cosH);
      double woh = glm::dot(wo, h);
      if (woh <= 0) return std::nullopt;
      s.wi = 2.0 * woh * h - wo;
      if (s.wi.z <= 0) return std::nullopt;
      s.pdf = pdfBsdf(m, wo, s.wi);
      if (!(s.pdf > 0)) return std::nullopt;
      s.weight = evalBsdf(m, albedo, wo, s.wi) * s.wi.z / s.pdf;
      return s;
    }
    case MaterialType::Dielectric: {
      // eta: index on the far side over index on wo's side.
      double eta = frontFace ? m.ior : 1.0 / m.ior;
      double f = fresnelDielectric(wo.z, eta);
      s.specular = true;
      s.pdf = 1.0;
      if (u1 < f) {
        s.wi = {-wo.x, -wo.y, wo.z};
        s.weight = glm::dvec3(1.0);  // (F / cos) cos / F
        return s;
      }
      double sin2T = (1.0 - wo.z * wo.z) / (eta * eta);
      double cosT = std::sqrt(std::max(0.0, 1.0 - sin2T));
      s.wi = -wo / eta + (wo.z / eta - cosT) * glm::dvec3(0, 0, 1);
      // Radiance is scaled by 1/eta^2 across the interface (pbrt-v4 Sec. 9.5.2).
      s.weight = albedo / (eta * eta);
      return s;
    }
    case MaterialType::Emissive:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace algray::render
