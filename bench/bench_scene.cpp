#include "bench/bench_scene.h"

#include <exception>
#include <map>
#include <mutex>

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

const Frame& DefaultBenchFrame(int size) {
  static std::mutex mutex;
  static std::map<int, Frame> frames;
  const std::lock_guard<std::mutex> lock(mutex);
  auto found = frames.find(size);
  if (found == frames.end()) {
    const BenchScene& bench = DefaultBenchScene();
    FrameConfig config = bench.config;
    config.width = config.height = size;
    found = frames.emplace(size, RenderFrame(bench.scene, config)).first;
  }
  return found->second;
}

}  // namespace ssgi
