// Direct light and tonemap timings at 1024x1024 on the default scene's G-buffer (made once, with its
// shadow term); bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
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

void BM_DirectLight(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const ShadingInputs& in = Inputs(bench);
  DirectLightOutputs out;
  for (auto _ : state) RunDirectLight({in.g.gbuffer, in.view, bench.scene}, bench.config.directLight, out);
  ReportPixels(state);
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

BENCHMARK(BM_DirectLight)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Tonemap)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ssgi
