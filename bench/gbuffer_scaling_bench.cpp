// ssgi's side of the G-buffer comparison with llvmpipe (bench/llvmpipe_bench.cpp, the 3x target): the
// whole G-buffer pass on the torus knots at every size and thread count the peer draws, so each
// ratio comes from one run. At 1024x1024 it is BM_GBuffer's work (freshPages:0).
#include <cstdint>

#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/camera.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "passes/gbuffer.h"

namespace ssgi {
namespace {

// range(0): the knot's triangle count; range(1): threads; range(2): the image side (GBufferPeerArgs).
void BM_GBufferSsgi(benchmark::State& state) {
  const BenchScene& bench = KnotScene(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  if (!RetainFreedMemory()) return state.SkipWithError("cannot set the allocator's page reuse (glibc mallopt)");
  const ThreadLimit threads(int(state.range(1)));
  const int size = int(state.range(2));
  const ViewProjection view = MakePerspective(bench.scene.camera, size, size);
  size_t covered = 0;
  // The outputs kept between frames, as llvmpipe's render targets are, and made (and first touched)
  // before timing: at 4096x4096 one repetition is a single frame.
  GBufferOutputs out;
  RunGBuffer({bench.scene, view}, GBufferParams{}, out);
  for (auto _ : state) {
    covered = RunGBuffer({bench.scene, view}, GBufferParams{}, out).coveredPixels;
    benchmark::DoNotOptimize(out.gbuffer.word[GBufferWord::kDepth].ConstRow(0));
  }
  const double pixels = double(size) * double(size);
  state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
  state.counters["pixels"] = benchmark::Counter(pixels, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["covered"] = double(covered) / pixels;
}

BENCHMARK(BM_GBufferSsgi)->Apply(GBufferPeerArgs);

}  // namespace
}  // namespace ssgi
