// Indirect-light pass timings at 1024x1024 on the default scene: Hi-Z, colour pyramid, SSR trace,
// cone trace and composite (the pyramids and the composite also at 2048x2048, with either kernel
// path; the pyramids beside the memory floors of their bytes), each on inputs made once, outputs
// reused between iterations (the steady state of a renderer). bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "bench/memory_floor.h"
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

// Arguments: KernelBenchArgs. Items: texels written, all levels.
void BM_HiZ(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Plane<uint32_t>& depthWord = DefaultBenchFrame(args.size).gbuffer.gbuffer.word[2];
  HiZ hiz;
  // Levels allocated before timing, as a renderer keeps them.
  const size_t texels = RunHiZ(depthWord, hiz, args.kernels).texels;
  for (auto _ : state) RunHiZ(depthWord, hiz, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(texels));
}

// Arguments: KernelBenchArgs. Items: RGB texels written, all levels.
void BM_ColorPyramid(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Plane3<float>& radiance = DefaultBenchFrame(args.size).direct.radiance;
  ColorPyramid pyramid;
  const size_t texels = RunColorPyramid(radiance, pyramid, args.kernels).texels;
  for (auto _ : state) RunColorPyramid(radiance, pyramid, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(texels));
}

// The memory floors of the pyramids' bytes per level-0 pixel. Hi-Z: word 2 read (4), levels written
// (4 x 4/3 = 5.33, rounded down, so its floor is a shade low). Colour pyramid: three float planes
// read (12), levels written (12 x 4/3 = 16).
[[maybe_unused]] const bool kPyramidFloors = (RegisterMemoryFloor(4, 5), RegisterMemoryFloor(12, 16), true);

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

BENCHMARK(BM_HiZ)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_ColorPyramid)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_SsrTrace)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SsrCone)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Composite)->Apply(KernelBenchArgs::Register);

}  // namespace
}  // namespace ssgi
