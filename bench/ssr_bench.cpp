// Indirect-light pass timings on the default scene: Hi-Z, colour pyramid, SSR trace, cone trace and
// composite at 1024x1024 and 2048x2048 with either kernel path, the pyramids beside the memory
// floors of their bytes, each on inputs made once, outputs reused between iterations (the steady
// state of a renderer). bench/README.md records results.
#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "bench/memory_floor.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

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

// Items: texels written, all levels.
void BM_HiZ(benchmark::State& state) {
  HiZ out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunHiZ(f.gbuffer.gbuffer.word[GBufferWord::kDepth], out, kernels).texels;
  });
}

// Items: RGB texels written, all levels.
void BM_ColorPyramid(benchmark::State& state) {
  ColorPyramid out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunColorPyramid(f.direct.radiance, out, kernels).texels;
  });
}

// The memory floors of the pyramids' bytes per level-0 pixel. Hi-Z: word 2 read (4), levels written
// (4 x 4/3 = 5.33, rounded down, so its floor is a shade low). Colour pyramid: three float planes
// read (12), levels written (12 x 4/3 = 16).
[[maybe_unused]] const bool kPyramidFloors = (RegisterMemoryFloor(4, 5), RegisterMemoryFloor(12, 16), true);

// Items: rays traced.
void BM_SsrTrace(benchmark::State& state) {
  SsrTraceOutputs out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunSsrTrace({f.gbuffer.gbuffer, f.view, f.hiz}, {}, out, kernels).rays;
  });
}

// The trace with every pixel tracing its own ray (shared rays off, as `--quality ultra`): what the
// shared rays save, in the same run. Items: rays traced.
void BM_SsrTraceEveryPixel(benchmark::State& state) {
  SsrTraceOutputs out;
  SsrTraceParams params;
  params.quadRoughness = params.blockRoughness = 1.0f;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunSsrTrace({f.gbuffer.gbuffer, f.view, f.hiz}, params, out, kernels).rays;
  });
}

// Items: pixels with a hit.
void BM_SsrCone(benchmark::State& state) {
  SsrConeOutputs out;
  RunKernels(state, [&](const Frame& f, KernelPath kernels) {
    return RunSsrCone({f.gbuffer.gbuffer, f.colorPyramid, f.ssrTrace.hitX, f.ssrTrace.hitY, f.ssrTrace.confidence}, {}, out,
                      kernels).pixels;
  });
}

// Arguments: KernelBenchArgs.
void BM_Composite(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& f = DefaultBenchFrame(args.size);
  const CompositeInputs in{f.gbuffer.gbuffer,      f.view,
                           f.direct.radiance,      &f.ssrCone.reflected,
                           &f.ssrTrace.confidence, bench.config.ssrTrace.roughnessCutoff};
  CompositeOutputs out;
  // Outputs allocated before timing, as a renderer keeps them.
  RunComposite(in, out, args.kernels);
  for (auto _ : state) RunComposite(in, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// The composite's memory floors per pixel: it always reads the trace confidence and direct R, G, B
// (16 bytes) and writes indirect and result R, G, B (24); where a vector of pixels has a confident
// lane it also reads words 0-2 and reflected R, G, B (24 more).
[[maybe_unused]] const bool kCompositeFloors = (RegisterMemoryFloor(16, 24), RegisterMemoryFloor(40, 24), true);

// The composite with every term on: the reflection, the sky's specular light and the surroundings'
// light from the interreflection volume where the trace did not see, the bounce on the diffuse albedo
// and its visibility darkening the sky's diffuse light, on every pixel (no tile is skipped).
void BM_CompositeEveryTerm(benchmark::State& state) {
  const BenchScene& bench = DefaultBenchScene();
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelBenchArgs args(state);
  const Frame& f = DefaultBenchFrame(args.size);
  if (!f.sky || !f.bounce) return state.SkipWithError("the default scene's frame runs no sky light or bounce");
  CompositeInputs in{f.gbuffer.gbuffer,
                     f.view,
                     f.Lit(),
                     &f.ssrCone.reflected,
                     &f.ssrTrace.confidence,
                     bench.config.ssrTrace.roughnessCutoff,
                     nullptr,
                     &f.environment,
                     &f.skyLight.visibility};
  if (f.skyLight.reflected.c[0].xsize() != 0) in.skyReflected = &f.skyLight.reflected;
  in.bounce = &f.diffuseBounce.bounce;
  in.skyDiffuse = &f.skyLight.diffuse;
  in.ambientVisibility = &f.diffuseBounce.visibility;
  CompositeOutputs out;
  RunComposite(in, out, args.kernels);
  for (auto _ : state) RunComposite(in, out, args.kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * args.size * args.size);
}

// Its floor per pixel: words 0-2, confidence, lit, reflected, the sky's visibility and its reflected
// surroundings, the bounce, the sky's diffuse light and the bounce's visibility read (12 + 4 + 12 +
// 12 + 4 + 12 + 12 + 12 + 4), indirect and result written (24).
[[maybe_unused]] const bool kCompositeEveryTermFloor = (RegisterMemoryFloor(84, 24), true);

BENCHMARK(BM_HiZ)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_ColorPyramid)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_SsrTrace)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_SsrTraceEveryPixel)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_SsrCone)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_Composite)->Apply(KernelBenchArgs::Register);
BENCHMARK(BM_CompositeEveryTerm)->Apply(KernelBenchArgs::Register);

}  // namespace
}  // namespace ssgi
