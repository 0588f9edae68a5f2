#include "bench/bench_scene.h"

#include <cmath>
#include <exception>
#include <iterator>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <utility>

#include "core/procedural_mesh.h"

namespace ssgi {

namespace {

BenchScene LoadBenchScene(const char* path, const char* hint = "") {
  try {
    SceneFile file = LoadSceneFile(path);
    const FrameConfig config = FrameConfigFromSceneFile(file);
    return BenchScene{std::move(file.scene), config, {}};
  } catch (const std::exception& e) {
    return BenchScene{{}, {}, std::string("cannot load ") + path + ": " + e.what() + hint};
  }
}

const BenchScene& SponzaBenchScene() {
  static const BenchScene scene =
      LoadBenchScene(SSGI_SOURCE_DATA_DIR "/scenes/sponza.json",
                     " (fetch the model with data/scenes/fetch.sh sponza, or --from DIR for a local copy)");
  return scene;
}

}  // namespace

const BenchScene& DefaultBenchScene() {
  static const BenchScene scene = LoadBenchScene(SSGI_SOURCE_DATA_DIR "/default.json");
  return scene;
}

const BenchScene& KnotScene(int64_t triangles) {
  struct Segments {
    int64_t triangles;
    int tubular, radial;
  };
  // About 8 tubular segments per radial one at every size, so the triangles keep their shape.
  static constexpr Segments kSegments[] = {
      {10000, 200, 25}, {30000, 375, 40}, {100000, 625, 80}, {300000, 1200, 125}, {1000000, 2000, 250}};
  static BenchScene scenes[std::size(kSegments)];
  for (size_t i = 0; i < std::size(kSegments); ++i) {
    if (kSegments[i].triangles != triangles) continue;
    if (scenes[i].scene.mesh.TriangleCount() == 0) {
      Scene scene;
      scene.mesh = MakeTorusKnot(kSegments[i].tubular, kSegments[i].radial);
      scene.materials.push_back(Material{});
      scene.camera.position = {0.0f, -0.6f, 4.0f};
      scene.camera.target = {0.0f, 0.0f, 0.0f};
      scene.camera.fovYDegrees = 45.0f;
      scenes[i] = BenchScene{std::move(scene), {}, {}};
    }
    return scenes[i];
  }
  static const BenchScene unknown{{}, {}, "no torus knot with that triangle count"};
  return unknown;
}

const BenchScene& BenchSceneOf(int64_t scene) {
  if (scene == -1) return SponzaBenchScene();
  return scene == 0 ? DefaultBenchScene() : KnotScene(scene);
}

void GBufferPeerArgs(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"scene", "threads", "size"})
      ->ArgsProduct({{10000, 100000, 1000000}, {1, 2}, {1024}})
      ->ArgsProduct({{30000, 300000}, {2}, {1024}})
      ->ArgsProduct({{100000}, {2}, {512, 2048, 4096}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

const FillrateScene& FillrateTriangles(int areaPixels) {
  static std::map<int, FillrateScene> scenes;
  auto found = scenes.find(areaPixels);
  if (found != scenes.end()) return found->second;

  constexpr double kPixelsPerFrame = 8.0 * kFillrateSize * kFillrateSize;
  const size_t triangles = size_t(kPixelsPerFrame / areaPixels);
  FillrateScene scene;
  scene.areaPixels = areaPixels;
  constexpr float kHalf = 0.5f * float(kFillrateSize);
  // Depth 0 (near) to 1 (far) along -z; world units are pixels.
  scene.view = MakeOrthographic({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, {0.0f, 1.0f, 0.0f}, kHalf, kHalf, 0.0f,
                                1.0f, kFillrateSize, kFillrateSize);
  std::mt19937 random(20170612u);
  const auto uniform = [&random] { return float(random() >> 8) * (1.0f / 16777216.0f); };  // [0, 1)
  const float leg = std::sqrt(2.0f * float(areaPixels));
  scene.positions.reserve(3 * triangles);
  for (size_t i = 0; i < triangles; ++i) {
    const float depth = float(triangles - i) / float(triangles + 1);
    glm::vec2 corners[3];
    bool inside = false;
    while (!inside) {  // a new rotation and offset until the triangle lies inside the image
      const float angle = uniform() * 6.28318531f;
      const glm::vec2 along(std::cos(angle), std::sin(angle)), across(-along.y, along.x);
      const glm::vec2 origin((uniform() * 2.0f - 1.0f) * kHalf, (uniform() * 2.0f - 1.0f) * kHalf);
      corners[0] = origin;
      corners[1] = origin + leg * along;
      corners[2] = origin + leg * across;  // counter-clockwise
      inside = true;
      for (const glm::vec2& corner : corners) {
        inside = inside && std::abs(corner.x) <= kHalf && std::abs(corner.y) <= kHalf;
      }
    }
    for (const glm::vec2& corner : corners) scene.positions.emplace_back(corner.x, corner.y, -depth);
  }
  scene.indices.resize(scene.positions.size());
  std::iota(scene.indices.begin(), scene.indices.end(), 0u);
  return scenes.emplace(areaPixels, std::move(scene)).first->second;
}

void FillrateArgs(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"area", "threads"})
      ->ArgsProduct({{10, 50, 100, 250, 500}, {1, 2}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

void ReportFillrate(benchmark::State& state, const FillrateScene& scene) {
  const auto triangles = int64_t(scene.TriangleCount());
  state.SetItemsProcessed(int64_t(state.iterations()) * triangles);
  state.counters["pixels"] =
      benchmark::Counter(double(triangles) * scene.areaPixels, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["triangles"] = double(triangles);
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
    // The bounce's buffers too, which the scene's own frame leaves to the interreflection volume: the
    // composite's every-term benchmark reads them.
    config.bounce = EffectMode::kOn;
    found = frames.emplace(size, RenderFrame(bench.scene, config)).first;
  }
  return found->second;
}

}  // namespace ssgi
