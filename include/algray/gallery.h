#pragma once
// Named classic algebraic surfaces with sensible clip radii, written from their
// definitions (references in plugin/core/gallery.cpp); used by tests, the renderer and the
// benchmarks. Names: sphere, ellipsoid, torus, clebsch-cubic, cayley-cubic, roman-surface,
// kummer-quartic, togliatti-quintic, barth-sextic, labs-septic, barth-decic, heart,
// chmutov-8, chmutov-12, chmutov-16, endrass-octic, sarti-dodecic. Higher degrees for stress tests
// are easy to build from these (e.g. products of spheres, Polynomial::pow).
#include "algray/polynomial.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace algray {

struct GallerySurface {
  std::string_view name;         // "sphere", "torus", "barth-sextic", ...
  std::string_view description;  // one line, with the reference of the formula
  double clipRadius;             // clip sphere about the origin that frames it
  Polynomial (*build)();         // the polynomial (built on demand)
  // The equation as parsePolynomial reads it (explicit '*': people paste what they are
  // shown), where it is short enough to show; empty for the long ones (their formulas are
  // in plugin/core/gallery.cpp). Parsed, it is build() to within rounding.
  std::string_view equation = {};
};

std::span<const GallerySurface> gallery();
// nullptr if there is no such name. Names match as people type them: ASCII letters in
// either case, and '_' or ' ' for '-' ("Barth_Sextic" finds "barth-sextic"), blanks
// around the name ignored.
const GallerySurface* findGallerySurface(std::string_view name);
// For messages about a name that is not in the gallery: the gallery's names close to it
// (one begins with the other, or at most a third of its letters edited), in gallery order;
// empty if none is.
std::vector<std::string_view> similarGallerySurfaces(std::string_view name);
// The same as words for a message, or empty: "the gallery surface 'chmutov-8'", "one of the
// gallery surfaces 'barth-sextic', 'barth-decic'".
std::string similarGallerySurfacesText(std::string_view name);
// Every name, comma-separated.
std::string galleryNames();

}  // namespace algray
