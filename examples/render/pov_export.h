#pragma once
// The same picture as a POV-Ray 3.7 scene, for tests/bench/povray_compare.py: the
// surface as a `polynomial` object with `clipped_by` its clip sphere (and `sturm`), the
// floor as a plane, each directional light as a `parallel` light with shadows, the
// environment as ambient light, the same camera. Only quick-mode-like scenes (surfaces
// with a clip sphere, planes, directional lights, diffuse materials) can be exported.
#include "scene_desc.h"

#include <string>

namespace algray::render {

// Throws std::runtime_error when the scene holds something POV-Ray cannot be given.
std::string povrayScene(const SceneDesc& scene, bool sturm);

}  // namespace algray::render
