#pragma once
// Materials and their BSDFs, evaluated in the local shading frame (normal = +z).
// The integrators make shading two-sided by flipping the normal towards the outgoing
// direction wo, so wo.z > 0 on entry to every function below; `frontFace` says whether
// wo lies on the side the geometric normal (the gradient, for algebraic surfaces) points
// to, which only the dielectric needs (it decides entering vs. leaving).
//
// Models and references:
//  * diffuse: Lambert, f = albedo / pi.
//  * conductor: Cook-Torrance microfacet BRDF with the GGX / Trowbridge-Reitz
//    distribution, Smith's separable masking-shadowing and Schlick's Fresnel with the
//    colour as F0 (Walter et al., "Microfacet Models for Refraction through Rough
//    Surfaces", EGSR 2007, Eqs. 20, 33, 34; Schlick 1994).
//  * dielectric: smooth glass, exact dielectric Fresnel (pbrt-v4 Sec. 9.3, 9.5).
//  * emissive: a diffuse emitter of `emission` radiance on both sides, black BSDF.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace algray::render {

// An RGB image in linear colour, looked up with bilinear filtering and wrapping.
class Texture {
 public:
  // Throws std::runtime_error naming the file when it cannot be read.
  static std::shared_ptr<const Texture> load(const std::string& path);
  Texture(int width, int height, std::vector<glm::vec3> texels);
  glm::dvec3 lookup(glm::dvec2 uv) const;
  // A lat-long map's lookup (v = 1 - theta / pi, the environment's): wrapping in u only,
  // rows clamped at the poles (wrapped, the zenith blended the top row with the bottom
  // one over half a texel, and v = 1 itself read the bottom row).
  glm::dvec3 lookupLatLong(glm::dvec2 uv) const;
  // Average colour; used as the albedo AOV and by tests.
  glm::dvec3 average() const;
  // The largest texel value of each channel (a colour times the texture stays below it).
  glm::dvec3 maximum() const;
  // Mean over the sphere of directions (solid-angle weighted) of lookupLatLong(), exactly
  // as interpolated: the ambient light of an image environment.
  glm::dvec3 latLongMean() const;

 private:
  glm::dvec3 bilinear(glm::dvec2 uv, bool clampRows) const;
  int width_, height_;
  std::vector<glm::vec3> texels_;
};

enum class MaterialType { Diffuse, Conductor, Dielectric, Emissive };

struct Material {
  MaterialType type = MaterialType::Diffuse;
  glm::dvec3 color{0.8};     // albedo, conductor F0, dielectric tint
  double roughness = 0.3;    // conductor: GGX alpha = roughness^2 (perceptual roughness)
  double ior = 1.5;          // dielectric: index of refraction (outside = 1)
  glm::dvec3 emission{0.0};  // emissive: radiance
  std::shared_ptr<const Texture> texture;  // multiplies `color` at the hit's uv

  // True when the BSDF is a Dirac delta (no light sampling, no MIS).
  bool isSpecular() const { return type == MaterialType::Dielectric; }
  // latLong: uv are a sphere's latitude-longitude coordinates (Hit::latLongUv), whose rows
  // clamp at the poles as the environment's do instead of repeating.
  glm::dvec3 albedo(glm::dvec2 uv, bool latLong = false) const {
    return texture ? color * (latLong ? texture->lookupLatLong(uv) : texture->lookup(uv)) : color;
  }
};

struct BsdfSample {
  glm::dvec3 wi{0.0};
  glm::dvec3 weight{0.0};  // f * |cos(wi)| / pdf
  double pdf = 0;          // solid-angle pdf; meaningless when specular
  bool specular = false;
};

// f(wo, wi) (without the cosine). albedo is Material::albedo(uv).
glm::dvec3 evalBsdf(const Material& m, const glm::dvec3& albedo, const glm::dvec3& wo,
                    const glm::dvec3& wi);
double pdfBsdf(const Material& m, const glm::dvec3& wo, const glm::dvec3& wi);
// u1 chooses a lobe (dielectric), u2 the direction.
std::optional<BsdfSample> sampleBsdf(const Material& m, const glm::dvec3& albedo,
                                     const glm::dvec3& wo, bool frontFace, double u1,
                                     glm::dvec2 u2);

}  // namespace algray::render
