// ssgi's side of the fill-rate comparison (llvmpipe's is in bench/llvmpipe_bench.cpp):
// the rasterizer alone (core/raster/raster.h) on FillrateTriangles, visibility output, at 1 and 2 threads.
// The G-buffer pass is not measured here: it resolves each pixel once, after the raster, so the
// overdraw of these scenes would only show in its raster half.
#include <cstdint>

#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "core/raster/raster.h"

namespace ssgi {
namespace {

// range(0): the triangles' area in pixels; range(1): threads.
void BM_FillrateRasterize(benchmark::State& state) {
  if (!RetainFreedMemory()) return state.SkipWithError("cannot set the allocator's page reuse (glibc mallopt)");
  const FillrateScene& scene = FillrateTriangles(int(state.range(0)));
  const ThreadLimit threads(int(state.range(1)));
  RasterInput input;
  input.positions = scene.positions.data();
  input.vertexCount = scene.positions.size();
  input.indices = scene.indices.data();
  input.triangleCount = scene.TriangleCount();
  for (auto _ : state) {
    VisibilityBuffer target = MakeVisibilityBuffer(kFillrateSize, kFillrateSize, RasterOutput::kVisibility);
    Rasterize(input, scene.view, RasterOutput::kVisibility, target);
    benchmark::DoNotOptimize(target.depthKey.ConstRow(0));
  }
  ReportFillrate(state, scene);
}

BENCHMARK(BM_FillrateRasterize)->Apply(FillrateArgs);

}  // namespace
}  // namespace ssgi
