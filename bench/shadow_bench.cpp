// Shadow pass timings on the default scene: the shadow map with its blocker search at 1024x1024, and
// the shadow filters at 1024x1024 and 2048x2048. Buffers are reused from iteration to iteration (the
// steady state of a renderer); bench/README.md records results.
#include <map>

#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

// The default scene's G-buffer at size x size, with word 3 from a 2048 shadow map, made once per size.
struct ShadowInputs {
  ViewProjection view;
  GBufferOutputs g;
  PreparedLight light;
  size_t lightIndex = 0;
};

const ShadowInputs& Inputs(const BenchScene& bench, int size) {
  static std::map<int, ShadowInputs> inputs;
  const auto found = inputs.find(size);
  if (found != inputs.end()) return found->second;
  const Scene& scene = bench.scene;
  ShadowInputs in;
  in.view = MakePerspective(scene.camera, size, size);
  RunGBuffer({scene, in.view}, {bench.config.normalEncoding}, in.g);
  in.lightIndex = ShadowCastingLights(scene).front();
  in.light = PrepareLights(scene, in.view.view)[in.lightIndex];
  ShadowMapOutputs out;
  RunShadowMap({scene, in.view, in.g.gbuffer, in.lightIndex}, {}, out, in.g.gbuffer.word[3]);
  return inputs.emplace(size, std::move(in)).first->second;
}

void BM_ShadowMap(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const ShadowInputs& in = Inputs(bench, kSize);
  ShadowMapParams params;
  params.resolution = int(state.range(1));
  Plane<uint32_t> term = MakePlane<uint32_t>(kSize, kSize, 0u);
  ShadowMapOutputs out;
  ShadowMapStats stats;
  for (auto _ : state) stats = RunShadowMap({bench.scene, in.view, in.g.gbuffer, in.lightIndex}, params, out, term);
  state.counters["rasterMs"] = stats.rasterMs;
  state.counters["searchMs"] = stats.searchMs;
  state.counters["pixels"] = benchmark::Counter(double(stats.pixels), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ShadowFilter(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const int size = int(state.range(0));
  const ThreadLimit threads(int(state.range(1)));
  const ShadowInputs& in = Inputs(bench, size);
  ShadowFilterParams params;
  params.filter = state.range(2) == 0 ? ShadowFilter::kSsabss : ShadowFilter::kSspcss;
  const KernelPath kernels = state.range(3) != 0 ? KernelPath::kSimd : KernelPath::kScalar;
  ShadowFilterOutputs out;
  ShadowFilterStats stats;
  for (auto _ : state) stats = RunShadowFilter({in.g.gbuffer, in.view, in.light}, params, out, kernels);
  state.counters["tilesBlurred"] = double(stats.tilesBlurred);
  state.SetItemsProcessed(int64_t(state.iterations()) * size * size);
}

// Arguments: threads (1, 2), then the shadow map resolution.
BENCHMARK(BM_ShadowMap)->ArgNames({"threads", "resolution"})->ArgsProduct({{1, 2}, {1024, 2048}})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
// Arguments: image size, threads (1, 2), the filter (0 ssabss, 1 sspcss), the row kernels (0 scalar,
// 1 SIMD).
BENCHMARK(BM_ShadowFilter)->ArgNames({"size", "threads", "sspcss", "simd"})
    ->ArgsProduct({{1024, 2048}, {1, 2}, {0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ssgi
