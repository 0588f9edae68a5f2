// The sky light per frame, and the sky visibility and interreflection volumes it reads, made once per
// scene; bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "bench/memory_floor.h"
#include "core/environment_lighting.h"
#include "core/parallel.h"
#include "passes/sky_light.h"
#include "passes/world_bounce.h"

namespace ssgi {
namespace {

// As a frame runs it, on the default scene's G-buffer and direct light under its sky, the volumes
// made beforehand (a frame keeps them). Arguments: KernelBenchArgs.
void BM_SkyLight(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& frame = DefaultBenchFrame(args.size);
  static const EnvironmentLighting environment = PrepareEnvironmentLighting(bench.config.environment);
  static const SkyVisibilityVolume volume = BuildSkyVisibility(bench.scene, bench.config.skyVisibility);
  static const WorldBounceVolume interreflection =
      BuildWorldBounce(bench.scene, volume, environment, bench.config.interreflection);
  const SkyLightInputs in{frame.gbuffer.gbuffer, frame.view,      environment, &volume,
                          frame.direct.radiance, &interreflection};
  SkyLightOutputs out;
  // Outputs allocated before timing, as a renderer keeps them.
  RunSkyLight(in, {}, out, args.kernels);
  for (auto _ : state) RunSkyLight(in, {}, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// The sky light's memory floor per pixel: G-buffer words 0-2 and the direct R, G, B read (24 bytes);
// the sky's diffuse R, G, B, its visibility, lit R, G, B and the interreflection volume towards the
// mirror direction R, G, B written (40).
[[maybe_unused]] const bool kSkyLightFloor = (RegisterMemoryFloor(24, 40), true);

// The volume of a scene (BenchSceneOf: 0 the default scene, -1 Sponza) at the frame's default
// settings: what the first frame of a scene pays once. Arguments: scene, threads.
void BM_SkyVisibilityBuild(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(BuildSkyVisibility(bench.scene, bench.config.skyVisibility));
  state.counters["cells"] = double(SkyVisibilityBytes(bench.scene, bench.config.skyVisibility) / (4 * sizeof(float)));
}

// The interreflection volume of a scene on its sky visibility grid (made beforehand), at the frame's
// default settings: what the first frame of a scene and its lights pays once. Arguments: scene,
// threads.
void BM_InterreflectionBuild(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(1)));
  const EnvironmentLighting environment = PrepareEnvironmentLighting(bench.config.environment);
  const SkyVisibilityVolume volume = BuildSkyVisibility(bench.scene, bench.config.skyVisibility);
  for (auto _ : state)
    benchmark::DoNotOptimize(BuildWorldBounce(bench.scene, volume, environment, bench.config.interreflection));
  state.counters["cells"] = double(volume.coefficients.size() / 4);
}

BENCHMARK(BM_SkyLight)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_InterreflectionBuild)
    ->ArgNames({"scene", "threads"})
    ->Args({0, 2})
    ->Args({-1, 2})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SkyVisibilityBuild)
    ->ArgNames({"scene", "threads"})
    ->Args({0, 2})
    ->Args({-1, 2})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ssgi
