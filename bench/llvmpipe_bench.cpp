// The peer (docs/design.md §13, the G-buffer target): Mesa's llvmpipe drawing what ssgi draws, in the same binary and
// run, so that bench/README.md quotes ratios. BM_GBufferLlvmpipe writes ssgi's G-buffer for the
// torus knots (BM_GBufferSsgi's arguments and camera), BM_FillrateLlvmpipe the visibility buffer of
// the fill-rate triangles (BM_FillrateRasterize's). Every frame is clear + draw + glFinish into
// render targets made before timing. Where no llvmpipe context can be had the benchmarks skip,
// saying why.
#include <cstdint>
#include <exception>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "bench/bench_scene.h"
#include "bench/egl_context.h"
#include "bench/gl_gbuffer.h"
#include "core/camera.h"
#include "core/gbuffer.h"

namespace ssgi {
namespace {

// The llvmpipe context with `threads` raster threads: opened on first use and kept while the
// benchmarks ask for that count (one context at a time, bench/egl_context.h). Null when none can be
// had, with `error` saying why.
LlvmpipeContext* ContextWithThreads(int threads, std::string& error) {
  static std::unique_ptr<LlvmpipeContext> context;
  if (context != nullptr && context->rasterThreads() == threads) return context.get();
  context.reset();
  context = LlvmpipeContext::Open(threads, error);
  return context.get();
}

// range(0): the knot's triangle count; range(1): llvmpipe's raster threads; range(2): the image side.
void BM_GBufferLlvmpipe(benchmark::State& state) {
  const BenchScene& bench = KnotScene(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  std::string error;
  if (ContextWithThreads(int(state.range(1)), error) == nullptr) return state.SkipWithError(error.c_str());
  const int size = int(state.range(2));
  const ViewProjection view = MakePerspective(bench.scene.camera, size, size);
  size_t covered = 0;
  try {
    const Mesh& mesh = bench.scene.mesh;
    const GlMesh glMesh(mesh.positions, mesh.normals, mesh.indices);
    const GlGBufferPass pass(size, size);
    pass.Draw(glMesh, view, bench.scene.materials[0]);  // compiles llvmpipe's shader variants
    for (auto _ : state) pass.Draw(glMesh, view, bench.scene.materials[0]);
    const Plane<uint32_t> depth = pass.ReadTarget(2);
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) covered += UnpackDepth(depth.ConstRow(size_t(y))[x]) != kBackgroundDepth;
    }
  } catch (const std::exception& e) {
    return state.SkipWithError(e.what());
  }
  const double pixels = double(size) * double(size);
  state.SetItemsProcessed(int64_t(state.iterations()) * state.range(0));
  state.counters["pixels"] = benchmark::Counter(pixels, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["covered"] = double(covered) / pixels;
}

// range(0): the triangles' area in pixels; range(1): llvmpipe's raster threads.
void BM_FillrateLlvmpipe(benchmark::State& state) {
  std::string error;
  if (ContextWithThreads(int(state.range(1)), error) == nullptr) return state.SkipWithError(error.c_str());
  const FillrateScene& scene = FillrateTriangles(int(state.range(0)));
  try {
    const GlMesh glMesh(scene.positions, {}, scene.indices);
    const GlVisibilityPass pass(kFillrateSize, kFillrateSize);
    pass.Draw(glMesh, scene.view);
    for (auto _ : state) pass.Draw(glMesh, scene.view);
  } catch (const std::exception& e) {
    return state.SkipWithError(e.what());
  }
  ReportFillrate(state, scene);
}

BENCHMARK(BM_GBufferLlvmpipe)->Apply(GBufferPeerArgs);
BENCHMARK(BM_FillrateLlvmpipe)->Apply(FillrateArgs);

}  // namespace
}  // namespace ssgi
