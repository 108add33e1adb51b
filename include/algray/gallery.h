#pragma once
// Named classic algebraic surfaces with sensible clip radii, written from their
// definitions; used by tests, the renderer and the benchmarks.
#include "algray/polynomial.h"

#include <span>
#include <string_view>

namespace algray {

struct GallerySurface {
  std::string_view name;         // "sphere", "torus", "barth-sextic", ...
  std::string_view description;  // one line, with the reference of the formula
  double clipRadius;             // clip sphere about the origin that frames it
  Polynomial (*build)();         // the polynomial (built on demand)
};

std::span<const GallerySurface> gallery();
// nullptr if there is no such name.
const GallerySurface* findGallerySurface(std::string_view name);

}  // namespace algray
