// Direct light and tonemap timings on the default scene's buffers (made once), outputs reused
// between iterations; bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "bench/memory_floor.h"
#include "core/parallel.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "passes/shadow_map.h"
#include "passes/tonemap.h"

namespace ssgi {
namespace {

// As a frame runs it: every light, the shadowed one scaled by its filtered visibility. Arguments:
// KernelBenchArgs.
void BM_DirectLight(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& frame = DefaultBenchFrame(args.size);
  DirectLightInputs in{frame.gbuffer.gbuffer, frame.view, bench.scene};
  if (frame.shadowMap) {
    in.lightVisibility = &frame.shadowVisibility.visibility;
    in.shadowedLight = ShadowCastingLights(bench.scene).front();
  }
  DirectLightOutputs out;
  // Outputs allocated before timing, as a renderer keeps them.
  RunDirectLight(in, bench.config.directLight, out, args.kernels);
  for (auto _ : state) RunDirectLight(in, bench.config.directLight, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// The frame's final image (direct + indirect) to 8-bit sRGB. Arguments: KernelBenchArgs.
void BM_Tonemap(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& frame = DefaultBenchFrame(args.size);
  TonemapOutputs out;
  // Output allocated before timing, as a renderer keeps it.
  RunTonemap(frame.Result(), bench.config.tonemap, out, args.kernels);
  for (auto _ : state) RunTonemap(frame.Result(), bench.config.tonemap, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// The tonemap's memory floor per pixel: radiance R, G, B read (12 bytes), 8-bit R, G, B written (3).
[[maybe_unused]] const bool kTonemapFloor = (RegisterMemoryFloor(12, 3), true);

BENCHMARK(BM_DirectLight)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_Tonemap)->Apply(KernelBenchArgs::Register);

}  // namespace
}  // namespace ssgi
