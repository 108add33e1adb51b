// A small render of the default scene against committed statistics. The reference
// (default_scene_stats.json) was produced by this renderer and only guards against
// regressions; correctness is checked by the white-furnace tests. Regenerate it with
// ALGRAY_UPDATE_REFERENCE=1 after an intended change.
#include "render.h"
#include "scene.h"
#include "scene_builders.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <vector>

namespace algray::render {
namespace {

const char* kReference = ALGRAY_SOURCE_DIR "/tests/render/default_scene_stats.json";

nlohmann::json statistics(const Image& image) {
  glm::dvec3 mean(0.0);
  std::vector<double> lum;
  int hits = 0;
  for (size_t i = 0; i < image.color.size(); ++i) {
    glm::dvec3 c(image.color[i]);
    mean += c;
    lum.push_back(0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b);
    hits += image.id[i] > 0;
  }
  mean /= static_cast<double>(image.color.size());
  std::sort(lum.begin(), lum.end());
  auto pct = [&](double p) { return lum[static_cast<size_t>(p * (lum.size() - 1))]; };
  return {{"mean", {mean.r, mean.g, mean.b}},
          {"p10", pct(0.1)},
          {"p50", pct(0.5)},
          {"p90", pct(0.9)},
          {"hit_fraction", hits / double(image.color.size())}};
}

TEST(DefaultScene, SmallRenderMatchesReferenceStatistics) {
  SceneDesc desc = defaultScene();
  ASSERT_GE(desc.surfaces.size(), 3u);
  ASSERT_GE(desc.meshes.size(), 2u);
  desc.settings.width = 96;
  desc.settings.height = 60;
  desc.settings.spp = 8;
  Scene scene(desc);
  Image image;
  RenderStats stats = render(scene, image);
  EXPECT_GT(stats.rays, 96u * 60u * 8u);
  nlohmann::json now = statistics(image);
  if (std::getenv("ALGRAY_UPDATE_REFERENCE")) {
    std::ofstream(kReference) << now.dump(2) << "\n";
    GTEST_SKIP() << "reference written to " << kReference;
  }
  std::ifstream in(kReference);
  ASSERT_TRUE(in) << kReference;
  nlohmann::json ref = nlohmann::json::parse(in);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(now["mean"][k].get<double>(), ref["mean"][k].get<double>(),
                0.03 * ref["mean"][k].get<double>());
  for (const char* key : {"p10", "p50", "p90"})
    EXPECT_NEAR(now[key].get<double>(), ref[key].get<double>(),
                0.05 * ref[key].get<double>() + 1e-3)
        << key;
  EXPECT_NEAR(now["hit_fraction"].get<double>(), ref["hit_fraction"].get<double>(), 0.01);
}

}  // namespace
}  // namespace algray::render
