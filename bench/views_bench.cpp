// Many views (`ssgi render-views`, cli/views.h): views per second in one process, over two MPI
// ranks, and as a loop of one-shot `ssgi render`s; the steady-state view against a Table 1 frame and
// one PNG encode; and the bytes and time of each transfer encoding. bench/README.md records results.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bench/bench_scene.h"
#include "cli/image_transfer.h"
#include "cli/views.h"
#include "core/image_io.h"
#include "core/parallel.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr int kSize = 1024;
constexpr int kViews = 24;        // per run of the command
constexpr int kOneShotViews = 8;  // per loop of one-shot renders (each loads the scene)

// A folder of the benchmarks' outputs, removed at exit.
const fs::path& Scratch() {
  static const struct Folder {
    fs::path path = fs::temp_directory_path() / ("ssgi-bench-views-" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } folder;
  return folder.path;
}

// The scene's camera turned about the vertical through its target, views spread over 60 degrees:
// a user walking round the scene.
CameraDesc TurnedCamera(const CameraDesc& camera, int i, int count) {
  const double angle = (double(i) / double(std::max(count - 1, 1)) - 0.5) * (60.0 * 3.14159265358979 / 180.0);
  const glm::dvec3 offset = glm::dvec3(camera.position) - glm::dvec3(camera.target);
  const double c = std::cos(angle), s = std::sin(angle);
  CameraDesc turned = camera;
  turned.position = glm::vec3(glm::dvec3(camera.target) +
                              glm::dvec3(c * offset.x + s * offset.z, offset.y, -s * offset.x + c * offset.z));
  return turned;
}

Json CameraJson(const CameraDesc& camera) {
  const auto v = [](const glm::vec3& p) { return Json::array({p.x, p.y, p.z}); };
  return {{"position", v(camera.position)},
          {"target", v(camera.target)},
          {"up", v(camera.up)},
          {"fov_y_deg", camera.fovYDegrees},
          {"near", camera.nearPlane}};
}

fs::path ScenePath(int64_t scene) {
  return fs::path(SSGI_SOURCE_DATA_DIR) / (scene == -1 ? "scenes/sponza.json" : "default.json");
}

// The views file of kViews turned cameras of the scene.
fs::path ViewsFile(int64_t scene, const CameraDesc& camera) {
  const fs::path file = Scratch() / ("views" + std::to_string(scene) + ".json");
  Json views = Json::array();
  for (int i = 0; i < kViews; ++i) views.push_back({{"camera", CameraJson(TurnedCamera(camera, i, kViews))}});
  std::ofstream(file) << Json{{"views", views}}.dump();
  return file;
}

// Runs a shell command; returns its output, or sets the benchmark's error.
std::string Run(benchmark::State& state, const std::string& command) {
  std::string output;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  size_t n;
  while (pipe && (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0) output.append(buffer, n);
  if (!pipe || ::pclose(pipe) != 0) state.SkipWithError(("failed: " + command + "\n" + output).c_str());
  return output;
}

// Arguments: ranks (1: one process, 2: mpirun -n 2), threads (per process), scene (0 the default
// scene, -1 Sponza). One iteration is one whole run of `ssgi render-views` on kViews views at
// 1024x1024: items are views (wall time, start-up included); `renderingViewsPerS` is the rate the
// command reports from its first view to its last (start-up, the scene's load and MPI's, excluded).
void BM_RenderViewsCommand(benchmark::State& state) {
  const int ranks = int(state.range(0)), threads = int(state.range(1));
  const BenchScene& bench = BenchSceneOf(state.range(2));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
#ifndef SSGI_MPIRUN
  if (ranks > 1) return state.SkipWithError("built without MPI");
  const std::string launcher;
#else
  const std::string launcher = ranks > 1 ? "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                                               std::string(SSGI_MPIRUN) + " -n " + std::to_string(ranks) +
                                               " --oversubscribe --bind-to none "
                                         : "";
#endif
  const fs::path views = ViewsFile(state.range(2), bench.scene.camera);
  const fs::path out = Scratch() / ("command-" + std::to_string(ranks) + "-" + std::to_string(state.range(2)));
  const std::string command = launcher + "'" SSGI_EXECUTABLE "' render-views '" + ScenePath(state.range(2)).string() +
                              "' --views '" + views.string() + "' -o '" + (out / "view_%03d.png").string() +
                              "' --size 1024x1024 --threads " + std::to_string(threads);
  double rate = 0.0;
  for (auto _ : state) {
    const std::string output = Run(state, command);
    // "rendered 24 of 24 views in 5.7 s (4.22 views/s) on ..."
    const size_t line = output.find("rendered ");
    const size_t open = output.find('(', line);
    if (line != std::string::npos && open != std::string::npos) rate += std::atof(output.c_str() + open + 1);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kViews);
  state.counters["renderingViewsPerS"] = rate / double(state.iterations());
}

BENCHMARK(BM_RenderViewsCommand)
    ->ArgNames({"ranks", "threads", "scene"})
    ->Args({1, 2, 0})
    ->Args({2, 1, 0})
    ->Args({1, 2, -1})
    ->Args({2, 1, -1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The loop a user without render-views runs: one `ssgi render` process per view (kOneShotViews
// turned cameras, each a scene file of its own), 2 threads. Items are views.
void BM_RenderOneShotLoop(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  std::ifstream in(ScenePath(state.range(0)));
  Json scene = Json::parse(in);
  for (Json& object : scene["objects"])
    object["obj"] = (ScenePath(state.range(0)).parent_path() / object["obj"].get<std::string>()).string();
  std::vector<std::string> commands;
  for (int i = 0; i < kOneShotViews; ++i) {
    scene["camera"] = CameraJson(TurnedCamera(bench.scene.camera, i, kOneShotViews));
    const fs::path file = Scratch() / ("oneshot" + std::to_string(state.range(0)) + "-" + std::to_string(i) + ".json");
    std::ofstream(file) << scene.dump();
    commands.push_back("'" SSGI_EXECUTABLE "' render '" + file.string() + "' --size 1024x1024 --threads 2 -o '" +
                       (Scratch() / "oneshot.png").string() + "'");
  }
  for (auto _ : state)
    for (const std::string& command : commands) Run(state, command);
  state.SetItemsProcessed(int64_t(state.iterations()) * kOneShotViews);
}

BENCHMARK(BM_RenderOneShotLoop)
    ->ArgNames({"scene"})
    ->Arg(0)
    ->Arg(-1)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The steady state of render-views in one process on 2 threads, as the command runs it
// (ViewRenderer into reused buffers, ViewWriter writing each PNG on its own thread while the next
// view renders): one iteration is one view. cameras 0: the scene's own camera every time (the
// frame of BM_Table1Frame/row:3, to which the target compares it); 1: kViews turned cameras in turn.
void BM_ViewsSteadyState(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(1));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const ThreadLimit threads(2);
  Scene scene = bench.scene;
  FrameConfig config = bench.config;
  config.width = config.height = kSize;
  std::vector<ViewSpec> views(kViews);
  for (int i = 0; i < kViews; ++i)
    views[size_t(i)].camera = state.range(0) ? TurnedCamera(scene.camera, i, kViews) : scene.camera;
  const cli::ViewOutputPattern pattern((Scratch() / "steady_%03d.png").string());
  cli::ViewRenderer renderer(scene, config, ImageFileKind::kPng, {});
  cli::ViewWriter writer(pattern, [](const cli::ViewImage&, const std::string&, double) {});
  cli::ViewImage image;
  // One untimed round: the buffers, the sky's visibility volume, the writer's buffers.
  for (int i = 0; i < kViews; ++i) {
    renderer.Render(views[size_t(i)], i, image);
    writer.Push(image);
  }
  writer.Finish();
  int i = 0;
  for (auto _ : state) {
    renderer.Render(views[size_t(i % kViews)], i % kViews, image);
    writer.Push(image);
    ++i;
  }
  writer.Finish();
  state.SetItemsProcessed(int64_t(state.iterations()));
}

BENCHMARK(BM_ViewsSteadyState)
    ->ArgNames({"cameras", "scene"})
    ->ArgsProduct({{0, 1}, {0, -1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// One 1024x1024 frame of the scene, kept for the encoders.
const cli::ViewImage& SceneImage(int64_t sceneArg) {
  static std::map<int64_t, cli::ViewImage> images;
  auto found = images.find(sceneArg);
  if (found != images.end()) return found->second;
  const BenchScene& bench = BenchSceneOf(sceneArg);
  FrameConfig config = bench.config;
  config.width = config.height = kSize;
  cli::ViewImage image;
  image.width = image.height = kSize;
  image.rgb8 = RenderFrame(bench.scene, config, BufferLifetime::kUntilLastReader).display.rgb;
  return images.emplace(sceneArg, std::move(image)).first->second;
}

// One PNG of the scene's 1024x1024 frame written as render-views writes it (core/image_io.h's
// WritePng, to a temporary file): the encode the target adds to a Table 1 frame.
void BM_PngEncode(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(0));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const cli::ViewImage& image = SceneImage(state.range(0));
  const fs::path file = Scratch() / "encode.png";
  for (auto _ : state) WritePng(file, image.width, image.height, image.rgb8);
  state.counters["bytes"] = double(fs::file_size(file));
}

BENCHMARK(BM_PngEncode)->ArgNames({"scene"})->Arg(0)->Arg(-1)->Unit(benchmark::kMillisecond)->UseRealTime();

// A transfer encoding (0 raw, 1 lz4, 2 jpeg at quality 90) of the scene's 1024x1024 frame as a rank
// sends it to rank 0: the time is the encode's; `bytes` the message's size, `decodeMs` rank 0's
// decode.
void BM_TransferEncoding(benchmark::State& state) {
  const BenchScene& bench = BenchSceneOf(state.range(1));
  if (!bench.error.empty()) return state.SkipWithError(bench.error.c_str());
  const cli::ViewImage& image = SceneImage(state.range(1));
  const auto encoding = cli::TransferEncoding(state.range(0));
  std::vector<uint8_t> message;
  for (auto _ : state) cli::EncodeViewImage(image, encoding, 90, message);
  cli::ViewImage decoded;
  cli::TransferTimes times;
  double decodeMs = 0.0;
  constexpr int kDecodes = 5;
  for (int i = 0; i < kDecodes; ++i) {
    cli::DecodeViewImage(message, decoded, times);
    decodeMs += times.decodeMs;
  }
  state.counters["bytes"] = double(message.size());
  state.counters["decodeMs"] = decodeMs / kDecodes;
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(image.rgb8.size()));
}

BENCHMARK(BM_TransferEncoding)
    ->ArgNames({"encoding", "scene"})
    ->ArgsProduct({{0, 1, 2}, {0, -1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ssgi
