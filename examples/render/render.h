#pragma once
// The render loop: 16x16 tiles in parallel with TBB, one random stream per pixel so the
// image is the same for any thread count, a progress bar on a terminal, cancellation
// (Ctrl-C) that keeps the tiles finished so far.
#include "scene.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace algray::render {

// Linear radiance and first-hit channels, row-major, row 0 at the top.
struct Image {
  int width = 0, height = 0;
  std::vector<glm::vec3> color;
  std::vector<float> depth;
  std::vector<glm::vec3> normal;
  std::vector<glm::vec3> albedo;
  std::vector<float> id;
  std::vector<double> overflow;  // a colour beyond float's range (its largest component), else 0
  void resize(int w, int h);
};

struct RenderOptions {
  bool progress = false;                      // draw a progress bar on stderr
  const std::atomic<bool>* cancel = nullptr;  // when true: stop, checked before every pixel
};

struct RenderStats {
  double seconds = 0;
  std::uint64_t rays = 0;  // camera, bounce and shadow rays
  int tilesDone = 0, tilesTotal = 0;
  bool interrupted = false;
  // Pixels whose colour lies beyond float's range (3.4e38), which the image cannot hold
  // (a point light 1e-20 above a plane: 2.5e39), and the first of them in row order.
  std::uint64_t overflowPixels = 0;
  int overflowX = -1, overflowY = -1;
  double overflowValue = 0;
  // seen[geomID]: a camera ray hit the geometry first, or through glass (SampleAov).
  std::vector<bool> seen;
  bool wasSeen(unsigned geomID) const { return geomID < seen.size() && seen[geomID]; }
};

// Renders scene.desc().settings (width, height, spp, integrator, seed, threads).
RenderStats render(const Scene& scene, Image& image, const RenderOptions& options = {});

}  // namespace algray::render
