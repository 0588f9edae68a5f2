// Shadow pass timings on the default scene (the shadow map on Sponza too): the shadow map with its
// blocker search, the blocker search alone, and the shadow filters. Buffers are reused from
// iteration to iteration (the steady state of a renderer); bench/README.md records results.
#include <benchmark/benchmark.h>

#include <map>
#include <utility>
#include <vector>

#include "bench/bench_scene.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "core/plane.h"
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

// Made once per scene.
const ShadowInputs& Inputs(const BenchScene& bench) {
  static std::map<const BenchScene*, ShadowInputs> inputs;
  const auto found = inputs.find(&bench);
  if (found != inputs.end()) return found->second;
  const Scene& scene = bench.scene;
  ShadowInputs in;
  in.view = MakePerspective(scene.camera, kSize, kSize);
  RunGBuffer({scene, in.view}, {bench.config.normalEncoding}, in.g);
  in.lightIndex = ShadowCastingLights(scene).front();
  in.light = PrepareLights(scene, in.view.view)[in.lightIndex];
  ShadowMapOutputs out;
  RunShadowMap({scene, in.view, in.g.gbuffer, in.lightIndex}, {}, out, in.g.gbuffer.word[GBufferWord::kShadowTerm]);
  return inputs.emplace(&bench, std::move(in)).first->second;
}

void BM_ShadowMap(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(3));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  // Freed blocks stay in the heap: the set-up's per-frame buffers reuse pages already faulted in.
  if (!RetainFreedMemory()) return state.SkipWithError("cannot set the allocator's page reuse (glibc mallopt)");
  const KernelPath kernels = state.range(0) ? KernelPath::kSimd : KernelPath::kScalar;
  const ThreadLimit threads(int(state.range(1)));
  const ShadowInputs& in = Inputs(bench);
  ShadowMapParams params;
  params.resolution = int(state.range(2));
  Plane<uint32_t> term = MakePlane<uint32_t>(kSize, kSize, 0u);
  ShadowMapOutputs out;
  ShadowMapStats stats;
  for (auto _ : state)
    stats = RunShadowMap({bench.scene, in.view, in.g.gbuffer, in.lightIndex}, params, out, term, kernels);
  state.counters["fitMs"] = stats.fitMs;
  state.counters["rasterMs"] = stats.rasterMs;
  state.counters["searchMs"] = stats.searchMs;
  state.counters["pixels"] = benchmark::Counter(double(stats.pixels), benchmark::Counter::kIsIterationInvariantRate);
}

// The blocker search alone, on the G-buffer and the first shadow-casting light's map of one
// default-scene frame at that size (its render block's shadow map parameters). Arguments:
// KernelBenchArgs.
void BM_BlockerSearch(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& frame = DefaultBenchFrame(args.size);
  if (!frame.shadowMap) return state.SkipWithError("the default scene has no shadow map");
  const GBuffer& gbuffer = frame.gbuffer.gbuffer;
  const ShadowMapOutputs& map = *frame.shadowMap;
  const ShadowMapParams& params = bench.config.shadowMap;
  const ReceiverPositions receivers(frame.view, map.lightView.view * glm::inverse(frame.view.view));
  const std::vector<glm::vec2> pattern = BlockerSearchPattern(params.blockerSearchTaps);
  const PreparedLight light = PrepareLights(bench.scene, glm::mat4(1.0f))[ShadowCastingLights(bench.scene).front()];
  const BlockerSearchContext context =
      MakeBlockerSearchContext(receivers, map, light, pattern, params.maxBlockerDistance, gbuffer.normalEncoding);
  Plane<uint32_t> term = MakePlane<uint32_t>(args.size, args.size, 0u);
  for (auto _ : state) RunBlockerSearch(context, gbuffer, term, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(frame.stats.shadowMap->pixels));
}

// The shadow filter on the G-buffer (word 3 from the first shadow-casting light's map) of one
// default-scene frame at that size, its render block's filter parameters, the output allocated
// before timing. Arguments: KernelBenchArgs, then sspcss (0 SSABSS, 1 SSPCSS).
void BM_ShadowFilter(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& frame = DefaultBenchFrame(args.size);
  if (!frame.shadowMap) return state.SkipWithError("the default scene has no shadow map");
  const PreparedLight light = PrepareLights(bench.scene, frame.view.view)[ShadowCastingLights(bench.scene).front()];
  const ShadowFilterInputs in{frame.gbuffer.gbuffer, frame.view, light};
  ShadowFilterParams params = bench.config.shadowFilter;
  params.filter = state.range(3) == 0 ? ShadowFilter::kSsabss : ShadowFilter::kSspcss;
  ShadowFilterOutputs out;
  ShadowFilterStats stats = RunShadowFilter(in, params, out, args.kernels);
  for (auto _ : state) stats = RunShadowFilter(in, params, out, args.kernels);
  state.counters["tilesBlurred"] = double(stats.tilesBlurred);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// Arguments: the kernel path (1 SIMD, 0 scalar: the raster's tile kernel and the blocker search's
// row kernel), threads (1, 2), the shadow map resolution, then the scene (BenchSceneOf: 0 the default
// scene, -1 Sponza, skipped where its model is not fetched).
BENCHMARK(BM_ShadowMap)
    ->ArgNames({"simd", "threads", "resolution", "scene"})
    ->ArgsProduct({{0, 1}, {1, 2}, {1024, 2048}, {0}})
    ->ArgsProduct({{1}, {1, 2}, {2048}, {-1}})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BlockerSearch)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_ShadowFilter)
    ->ArgNames({"simd", "size", "threads", "sspcss"})
    ->ArgsProduct({{0, 1}, {1024, 2048}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ssgi
