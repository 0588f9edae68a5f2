// Diffuse bounce and ambient occlusion (passes/bounce.h) at 1024x1024 on the default scene and on
// Sponza: the whole pass (prepare, march, filter, upsample) with either kernel path at 1 and 2
// threads, the default settings and a few others, beside the memory floor of its full-resolution
// bytes. Inputs are one frame of each scene (its G-buffer and its lit image: direct plus sky light),
// made once; outputs are reused between iterations (the steady state of a renderer).
// docs/pipeline.md (§Diffuse bounce and ambient occlusion) records results.
#include <benchmark/benchmark.h>

#include <map>
#include <mutex>
#include <utility>

#include "bench/bench_scene.h"
#include "bench/memory_floor.h"
#include "passes/bounce.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

constexpr int kSize = 1024;

// One frame of the scene at kSize x kSize, rendered once.
const Frame& SceneFrame(const BenchScene& bench) {
  static std::mutex mutex;
  static std::map<const BenchScene*, Frame> frames;
  const std::lock_guard<std::mutex> lock(mutex);
  auto found = frames.find(&bench);
  if (found == frames.end()) {
    FrameConfig config = bench.config;
    config.width = config.height = kSize;
    found = frames.emplace(&bench, RenderFrame(bench.scene, config)).first;
  }
  return found->second;
}

// Arguments: scene (BenchSceneOf: 0 the default scene, -1 Sponza, skipped where its model is not
// fetched), simd (1 KernelPath::kSimd, 0 kScalar), threads, slices, steps (0: the defaults).
// Items: full-resolution pixels. Counters: each step's milliseconds (the last iteration's) and the
// march's depth samples per half-resolution pixel.
void BM_Bounce(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const KernelPath kernels = state.range(1) ? KernelPath::kSimd : KernelPath::kScalar;
  const ThreadLimit threads(int(state.range(2)));
  BounceParams params;
  if (state.range(3) > 0) params.slices = int(state.range(3));
  if (state.range(4) > 0) params.steps = int(state.range(4));
  const Frame& frame = SceneFrame(bench);
  const BounceInputs in{frame.gbuffer.gbuffer, frame.view, frame.Lit()};
  BounceOutputs out;
  BounceStats stats = RunBounce(in, params, out, kernels);  // allocates the outputs
  for (auto _ : state) stats = RunBounce(in, params, out, kernels);
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(stats.pixels));
  state.counters["prepareMs"] = stats.prepareMs;
  state.counters["marchMs"] = stats.marchMs;
  state.counters["filterMs"] = stats.filterMs;
  state.counters["upsampleMs"] = stats.upsampleMs;
  const double halfPixels = double(((kSize + 1) / 2) * ((kSize + 1) / 2));
  state.counters["tapsPerPixel"] = double(stats.taps) / halfPixels;
}

BENCHMARK(BM_Bounce)
    ->ArgNames({"scene", "simd", "threads", "slices", "steps"})
    ->ArgsProduct({{0, -1}, {1}, {1, 2}, {0}, {0}})
    ->ArgsProduct({{0}, {0}, {1}, {0}, {0}})
    ->ArgsProduct({{0, -1}, {1}, {2}, {1, 2, 3, 4}, {2, 4, 8}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The pass's full-resolution bytes per pixel: G-buffer words 1 and 2 read (8), visibility and bounce
// written (16); its half-resolution buffers and the lit image's even rows come on top.
[[maybe_unused]] const bool kBounceFloor = (RegisterMemoryFloor(8, 16), true);

}  // namespace
}  // namespace ssgi
