// Shadow pass timings on the default scene: the shadow map with its blocker search, the blocker
// search alone, and the shadow filters. Buffers are reused from iteration to iteration (the steady
// state of a renderer); bench/README.md records results.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "bench/bench_scene.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "passes/gbuffer.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

// The default scene's G-buffer, with word 3 from a 2048 shadow map, made once.
struct ShadowInputs {
  ViewProjection view;
  GBufferOutputs g;
  PreparedLight light;
  size_t lightIndex = 0;
};

const ShadowInputs& Inputs(const BenchScene& bench) {
  static const ShadowInputs inputs = [&] {
    const Scene& scene = bench.scene;
    ShadowInputs in;
    in.view = MakePerspective(scene.camera, kSize, kSize);
    RunGBuffer({scene, in.view}, {bench.config.normalEncoding}, in.g);
    in.lightIndex = ShadowCastingLights(scene).front();
    in.light = PrepareLights(scene, in.view.view)[in.lightIndex];
    ShadowMapOutputs out;
    RunShadowMap({scene, in.view, in.g.gbuffer, in.lightIndex}, {}, out, in.g.gbuffer.word[3]);
    return in;
  }();
  return inputs;
}

void BM_ShadowMap(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const ShadowInputs& in = Inputs(bench);
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

// What RunShadowMap's blocker search reads for a G-buffer of size x size: the default scene's
// G-buffer and its first shadow-casting light's map (default parameters), made once per size.
struct SearchInputs {
  ViewProjection view;
  GBufferOutputs g;
  ShadowMapParams params;
  ShadowMapOutputs map;
  std::unique_ptr<ReceiverPositions> positions;
  std::vector<glm::vec2> pattern;
  std::unique_ptr<BlockerSearchContext> context;
  size_t receivers = 0;  // G-buffer pixels with geometry: the items searched
};

const SearchInputs& SearchInputsOfSize(const BenchScene& bench, int size) {
  static std::map<int, std::unique_ptr<SearchInputs>> inputs;
  std::unique_ptr<SearchInputs>& in = inputs[size];
  if (in) return *in;
  const Scene& scene = bench.scene;
  in = std::make_unique<SearchInputs>();
  in->view = MakePerspective(scene.camera, size, size);
  RunGBuffer({scene, in->view}, {bench.config.normalEncoding}, in->g);
  const size_t light = ShadowCastingLights(scene).front();
  RunShadowMap({scene, in->view, in->g.gbuffer, light}, in->params, in->map, in->g.gbuffer.word[3]);
  in->positions = std::make_unique<ReceiverPositions>(in->view, in->map.lightView.view * glm::inverse(in->view.view));
  in->pattern = BlockerSearchPattern(in->params.blockerSearchTaps);
  in->context = std::make_unique<BlockerSearchContext>(
      MakeBlockerSearchContext(*in->positions, in->map, PrepareLights(scene, glm::mat4(1.0f))[light], in->pattern,
                               in->params.maxBlockerDistance, in->g.gbuffer.normalEncoding));
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) in->receivers += UnpackDepth(in->g.gbuffer.word[2].ConstRow(y)[x]) < kBackgroundDepth;
  return *in;
}

void BM_BlockerSearch(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelPath kernels = state.range(0) == 0 ? KernelPath::kSimd : KernelPath::kScalar;
  const int size = int(state.range(1));
  const ThreadLimit threads(int(state.range(2)));
  const SearchInputs& in = SearchInputsOfSize(bench, size);
  Plane<uint32_t> term = MakePlane<uint32_t>(size, size, 0u);
  for (auto _ : state) RunBlockerSearch(*in.context, in.g.gbuffer, term, kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(in.receivers));
}

void BM_ShadowFilter(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const ShadowInputs& in = Inputs(bench);
  ShadowFilterParams params;
  params.filter = state.range(1) == 0 ? ShadowFilter::kSsabss : ShadowFilter::kSspcss;
  ShadowFilterOutputs out;
  ShadowFilterStats stats;
  for (auto _ : state)
    stats = RunShadowFilter({in.g.gbuffer, in.view, in.light}, params, out);
  state.counters["tilesBlurred"] = double(stats.tilesBlurred);
  state.counters["pixels"] =
      benchmark::Counter(double(kSize) * kSize, benchmark::Counter::kIsIterationInvariantRate);
}

// Arguments: threads (1, 2), then the shadow map resolution, or the filter (0 ssabss, 1 sspcss).
BENCHMARK(BM_ShadowMap)->ArgNames({"threads", "resolution"})->ArgsProduct({{1, 2}, {1024, 2048}})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
// Arguments: the row kernel (0 SIMD, 1 scalar), the G-buffer's width and height, threads (1, 2).
BENCHMARK(BM_BlockerSearch)->ArgNames({"scalar", "size", "threads"})->ArgsProduct({{0, 1}, {1024, 2048}, {1, 2}})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ShadowFilter)->ArgNames({"threads", "sspcss"})->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ssgi
