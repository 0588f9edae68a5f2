// Indirect-light pass timings at 1024x1024 on the default scene: Hi-Z, colour pyramid, SSR trace,
// cone trace and composite, each on inputs made once, outputs reused between iterations (the
// steady state of a renderer). bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "passes/frame.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

// One whole frame of the default scene, whose buffers are the passes' inputs.
const Frame& DefaultFrame(const BenchScene& bench) {
  static const Frame frame = [&] {
    FrameConfig config = bench.config;
    config.width = config.height = kSize;
    return RenderFrame(bench.scene, config);
  }();
  return frame;
}

template <class Body>
void Run(benchmark::State& state, Body&& body) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const Frame& frame = DefaultFrame(bench);
  for (auto _ : state) body(frame);
  state.counters["pixels"] = benchmark::Counter(double(kSize) * kSize, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_HiZ(benchmark::State& state) {
  HiZ hiz;
  Run(state, [&](const Frame& f) { RunHiZ(f.gbuffer.gbuffer.word[2], hiz); });
}

void BM_ColorPyramid(benchmark::State& state) {
  ColorPyramid pyramid;
  Run(state, [&](const Frame& f) { RunColorPyramid(f.direct.radiance, pyramid); });
}

void BM_SsrTrace(benchmark::State& state) {
  SsrTraceOutputs trace;
  Run(state, [&](const Frame& f) {
    RunSsrTrace({f.gbuffer.gbuffer, f.view, f.hiz}, {}, trace);
  });
}

void BM_SsrCone(benchmark::State& state) {
  SsrConeOutputs cone;
  Run(state, [&](const Frame& f) { RunSsrCone({f.gbuffer.gbuffer, f.colorPyramid, f.ssrTrace}, {}, cone); });
}

void BM_Composite(benchmark::State& state) {
  CompositeOutputs out;
  Run(state, [&](const Frame& f) {
    RunComposite({f.gbuffer.gbuffer, f.view, f.direct.radiance, f.ssrCone.reflected,
                   f.ssrTrace.confidence, SsrTraceParams{}.roughnessCutoff},
                  out);
  });
}

BENCHMARK(BM_HiZ)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ColorPyramid)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SsrTrace)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SsrCone)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Composite)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ssgi
