// Rasterizer and G-buffer pass timings at 1024x1024 (docs/design.md §13: at least 3x faster than Mesa
// llvmpipe writing the same G-buffer). bench/README.md says what each benchmark measures and
// records results.
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/camera.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "core/raster/scene_raster_input.h"
#include "passes/gbuffer.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;
constexpr int64_t kPixels = int64_t(kSize) * kSize;

// range(0) of every benchmark here: 1 runs the raster's SIMD tile kernel, 0 its scalar definition.
KernelPath Kernels(const benchmark::State& state) {
  return state.range(0) ? KernelPath::kSimd : KernelPath::kScalar;
}

// Skips the benchmark (and returns false) when its scene or its memory mode is unavailable.
bool Begin(benchmark::State& state, const BenchScene& bench) {
  if (!bench.error.empty()) {
    state.SkipWithError(bench.error.c_str());
    return false;
  }
  if (!RetainFreedMemory(state.range(3) == 0)) {
    state.SkipWithError("cannot set the allocator's page reuse (glibc mallopt)");
    return false;
  }
  return true;
}

void ReportCommon(benchmark::State& state, const Scene& scene) {
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(scene.mesh.TriangleCount()));
  state.counters["pixels"] = benchmark::Counter(double(kPixels), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["triangles"] = double(scene.mesh.TriangleCount());
}

// Visibility only: vertex transform, clipping, setup, binning, tile rasterization, including the
// clear of a fresh visibility buffer each frame. The scene's raster input (flags, alpha test) is
// prepared once, outside the timed loop.
void RasterizeOnly(benchmark::State& state, const BenchScene& bench) {
  if (!Begin(state, bench)) return;
  const ThreadLimit threads(int(state.range(2)));
  const Scene& scene = bench.scene;
  const ViewProjection view = MakePerspective(scene.camera, kSize, kSize);
  const SceneRasterInput input(scene, view, true);
  size_t binEntries = 0;
  for (auto _ : state) {
    VisibilityBuffer target = MakeVisibilityBuffer(kSize, kSize, RasterOutput::kVisibility);
    binEntries = Rasterize(input.Get(), view, RasterOutput::kVisibility, target, nullptr, Kernels(state)).binEntries;
    benchmark::DoNotOptimize(target.depthKey.ConstRow(0));
  }
  ReportCommon(state, scene);
  state.counters["binEntries"] = double(binEntries);
}

// The whole G-buffer pass: RunGBuffer as a renderer keeping its buffers calls it, raster + resolve
// + packing into the G-buffer and visibility buffer of the previous iteration, with specular
// anti-aliasing's `specularAaKappa`.
void GBufferPass(benchmark::State& state, const BenchScene& bench, float specularAaKappa) {
  if (!Begin(state, bench)) return;
  const ThreadLimit threads(int(state.range(2)));
  const Scene& scene = bench.scene;
  const ViewProjection view = MakePerspective(scene.camera, kSize, kSize);
  double rasterMs = 0.0, resolveMs = 0.0;
  size_t covered = 0;
  GBufferOutputs out;  // kept from frame to frame, as a renderer keeps its G-buffer
  for (auto _ : state) {
    if (state.range(3) == 1) out = GBufferOutputs{};  // fresh pages: new buffers, as a one-frame run
    const GBufferStats stats =
        RunGBuffer({scene, view}, {NormalEncoding::kOct24, false, specularAaKappa}, out, Kernels(state));
    rasterMs += stats.rasterMs;
    resolveMs += stats.resolveMs;
    covered = stats.coveredPixels;
    benchmark::DoNotOptimize(out.gbuffer.word[GBufferWord::kDepth].ConstRow(0));
  }
  ReportCommon(state, scene);
  state.counters["rasterMs"] = benchmark::Counter(rasterMs, benchmark::Counter::kAvgIterations);
  state.counters["resolveMs"] = benchmark::Counter(resolveMs, benchmark::Counter::kAvgIterations);
  state.counters["covered"] = double(covered) / double(kPixels);
}

// range(0): the kernel path (Kernels); range(1): the scene (BenchSceneOf); range(2): threads (0 =
// oneTBB's default, all cores); range(3): 1 = fresh pages every frame (UseFreshPages).
void BM_Rasterize(benchmark::State& state) { RasterizeOnly(state, BenchSceneOf(state.range(1))); }
void BM_GBuffer(benchmark::State& state) { GBufferPass(state, BenchSceneOf(state.range(1)), 0.0f); }
// With specular anti-aliasing on: its cost is the ratio to BM_GBuffer's in the same run.
void BM_GBufferSpecularAa(benchmark::State& state) {
  GBufferPass(state, BenchSceneOf(state.range(1)), kSpecularAaKappa);
}

void Configure(benchmark::internal::Benchmark* b) {
  const std::vector<int64_t> scenes = {-1, 0, 10000, 100000, 1000000};
  b->ArgNames({"simd", "scene", "threads", "freshPages"})
      ->ArgsProduct({{0, 1}, scenes, {0, 1, 2}, {0}})
      ->ArgsProduct({{0, 1}, scenes, {0}, {1}})
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_Rasterize)->Apply(Configure);
BENCHMARK(BM_GBuffer)->Apply(Configure);
BENCHMARK(BM_GBufferSpecularAa)->Apply(Configure);

}  // namespace
}  // namespace ssgi

BENCHMARK_MAIN();
