// Scenes shared by the benchmarks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/kernel_path.h"
#include "core/parallel.h"
#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/frame/config.h"

namespace ssgi {

// A scene to draw, or why it could not be built.
struct BenchScene {
  Scene scene;
  FrameConfig config;  // the scene file's render block
  std::string error;
};

// data/default.json with its frame configuration, loaded once; a missing or malformed file becomes the error every benchmark that
// needs it reports.
const BenchScene& DefaultBenchScene();

// A torus knot (core/procedural_mesh.h) of exactly `triangles` triangles (10k, 30k, 100k, 300k or
// 1M; 10k, 100k and 1M are the sizes docs/design.md §13 gives for llvmpipe), default material, seen along
// its symmetry axis so it fills most of a square image: 68% of it, with many silhouettes and
// self-occlusion. Made once per size; another count gives a scene whose error says so.
const BenchScene& KnotScene(int64_t triangles);

// The scene a benchmark's `scene` argument names: 0 the default scene, -1 data/scenes/sponza.json
// (Dabrovic Sponza in data/scenes/models, fetched by data/scenes/fetch.sh: 66k triangles, textured,
// alpha cut-outs; loaded once, and where the model is absent its error says so and how to fetch it,
// and the benchmark skips), else the knot of that many triangles.
const BenchScene& BenchSceneOf(int64_t scene);

// The arguments of the G-buffer comparison with llvmpipe, the same for ssgi (BM_GBufferSsgi) and the
// peer (BM_GBufferLlvmpipe): scene (a KnotScene's triangle count), threads (1 or 2), size (of the
// square image). The knots of docs/design.md §13 at 1 and 2 threads at 1024x1024, and at 2 threads every
// knot at 1024 and the 100k knot from 512 to 4096, the two sweeps docs/user-guide.md plots.
void GBufferPeerArgs(benchmark::internal::Benchmark* benchmark);

// Random triangles for the fill-rate benchmarks, in the style of Intel's Masked Occlusion Culling
// FillrateTest: right isosceles triangles of one area, randomly rotated and placed wholly inside a
// 1024x1024 image, drawn back to front (each nearer than all before it), so every covered sample
// passes the depth test and is written: the most work per pixel. About 8 Mpixels per frame (eight
// screens) whatever the area. The random numbers are std::mt19937's from a fixed seed, turned into
// floats by bit shifts, so every run draws the same triangles.
struct FillrateScene {
  std::vector<glm::vec3> positions;  // three per triangle, world space of `view`
  std::vector<uint32_t> indices;     // 0, 1, 2, ... (unshared vertices)
  ViewProjection view;               // orthographic: world x, y are pixels from the image centre, y up
  int areaPixels = 0;                // of each triangle
  size_t TriangleCount() const { return indices.size() / 3; }
};
inline constexpr int kFillrateSize = 1024;
// Made once per area.
const FillrateScene& FillrateTriangles(int areaPixels);
// The arguments of every fill-rate benchmark: area (pixels, 10 to 500: most triangles of real scenes
// cover fewer than 16x16 pixels), threads (1 or 2).
void FillrateArgs(benchmark::internal::Benchmark* benchmark);
// Counters of a fill-rate benchmark: items_per_second are triangles per second, pixels the pixels
// written per second (triangles x area, as FillrateTest counts them).
void ReportFillrate(benchmark::State& state, const FillrateScene& scene);

// One whole frame of the default scene at size x size, rendered once per size: its buffers are the
// inputs of the benchmarks of single passes.
const Frame& DefaultBenchFrame(int size);

// The arguments of a benchmark of one pass on a DefaultBenchFrame, either kernel path: simd (1:
// KernelPath::kSimd, 0: kScalar), size (of the square image, 1024 or 2048), threads (1 or 2, the cap
// on oneTBB while this lives). KernelBenchArgs::Register gives a benchmark those arguments.
struct KernelBenchArgs {
  explicit KernelBenchArgs(const benchmark::State& state)
      : kernels(state.range(0) ? KernelPath::kSimd : KernelPath::kScalar),
        size(int(state.range(1))),
        threads(int(state.range(2))) {}
  static void Register(benchmark::internal::Benchmark* benchmark) {
    benchmark->ArgNames({"simd", "size", "threads"})
        ->ArgsProduct({{0, 1}, {1024, 2048}, {1, 2}})
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }

  KernelPath kernels;
  int size;
  ThreadLimit threads;
};

}  // namespace ssgi
