// `ssgi diff` against the floor it cannot go below: reading its two files. Each iteration reads the
// oracle's and the port's dumps of the default scene at 1024x1024 whole, then runs the diff as
// cli/diff_command.cpp does (both files read, the scene loaded for the coverage classification,
// every layer compared), so that the ratio of the two comes from the same run (docs/design.md §13).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "bench/bench_scene.h"
#include "core/camera.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/stopwatch.h"
#include "passes/frame/diff.h"
#include "passes/frame/dump.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

constexpr int kSize = 1024;

// The oracle's dump of the default scene, and two ports' in a scratch folder removed at exit: the
// same frame with the SSPCSS shadow filter (every layer present, many differing), and a port of the
// direct light alone (its three layers).
struct DiffBenchDumps {
  fs::path folder, oracle, fullPort, directPort;
  std::string error;
  ~DiffBenchDumps() {
    std::error_code ignored;
    if (!folder.empty()) fs::remove_all(folder, ignored);
  }
};

const DiffBenchDumps& Dumps() {
  static const DiffBenchDumps dumps = [] {
    DiffBenchDumps d;
    const BenchScene& scene = DefaultBenchScene();
    if (!scene.error.empty()) {
      d.error = scene.error;
      return d;
    }
    d.folder = fs::temp_directory_path() / ("ssgi_diff_bench." + std::to_string(::getpid()));
    fs::create_directories(d.folder);
    d.oracle = d.folder / "oracle.exr";
    d.fullPort = d.folder / "sspcss.exr";
    d.directPort = d.folder / "direct.exr";
    FrameConfig config = scene.config;
    config.width = config.height = kSize;
    const std::string scenePath = fs::absolute(SSGI_SOURCE_DATA_DIR "/default.json").string();
    WriteFrameDump(d.oracle, RenderFrame(scene.scene, config), DumpMetadata(scenePath, config));
    FrameConfig other = config;
    ApplySetting(other, "shadow_filter", "sspcss");
    WriteFrameDump(d.fullPort, RenderFrame(scene.scene, other), DumpMetadata(scenePath, other));
    ExrFile direct = ReadExrFile(
        d.fullPort, [](const std::string&, const std::string& name) { return name.rfind("direct.", 0) == 0; });
    std::erase_if(direct.layers, [](const ExrLayer& layer) { return layer.samples.empty(); });
    WriteExrFile(d.directPort, direct);
    return d;
  }();
  return dumps;
}

// What `ssgi diff ORACLE PORT` computes, all but the printing.
DiffReport RunDiff(const fs::path& oraclePath, const fs::path& portPath, const DiffThresholds& thresholds) {
  const ExrFile port = ReadExrFile(portPath);
  const ExrFile oracle = ReadExrFile(oraclePath, OracleLayersToRead(port));
  const DumpScene scene = LoadDumpScene(oracle, oraclePath, "");
  const ViewProjection view = MakePerspective(scene.scene.camera, scene.config.width, scene.config.height);
  return DiffDumps(oracle, port, thresholds, CoverageGeometry{scene.scene.mesh, view});
}

// range(0): threads; range(1): the port, 0 the SSPCSS frame (every layer), 1 the direct light
// alone. The iteration's time is the diff's; readMs is reading both files whole in the same
// iteration, and diffPerRead the ratio of the two (the target: at most 2 for port:0).
void BM_DiffDumps(benchmark::State& state) {
  const DiffBenchDumps& dumps = Dumps();
  if (!dumps.error.empty()) {
    state.SkipWithError(dumps.error.c_str());
    return;
  }
  const ThreadLimit threads(int(state.range(0)));
  const fs::path& port = state.range(1) == 0 ? dumps.fullPort : dumps.directPort;
  const DiffThresholds thresholds = LoadDiffThresholds(SSGI_SOURCE_DATA_DIR "/diff_thresholds.json");
  double readMs = 0.0, diffMs = 0.0;
  size_t layers = 0;
  for (auto _ : state) {
    Stopwatch read;
    {
      const ExrFile a = ReadExrFile(dumps.oracle);
      const ExrFile b = ReadExrFile(port);
      benchmark::DoNotOptimize(a.layers.data());
      benchmark::DoNotOptimize(b.layers.data());
    }
    readMs += read.Milliseconds();
    Stopwatch diff;
    const DiffReport report = RunDiff(dumps.oracle, port, thresholds);
    const double ms = diff.Milliseconds();
    diffMs += ms;
    state.SetIterationTime(ms / 1000.0);
    layers = 0;
    for (const LayerDiff& layer : report.layers) layers += layer.compared ? 1 : 0;
  }
  const double iterations = double(state.iterations());
  state.counters["readMs"] = readMs / iterations;
  state.counters["diffPerRead"] = diffMs / readMs;
  state.counters["layersCompared"] = double(layers);
}
BENCHMARK(BM_DiffDumps)
    ->ArgNames({"threads", "port"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ssgi
