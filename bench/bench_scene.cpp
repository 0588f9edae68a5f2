#include "bench/bench_scene.h"

#include <exception>

namespace ssgi {

const BenchScene& DefaultBenchScene() {
  static const BenchScene scene = [] {
    try {
      SceneFile file = LoadSceneFile(SSGI_SOURCE_DATA_DIR "/default.json");
      const FrameConfig config = FrameConfigFromSceneFile(file);
      return BenchScene{std::move(file.scene), config, {}};
    } catch (const std::exception& e) {
      return BenchScene{{}, {}, std::string("cannot load the default scene: ") + e.what()};
    }
  }();
  return scene;
}

}  // namespace ssgi
