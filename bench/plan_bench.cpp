// Cost that follows need (docs/design.md §9): whole frames of a floor whose smooth share grows
// strip by strip, against the same frame with reflections switched off. bench/README.md records
// results; bench/plot_cost_share.py draws them.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "core/procedural_mesh.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

constexpr int kStrips = 32;
constexpr int kSize = 1024;

// A floor of kStrips strips running away from the camera, the first `smooth` of them (from the left)
// smooth enough to reflect, the others rough; grey posts stand on it; a sun of that angular
// diameter casts shadows (the wider the sun, the wider the penumbrae).
Scene StripFloor(int smooth, float sunDegrees = 2.0f) {
  Scene scene;
  // Looking down at the floor, which fills the image.
  scene.camera.position = {0.0f, 2.5f, 3.0f};
  scene.camera.target = {0.0f, 0.0f, -1.5f};
  Material rough;
  rough.roughness = 0.9f;
  Material mirror;
  mirror.roughness = 0.15f;
  mirror.metallic = 1.0f;
  scene.materials = {rough, mirror};
  constexpr float kHalfWidth = 8.0f;
  for (int i = 0; i < kStrips; ++i) {
    const float x0 = -kHalfWidth + 2.0f * kHalfWidth * float(i) / kStrips;
    AddQuad(scene.mesh, {x0, 0.0f, 4.0f}, {2.0f * kHalfWidth / kStrips, 0.0f, 0.0f}, {0.0f, 0.0f, -30.0f},
            i < smooth ? 1u : 0u);
  }
  // A grid of tall posts: their shadows, and penumbrae, stripe the floor.
  for (int row = 0; row < 6; ++row) {
    for (int column = 0; column < 9; ++column) {
      const float x = -3.2f + 0.8f * float(column) + 0.4f * float(row % 2), z = 1.0f - 1.1f * float(row);
      AddBox(scene.mesh, {x - 0.08f, 0.0f, z - 0.08f}, {x + 0.08f, 1.4f, z + 0.08f}, 0u);
    }
  }
  DirectionalLight sun;
  sun.direction = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
  sun.angularDiameterDegrees = sunDegrees;
  scene.directionalLights.push_back(sun);
  return scene;
}

// Renders the frame again and again into the same buffers (after one untimed frame), reporting
// each stage's mean time as a counter, to show where a frame's cost, or a step in it, comes from.
// Returns the frame, for its plan and stats.
Frame TimeFrames(benchmark::State& state, const Scene& scene, const FrameConfig& config, BufferLifetime lifetime) {
  // Kept buffers: the heap keeps what a frame frees for the next, as in a running renderer (and as
  // `ssgi figures` renders Table 1); freed ones: every plane on fresh pages, as `ssgi render` pays.
  const bool keep = lifetime != BufferLifetime::kUntilLastReader;
  if (!RetainFreedMemory(keep) && keep)
    state.SkipWithError("cannot set the allocator's page reuse (glibc mallopt)");
  Frame frame;
  RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime);
  std::map<std::string, double> stageMs;
  for (auto _ : state) {
    RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime);
    for (const StageStats& stage : StageRows(frame.stats)) stageMs[stage.name] += stage.ms;
  }
  for (const auto& [name, ms] : stageMs) {
    std::string counter = name + " ms";
    std::replace(counter.begin(), counter.end(), ' ', '_');
    state.counters[counter] = ms / double(state.iterations());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * config.width * config.height);
  return frame;
}

// Times one frame of the scene at kSize x kSize on range(2) threads, its buffers kept for the next
// frame as a running renderer keeps them (range(3) 1) or each freed after its last reader as
// `ssgi render` frees them (0); `effect` is set to automatic when range(1) is 1 or 2, else switched
// off; `configure` may change the rest of the configuration.
Frame TimeFrame(benchmark::State& state, const Scene& scene, EffectMode FrameConfig::*effect,
                void (*configure)(FrameConfig&) = nullptr) {
  const ThreadLimit threads(int(state.range(2)));
  FrameConfig config;
  config.width = config.height = kSize;
  config.*effect = state.range(1) ? EffectMode::kAuto : EffectMode::kOff;
  if (configure) configure(config);
  return TimeFrames(state, scene, config,
                    state.range(3) ? BufferLifetime::kKeepForReuse : BufferLifetime::kUntilLastReader);
}

// Arguments: smooth strips (0 .. kStrips), reflections (1 auto, 0 off), threads, keep (1 the frame's
// buffers kept, 0 freed as `ssgi render` frees them). Reports the share of the image's pixels that
// need reflections, as the frame plan counts them.
void BM_FrameReflectionShare(benchmark::State& state) {
  const Frame frame = TimeFrame(state, StripFloor(int(state.range(0))), &FrameConfig::reflections);
  state.counters["reflectionShare"] = double(frame.plan.reflections.pixels) / double(frame.plan.pixels);
}

void RegisterShares(benchmark::internal::Benchmark* b) {
  b->ArgNames({"smooth", "reflections", "threads", "keep"});
  for (int keep : {1, 0}) {
    for (int smooth = 0; smooth <= kStrips; smooth += 2) b->Args({smooth, 1, 2, keep});
    b->Args({0, 0, 2, keep});
  }
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_FrameReflectionShare)->Apply(RegisterShares);

// The same floor, all rough, under suns of growing size: the share of the image the shadow blur
// runs on grows with the penumbrae. Arguments: the sun's angular diameter in tenths of a degree,
// shadows (1 auto, soft; 2 auto with the blur switched off, hard shadows: `--shadow-filter hard`; 0
// off), threads, keep (1). Reports the share of 16x16 tiles the blur ran on.
void BM_FramePenumbraShare(benchmark::State& state) {
  const auto hard = [](FrameConfig& config) { config.shadowFilter.filter = ShadowFilter::kHard; };
  const Frame frame = TimeFrame(state, StripFloor(0, float(state.range(0)) / 10.0f), &FrameConfig::shadows,
                                state.range(1) == 2 ? +hard : nullptr);
  const auto& filter = frame.stats.shadowFilter;
  state.counters["penumbraShare"] =
      filter && filter->tiles > 0 ? double(filter->tilesBlurred) / double(filter->tiles) : 0.0;
}

void RegisterPenumbrae(benchmark::internal::Benchmark* b) {
  b->ArgNames({"sunTenthsDeg", "shadows", "threads", "keep"});
  for (int tenths : {0, 2, 5, 10, 20, 40, 80, 160}) b->Args({tenths, 1, 2, 1});
  b->Args({0, 2, 2, 1});
  b->Args({0, 0, 2, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_FramePenumbraShare)->Apply(RegisterPenumbrae);

// The rows of `ssgi figures`' Table 1, with each stage's time: the scene (BenchSceneOf: 0 the default
// scene, -1 Dabrovic Sponza) at its own 1024x1024, row 0 direct light only, 1 with shadows,
// 2 with shadows and reflections (rows 0-2 the paper's pipeline: the effects it does not have, the
// sky light and the diffuse bounce, switched off), 3 with every effect, on `threads` threads,
// rendered as Table 1 renders them (into the last frame's buffers), with the anti-aliasing `aa`
// (0 off, 1 edge, 2 mlaa; passes/antialias.h, passes/mlaa.h).
void BM_Table1Frame(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(2));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(1)));
  FrameConfig config = bench.config;
  config.shadows = state.range(0) >= 1 ? EffectMode::kAuto : EffectMode::kOff;
  config.reflections = state.range(0) >= 2 ? EffectMode::kAuto : EffectMode::kOff;
  config.sky = state.range(0) >= 3 ? EffectMode::kAuto : EffectMode::kOff;
  config.bounce = state.range(0) >= 3 ? EffectMode::kAuto : EffectMode::kOff;
  config.antialiasing = Antialiasing(state.range(3));
  TimeFrames(state, bench.scene, config, BufferLifetime::kKeepForReuse);
}

BENCHMARK(BM_Table1Frame)
    ->ArgNames({"row", "threads", "scene", "aa"})
    ->ArgsProduct({{0, 1, 2, 3}, {2}, {0, -1}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ssgi
