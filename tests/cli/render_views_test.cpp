// End-to-end tests of `ssgi render-views`: each view's bytes equal `ssgi render` of its camera, in any
// order of the views (reused buffers leak nothing), camera paths, failing views, bad views files,
// --resume, and over MPI ranks: the bytes of one process, and a killed rank resumed.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "tests/test_support.h"

extern char** environ;

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

Json Camera(std::array<float, 3> position, std::array<float, 3> target, float fov = 40.0f) {
  return Json{{"position", position}, {"target", target}, {"fov_y_deg", fov}};
}

// Views of the default scene that differ in what they need: the mirror sphere close up (most tiles
// reflect), the rough floor from above (few do), the sky over the board (little geometry), a view
// of its own size, and one with the sun turned (a time of day).
Json SomeViews() {
  Json views = Json::array();
  views.push_back({{"camera", Camera({0.6f, 0.8f, 0.2f}, {0.25f, 0.45f, -1.25f}, 35.0f)}});
  views.push_back({{"camera", Camera({0.0f, 6.0f, 0.5f}, {0.0f, 0.0f, 0.0f})}});
  views.push_back({{"camera", Camera({0.0f, 0.3f, 3.0f}, {0.0f, 2.5f, -4.0f})}, {"size", "61x47"}});
  views.push_back(
      {{"camera", Camera({0.0f, 2.7f, 5.6f}, {0.0f, 0.25f, -0.05f})}, {"light_direction", {0.7f, -0.5f, 0.2f}}});
  views.push_back({{"camera", Camera({-3.0f, 1.5f, 2.0f}, {0.2f, 0.3f, -0.5f}, 50.0f)}});
  return views;
}

// data/default.json with this camera (and light direction), its models named by absolute path so the
// file can live anywhere.
void WriteSceneWithCamera(const fs::path& file, const Json& view) {
  std::ifstream in(SourceDir() / "data" / "default.json");
  Json scene = Json::parse(in);
  scene["camera"] = view["camera"];
  if (view.contains("light_direction")) scene["lights"][0]["direction"] = view["light_direction"];
  for (Json& object : scene["objects"])
    object["obj"] = (SourceDir() / "data" / object["obj"].get<std::string>()).string();
  std::ofstream(file) << scene.dump(2);
}

void WriteViews(const fs::path& file, const Json& views) { std::ofstream(file) << Json{{"views", views}}.dump(2); }

constexpr const char* kSize = "--size 96x72 --threads 2";

std::string ViewName(int index) {
  char name[32];
  std::snprintf(name, sizeof(name), "view_%03d.png", index);
  return name;
}

TEST_CASE("render-views: each view is byte-identical to `ssgi render` of its camera, in any order",
          "[cli][views][determinism]") {
  ScratchDir dir("views-order");
  const Json views = SomeViews();
  const int n = int(views.size());
  // In order, reversed and shuffled: the same camera gives the same bytes wherever it comes.
  const std::vector<std::vector<int>> orders = {{0, 1, 2, 3, 4}, {4, 3, 2, 1, 0}, {2, 0, 4, 1, 3}};
  std::vector<std::vector<std::string>> bytes(orders.size(), std::vector<std::string>(size_t(n)));
  for (size_t o = 0; o < orders.size(); ++o) {
    Json ordered = Json::array();
    for (int i : orders[o]) ordered.push_back(views[size_t(i)]);
    const fs::path viewsFile = dir / ("views" + std::to_string(o) + ".json");
    WriteViews(viewsFile, ordered);
    const fs::path out = dir / ("out" + std::to_string(o));
    const CommandResult result = RunCli("render-views " + DefaultSceneArg() + " --views " + Quote(viewsFile) + " -o " +
                                        Quote(out / "view_%03d.png") + " " + kSize);
    CAPTURE(o, result.output);
    REQUIRE(result.exitCode == 0);
    CHECK(result.output.find("rendered 5 of 5 views") != std::string::npos);
    for (int k = 0; k < n; ++k) bytes[o][size_t(orders[o][size_t(k)])] = ReadFileBytes(out / ViewName(k));
    CHECK(fs::exists(out / "manifest.json"));
  }
  for (int i = 0; i < n; ++i) {
    CAPTURE(i);
    REQUIRE(!bytes[0][size_t(i)].empty());
    CHECK(bytes[1][size_t(i)] == bytes[0][size_t(i)]);
    CHECK(bytes[2][size_t(i)] == bytes[0][size_t(i)]);
    // `ssgi render` of a scene file with this camera (and light), at this view's size.
    const fs::path scene = dir / ("scene" + std::to_string(i) + ".json");
    WriteSceneWithCamera(scene, views[size_t(i)]);
    const std::string size = views[size_t(i)].contains("size") ? views[size_t(i)]["size"].get<std::string>() : "96x72";
    const fs::path single = dir / ("single" + std::to_string(i) + ".png");
    const CommandResult render = RunCli("render " + Quote(scene) + " -o " + Quote(single) + " --size " + size);
    CAPTURE(render.output);
    REQUIRE(render.exitCode == 0);
    CHECK(ReadFileBytes(single) == bytes[0][size_t(i)]);
  }
}

TEST_CASE("render-views: a camera path interpolates its keyframes", "[cli][views]") {
  ScratchDir dir("views-path");
  // Three frames over two keyframes: the middle one is the cameras' midpoint, exact in float.
  const Json path = {{"path",
                      {{"keyframes",
                        {{{"camera", Camera({-2.0f, 2.0f, 4.0f}, {0.0f, 0.0f, -1.0f})}},
                         {{"camera", Camera({2.0f, 3.0f, 4.0f}, {0.0f, 1.0f, -1.0f}, 50.0f)}}}},
                       {"frames", 3}}}};
  std::ofstream(dir / "path.json") << path.dump();
  WriteViews(dir / "middle.json", Json::array({{{"camera", Camera({0.0f, 2.5f, 4.0f}, {0.0f, 0.5f, -1.0f}, 45.0f)}}}));
  const CommandResult a = RunCli("render-views " + DefaultSceneArg() + " --views " + Quote(dir / "path.json") + " -o " +
                                 Quote(dir / "path_%d.png") + " " + kSize);
  CAPTURE(a.output);
  REQUIRE(a.exitCode == 0);
  const CommandResult b = RunCli("render-views " + DefaultSceneArg() + " --views " + Quote(dir / "middle.json") +
                                 " -o " + Quote(dir / "mid" / "m_%d.png") + " " + kSize);
  CAPTURE(b.output);
  REQUIRE(b.exitCode == 0);
  CHECK(ReadFileBytes(dir / "path_1.png") == ReadFileBytes(dir / "mid" / "m_0.png"));
  CHECK(ReadFileBytes(dir / "path_0.png") != ReadFileBytes(dir / "path_1.png"));
  CHECK(fs::exists(dir / "path_2.png"));
}

TEST_CASE("render-views: a failing view is reported by its index and the others are written", "[cli][views]") {
  ScratchDir dir("views-fail");
  Json views = SomeViews();
  views[1]["camera"]["target"] = views[1]["camera"]["position"];  // no view direction
  views[3]["size"] = "0x10";
  WriteViews(dir / "views.json", views);
  const CommandResult result = RunCli("render-views " + DefaultSceneArg() + " --views " + Quote(dir / "views.json") +
                                      " -o " + Quote(dir / "out" / "view_%03d.png") + " " + kSize);
  CAPTURE(result.output);
  CHECK(result.exitCode == 1);
  CHECK(result.output.find("ssgi: view 1 failed: ") != std::string::npos);
  CHECK(result.output.find("views[1].camera.target must differ") != std::string::npos);
  CHECK(result.output.find("ssgi: view 3 failed: ") != std::string::npos);
  CHECK(result.output.find("views[3].size") != std::string::npos);
  CHECK(result.output.find("2 of 5 views failed (view 1, 3)") != std::string::npos);
  for (int i : {0, 2, 4}) CHECK(fs::exists(dir / "out" / ViewName(i)));
  for (int i : {1, 3}) CHECK_FALSE(fs::exists(dir / "out" / ViewName(i)));
  const Json manifest = Json::parse(ReadFileBytes(dir / "out" / "manifest.json"));
  CHECK(manifest["delivered"] == Json::array({0, 2, 4}));
}

TEST_CASE("render-views: a bad views file or pattern fails with one line and writes nothing", "[cli][views]") {
  ScratchDir dir("views-bad");
  const auto write = [&](const std::string& name, const std::string& text) {
    WriteText(dir / name, text);
    return Quote(dir / name);
  };
  const std::string out = " -o " + Quote(dir / "out" / "v_%d.png");
  const std::string good =
      write("good.json", R"({"views": [{"camera": {"position": [0, 1, 4], "target": [0, 0, 0]}}]})");
  CheckCliErrors({
      {"render-views --views " + write("a.json", "{\"views\": [\n  {\"camera\": ") + out, "a.json:2", 1},
      {"render-views --views " + write("b.json", "{}") + out, "needs \"views\"", 1},
      {"render-views --views " + write("c.json", R"({"views": []})") + out, "views must be a non-empty array", 1},
      {"render-views --views " + write("d.json", R"({"views": [], "camras": 1})") + out, "unknown key camras", 1},
      {"render-views --views " + write("e.json", R"({"path": {"keyframes": [], "frames": 3}})") + out,
       "path.keyframes must be a non-empty array", 1},
      {"render-views --views " +
           write(
               "f.json",
               R"({"path": {"keyframes": [{"camera": {"position": [0, 1, 4], "target": [0, 0, 0]}}], "frames": 0}})") +
           out,
       "path.frames must be a whole number", 1},
      {"render-views --views " + write("g.json", "[1, 2]") + out, "g.json:1", 1},
      {"render-views --views " + Quote(dir / "missing.json") + out, "missing.json", 1},
      {"render-views --views " + good + " -o " + Quote(dir / "v.png"), "needs a %d", 1},
      {"render-views --views " + good + " -o " + Quote(dir / "v_%d_%d.png"), "not several", 1},
      {"render-views --views " + good + " -o " + Quote(dir / "v_%s.png"), "one integer", 1},
      {"render-views --views " + good + " -o " + Quote(dir / "v_%d.jpg"), "unsupported output format", 1},
      {"render-views --views " + good + " -o " + Quote(dir / "v_%d.exr") + " --encoding jpeg", "8-bit", 1},
      {"render-views --views " + good + out + " --encoding gzip", "--encoding", 2},
  });
  RequireOnlyFiles(dir, {"a.json", "b.json", "c.json", "d.json", "e.json", "f.json", "g.json", "good.json"});
}

TEST_CASE("render-views: --resume renders only the views missing from the manifest", "[cli][views]") {
  ScratchDir dir("views-resume");
  WriteViews(dir / "views.json", SomeViews());
  const std::string command = "render-views " + DefaultSceneArg() + " --views " + Quote(dir / "views.json") + " -o " +
                              Quote(dir / "out" / "view_%03d.png") + " " + kSize;
  REQUIRE(RunCli(command).exitCode == 0);
  const std::string second = ReadFileBytes(dir / "out" / ViewName(2));
  fs::remove(dir / "out" / ViewName(2));
  // A manifest that lost view 4, as if the run had died before delivering it.
  Json manifest = Json::parse(ReadFileBytes(dir / "out" / "manifest.json"));
  manifest["delivered"] = Json::array({0, 1, 2, 3});
  std::ofstream(dir / "out" / "manifest.json") << manifest.dump();
  const CommandResult resumed = RunCli(command + " --resume");
  CAPTURE(resumed.output);
  REQUIRE(resumed.exitCode == 0);
  CHECK(resumed.output.find("resuming: 3 of 5 views delivered, 2 to render") != std::string::npos);
  CHECK(resumed.output.find("rendered 2 of 2 views") != std::string::npos);
  CHECK(ReadFileBytes(dir / "out" / ViewName(2)) == second);
  CHECK(Json::parse(ReadFileBytes(dir / "out" / "manifest.json"))["delivered"] == Json::array({0, 1, 2, 3, 4}));
  // Another run's manifest is refused.
  WriteViews(dir / "other.json", SomeViews());
  const CommandResult other = RunCli("render-views " + DefaultSceneArg() + " --views " + Quote(dir / "other.json") +
                                     " -o " + Quote(dir / "out" / "view_%03d.png") + " --resume " + kSize);
  CHECK(other.exitCode == 1);
  CHECK(other.output.find("another run") != std::string::npos);
}

#ifdef SSGI_TEST_MPIRUN

// `mpirun -n ranks` of ssgi with these arguments, as root where the tests run as root.
std::string MpirunArguments(int ranks, const std::string& arguments) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 " +
         std::string(SSGI_TEST_MPIRUN) + " -n " + std::to_string(ranks) + " --oversubscribe --bind-to none " +
         Quote(CliPath()) + " " + arguments;
}

CommandResult Mpirun(int ranks, const std::string& arguments) {
  return RunProgram("/usr/bin/env", MpirunArguments(ranks, arguments));
}

// Many small views, so that a run lasts long enough to be interrupted.
Json ManyViews(int count) {
  Json views = Json::array();
  for (int i = 0; i < count; ++i) {
    const float angle = 0.13f * float(i);
    views.push_back({{"camera", Camera({4.0f * std::sin(angle), 1.5f + 0.05f * float(i % 7), 4.0f * std::cos(angle)},
                                       {0.0f, 0.3f, 0.0f})}});
  }
  return views;
}

TEST_CASE("render-views over 2 MPI ranks gives the bytes of one process", "[cli][views][mpi]") {
  ScratchDir dir("views-mpi");
  WriteViews(dir / "views.json", SomeViews());
  const std::string views = DefaultSceneArg() + " --views " + Quote(dir / "views.json") + " " + kSize;
  REQUIRE(RunCli("render-views " + views + " -o " + Quote(dir / "one" / "view_%03d.png")).exitCode == 0);
  REQUIRE(RunCli("render-views " + views + " -o " + Quote(dir / "one" / "view_%03d.exr")).exitCode == 0);
  for (const std::string mode : {"--encoding lz4", "--encoding raw", "--write-on-rank"}) {
    CAPTURE(mode);
    const fs::path out = dir / ("mpi" + std::to_string(mode.size()));
    const CommandResult png = Mpirun(2, "render-views " + views + " " + mode + " -o " + Quote(out / "view_%03d.png"));
    CAPTURE(png.output);
    REQUIRE(png.exitCode == 0);
    CHECK(png.output.find("on 2 ranks") != std::string::npos);
    if (mode != "--write-on-rank") CHECK(png.output.find("KiB per view") != std::string::npos);
    for (int i = 0; i < 5; ++i) CHECK(ReadFileBytes(out / ViewName(i)) == ReadFileBytes(dir / "one" / ViewName(i)));
  }
  // EXR: the same pixels (the header carries a date).
  const CommandResult exr = Mpirun(2, "render-views " + views + " -o " + Quote(dir / "mpiexr" / "view_%03d.exr"));
  CAPTURE(exr.output);
  REQUIRE(exr.exitCode == 0);
  for (int i = 0; i < 5; ++i) {
    const std::string name = "view_00" + std::to_string(i) + ".exr";
    const StoredImage a = ReadStoredImage(dir / "mpiexr" / name), b = ReadStoredImage(dir / "one" / name);
    CHECK(a.width == b.width);
    CHECK(a.bytes == b.bytes);
  }
  // JPEG: lossy, but every view arrives.
  const CommandResult jpeg =
      Mpirun(2, "render-views " + views + " --encoding jpeg -o " + Quote(dir / "jpeg" / "v_%d.png"));
  CAPTURE(jpeg.output);
  REQUIRE(jpeg.exitCode == 0);
  for (int i = 0; i < 5; ++i) CHECK(fs::exists(dir / "jpeg" / ("v_" + std::to_string(i) + ".png")));
}

// The process of this mpirun that is rank `rank` (its environment says so), or -1.
pid_t RankProcess(pid_t mpirun, int rank) {
  const std::string wanted = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::istringstream stat(ReadFileBytes(entry.path() / "stat"));
    std::string pid, comm, state;
    pid_t parent = 0;
    stat >> pid >> comm >> state >> parent;
    if (parent != mpirun) continue;
    const std::string environment = ReadFileBytes(entry.path() / "environ");
    for (size_t at = 0; at < environment.size(); at = environment.find('\0', at) + 1) {
      if (environment.compare(at, wanted.size() + 1, wanted + '\0') == 0) return pid_t(std::stoi(name));
      if (environment.find('\0', at) == std::string::npos) break;
    }
  }
  return -1;
}

TEST_CASE("render-views over MPI: a killed rank ends the run, and --resume completes it with the same bytes",
          "[cli][views][mpi]") {
  ScratchDir dir("views-kill");
  constexpr int kViews = 200;  // enough that a loaded machine does not finish before the kill
  WriteViews(dir / "views.json", ManyViews(kViews));
  const std::string views = DefaultSceneArg() + " --views " + Quote(dir / "views.json") + " --size 200x150 --threads 1";
  const CommandResult whole = Mpirun(2, "render-views " + views + " -o " + Quote(dir / "whole" / "view_%03d.png"));
  CAPTURE(whole.output);
  REQUIRE(whole.exitCode == 0);

  // The same run, with rank 1 killed once rank 0 has delivered a few views.
  fs::create_directories(dir / "cut");
  const std::string command =
      "exec /usr/bin/env " +
      MpirunArguments(2, "render-views " + views + " -o " + Quote(dir / "cut" / "view_%03d.png")) + " > " +
      Quote(dir / "cut.log") + " 2>&1";
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  pid_t mpirun = 0;
  REQUIRE(posix_spawn(&mpirun, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) == 0);
  const fs::path manifest = dir / "cut" / "manifest.json";
  pid_t victim = -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    std::error_code error;
    if (fs::exists(manifest, error)) {
      const std::string text = ReadFileBytes(manifest);
      if (Json::accept(text) && Json::parse(text)["delivered"].size() >= 4) {
        victim = RankProcess(mpirun, 1);
        if (victim > 0) break;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  REQUIRE(victim > 0);
  ::kill(victim, SIGKILL);
  int status = 0;
  ::waitpid(mpirun, &status, 0);
  CAPTURE(ReadFileBytes(dir / "cut.log"));
  // The run ended without finishing, and what it delivered is whole.
  REQUIRE(!(WIFEXITED(status) && WEXITSTATUS(status) == 0));
  const Json delivered = Json::parse(ReadFileBytes(manifest))["delivered"];
  CHECK(delivered.size() < size_t(kViews));
  for (const Json& index : delivered)
    CHECK(ReadFileBytes(dir / "cut" / ViewName(index.get<int>())) ==
          ReadFileBytes(dir / "whole" / ViewName(index.get<int>())));

  const CommandResult resumed =
      Mpirun(2, "render-views " + views + " --resume -o " + Quote(dir / "cut" / "view_%03d.png"));
  CAPTURE(resumed.output);
  REQUIRE(resumed.exitCode == 0);
  CHECK(resumed.output.find("resuming: " + std::to_string(delivered.size()) + " of " + std::to_string(kViews)) !=
        std::string::npos);
  for (int i = 0; i < kViews; ++i) {
    CAPTURE(i);
    CHECK(ReadFileBytes(dir / "cut" / ViewName(i)) == ReadFileBytes(dir / "whole" / ViewName(i)));
  }
  // Only the images and the manifest: the temporaries a killed process may leave (SIGKILL runs no
  // handler) are swept by the next run.
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "cut")) {
    CAPTURE(entry.path().filename().string());
    CHECK(entry.path().filename().string()[0] != '.');
    ++files;
  }
  CHECK(files == size_t(kViews) + 1);
}

#endif

}  // namespace
}  // namespace ssgi::test
