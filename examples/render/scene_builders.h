#pragma once
// Scenes made without a scene file: the embedded default scene (no arguments), quick mode
// (one equation or gallery surface framed automatically) and SURFER/jsurf import.
#include "scene_desc.h"

#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace algray::render {

// Several gallery surfaces of different degrees on a triangle-mesh floor beside a
// triangle-mesh icosphere, lit by a quad area light and a dim sky.
SceneDesc defaultScene();

struct QuickOptions {
  std::string surface;  // an equation or a gallery name
  std::map<std::string, double, std::less<>> parameters;
  std::optional<double> clipRadius;  // unset: the gallery's radius, or 2 for an equation
  // The image size asked for; unset: 512 x 512, and one of them alone keeps it square.
  std::optional<int> width, height;
};
// The surface centred at the origin inside its clip sphere of radius R, a floor at
// z = -R, a camera that frames the sphere in the image's shorter side, one directional
// light with shadows and a
// constant environment (ambient light). Throws algray::Error / ParseError.
SceneDesc quickScene(const QuickOptions& options);
// True when f has no real zero for a reason read off its terms: every term an even power
// of x, y and z with the constant's sign (x^2+y^2+z^2+1). So no clip sphere can reach
// any of it. False says nothing (deciding that in general is not cheap).
bool evidentlyHasNoRealPoints(const Polynomial& f);

// A .jsurf file framed as SURFER frames it: the clip sphere of radius 1 in view space,
// surface coordinates = 10^scale_factor * rotation_matrix * view coordinates, an
// orthographic (or perspective) camera looking down -z with height camera_height, front
// and back materials, the lights that are ON (far away: directional), background colour,
// ambient as a constant environment. Throws algray::Error with file:line.
SceneDesc jsurfScene(const std::filesystem::path& path);

}  // namespace algray::render
