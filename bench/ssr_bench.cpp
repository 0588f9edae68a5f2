// Indirect-light pass timings at 1024x1024 on the default scene: Hi-Z, colour pyramid, SSR trace,
// cone trace and composite (the last three also at 2048x2048, with either kernel path), each on
// inputs made once, outputs reused between iterations (the steady state of a renderer).
// bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "passes/frame.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

template <class Body>
void Run(benchmark::State& state, Body&& body) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(int(state.range(0)));
  const Frame& frame = DefaultBenchFrame(kSize);
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

// Times items += pass(frame, kernels) with KernelBenchArgs; a first call, untimed, allocates the
// outputs, as a renderer keeps them. Items: what the pass returns, summed.
template <class Pass>
void RunKernels(benchmark::State& state, Pass&& pass) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& f = DefaultBenchFrame(args.size);
  pass(f, args.kernels);
  int64_t items = 0;
  for (auto _ : state) items += int64_t(pass(f, args.kernels));
  state.SetItemsProcessed(items);
}

// Items: rays traced.
void BM_SsrTrace(benchmark::State& state) {
  SsrTraceOutputs out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunSsrTrace({f.gbuffer.gbuffer, f.view, f.hiz}, {}, out, kernels).rays;
  });
}

// Items: pixels with a hit.
void BM_SsrCone(benchmark::State& state) {
  SsrConeOutputs out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunSsrCone({f.gbuffer.gbuffer, f.colorPyramid, f.ssrTrace}, {}, out, kernels).pixels;
  });
}

// Arguments: KernelBenchArgs.
void BM_Composite(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& f = DefaultBenchFrame(args.size);
  const CompositeInputs in{f.gbuffer.gbuffer,     f.view, f.direct.radiance, f.ssrCone.reflected,
                           f.ssrTrace.confidence, bench.config.ssrTrace.roughnessCutoff};
  CompositeOutputs out;
  // Outputs allocated before timing, as a renderer keeps them.
  RunComposite(in, out, args.kernels);
  for (auto _ : state) RunComposite(in, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

BENCHMARK(BM_HiZ)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ColorPyramid)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SsrTrace)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_SsrCone)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_Composite)->Apply(KernelBenchArgs::Register);

}  // namespace
}  // namespace ssgi
