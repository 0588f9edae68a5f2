// Scenes shared by the benchmarks.
#pragma once

#include <string>

#include <benchmark/benchmark.h>

#include "core/kernel_path.h"
#include "core/parallel.h"
#include "core/scene.h"
#include "passes/frame.h"
#include "passes/frame_config.h"

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
