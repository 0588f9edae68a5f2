// Direct light and tonemap timings on the default scene's buffers (made once), outputs reused
// between iterations; bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "passes/shadow_map.h"
#include "passes/tonemap.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

struct ShadingInputs {
  ViewProjection view;
  GBufferOutputs g;
  DirectLightOutputs direct;
};

const ShadingInputs& Inputs(const BenchScene& bench) {
  static const ShadingInputs inputs = [&] {
    ShadingInputs in;
    in.view = MakePerspective(bench.scene.camera, kSize, kSize);
    RunGBuffer({bench.scene, in.view}, {bench.config.normalEncoding}, in.g);
    RunDirectLight({in.g.gbuffer, in.view, bench.scene}, bench.config.directLight, in.direct);
    return in;
  }();
  return inputs;
}

void ReportPixels(benchmark::State& state) {
  state.counters["pixels"] = benchmark::Counter(double(kSize) * kSize, benchmark::Counter::kIsIterationInvariantRate);
}

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

void BM_Tonemap(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const ShadingInputs& in = Inputs(bench);
  TonemapOutputs out;
  for (auto _ : state) RunTonemap(in.direct.radiance, {}, out);
  ReportPixels(state);
}

BENCHMARK(BM_DirectLight)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_Tonemap)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ssgi
