// Every command as careful as `render`: memory guards, all-or-nothing outputs (on failure, on a
// signal and on a full disk), one-line refusals of bad input with nothing left behind, and the small
// things a user trips on. The corpus of bad inputs here is held out from the commands' own code: each
// case runs the built executable.
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <thread>

#include "core/image_compare.h"
#include "passes/tonemap.h"
#include "tests/test_support.h"

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;

// A small dump of the default scene, and a copy of it, made once per test case that needs them.
struct Dumps {
  explicit Dumps(const ScratchDir& dir) : oracle(dir / "oracle.exr"), image(dir / "oracle.png") {
    const CommandResult made = RunCli("render " + DefaultSceneArg() + " --size 48x32 --shadow-map-size 256 -o " +
                                      Quote(image) + " --dump " + Quote(oracle));
    REQUIRE(made.exitCode == 0);
  }
  fs::path oracle, image;
};

// Every case fails with one "ssgi: error:" line and its exit code, and leaves `dir` holding only `keep`.
void CheckRefusals(const ScratchDir& dir, std::initializer_list<std::string> keep,
                   const std::vector<CliErrorCase>& cases) {
  CheckCliErrors(cases);
  RequireOnlyFiles(dir, keep);
}

TEST_CASE("commands: each refuses, before allocating, work over --max-memory, and leaves nothing", "[cli][memory]") {
  ScratchDir dir("cli-commands-memory");
  const Dumps d(dir);
  const std::string out = Quote(dir / "out.exr");
  CheckRefusals(dir, {"oracle.exr", "oracle.png"},
                {{"figures " + Quote(dir / "figs") + " --size 2048x2048 --max-memory 100M",
                  "figures of 2048x2048 needs about", 1},
                 {"reference --size 4096x4096 --max-memory 256M -o " + out, "a 4096x4096 reference needs about", 1},
                 {"passes " + Quote(d.oracle) + " --max-memory 1M -o " + out, "more than --max-memory", 1},
                 {"diff " + Quote(d.oracle) + " " + Quote(d.oracle) + " --max-memory 1M", "more than --max-memory", 2},
                 {"render " + DefaultSceneArg() + " --size 16384x16384 --max-memory 4G -o " + Quote(dir / "big.png"),
                  "a 16384x16384 frame needs about", 1}});
  RequireOnlyFiles(dir, {"oracle.exr", "oracle.png"});
}

TEST_CASE("commands: a failed command leaves none of its outputs", "[cli]") {
  ScratchDir dir("cli-commands-all-or-nothing");
  const Dumps d(dir);
  fs::create_directory(dir / "folder.png");
  const std::string ok = Quote(dir / "ok.png");
  CheckRefusals(dir, {"oracle.exr", "oracle.png", "folder.png"},
                {// The dump cannot be written: the image is not written either, and nothing is rendered.
                 {"render " + DefaultSceneArg() + " --size 32x32 --dump /proc/d.exr -o " + ok, "/proc/d.exr", 1},
                 {"render " + DefaultSceneArg() + " --size 32x32 -o /proc/x.png", "/proc/x.png: cannot write here", 1},
                 {"render " + DefaultSceneArg() + " --size 32x32 -o " + Quote(dir / "folder.png"), "is a directory", 1},
                 {"render " + Quote(dir.path()) + " -o " + ok, "is a directory, not a scene file", 1},
                 {"render " + DefaultSceneArg() + " -o ''", "the output file name is empty", 1},
                 {"compare " + Quote(dir.path()) + " " + Quote(d.oracle), "is a directory", 1},
                 {"compare " + Quote(d.oracle) + " " + Quote(d.oracle) + " --layer result --heatmap /proc/h.png",
                  "/proc/h.png", 1},
                 {"passes " + Quote(d.oracle) + " -o /proc/o.exr", "/proc/o.exr", 1},
                 {"reference --size 16x16 --spp 1 -o " + Quote(dir / "folder.png"), "is a directory", 1},
                 {"diff " + Quote(d.oracle) + " " + Quote(dir.path()), "is a directory", 2},
                 {"diff " + Quote(d.oracle) + " " + Quote(d.oracle) + " --json /proc/r.json", "/proc/r.json", 2}});
  // figures writes into a temporary name per file and moves them in together: one output it cannot
  // write (a folder in the way) leaves the folder as it was, and a folder it created is removed.
  fs::create_directories(dir / "figs" / "table1.md");
  const CommandResult figures = RunCli("figures " + Quote(dir / "figs") + " --size 32x32");
  CHECK(figures.exitCode == 1);
  CHECK(figures.output.find("table1.md: is a directory") != std::string::npos);
  CHECK(std::distance(fs::directory_iterator(dir / "figs"), fs::directory_iterator()) == 1);
  fs::remove_all(dir / "figs");
  const CommandResult nested = RunCli("figures " + Quote(dir / "new" / "figs") + " --size 2048x2048 --max-memory 1M");
  CHECK(nested.exitCode == 1);
  CHECK_FALSE(fs::exists(dir / "new"));
  RequireOnlyFiles(dir, {"oracle.exr", "oracle.png", "folder.png"});
}

TEST_CASE("commands: SIGTERM and SIGINT remove the temporaries and leave no output", "[cli][signals]") {
  for (int signal : {SIGTERM, SIGINT}) {
    CAPTURE(signal);
    ScratchDir dir("cli-commands-signal");
    const std::string command = "exec '" + CliPath().string() + "' render " + DefaultSceneArg() +
                                " --size 2048x2048 --threads 1 -o " + Quote(dir / "out.png") + " --dump " +
                                Quote(dir / "d.exr") + " >/dev/null 2>&1";
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // The temporaries are made before the render starts: wait for them, then interrupt the render.
    bool started = false;
    for (int i = 0; i < 400 && !started; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
      started = std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) >= 2;
    }
    REQUIRE(started);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(child, signal);
    int status = 0;
    ::waitpid(child, &status, 0);
    CHECK(WIFSIGNALED(status));
    RequireOnlyFiles(dir, {});
  }
}

TEST_CASE("commands: a full disk fails with one line and leaves no half-written output", "[cli]") {
  ScratchDir dir("cli-commands-enospc");
  const fs::path disk = dir / "disk";
  fs::create_directory(disk);
  // A 256 KiB file system: room for the small image, not for the dump.
  if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=256k") != 0) {
    WARN("skipped: cannot mount a small tmpfs here (needs root and mount rights)");
    return;
  }
  const CommandResult full = RunCli("render " + DefaultSceneArg() + " --size 256x256 -o " + Quote(disk / "out.png") +
                                    " --dump " + Quote(disk / "d.exr"));
  const bool empty = fs::is_empty(disk);
  ::umount(disk.c_str());
  CAPTURE(full.output);
  CHECK(full.exitCode == 1);
  CHECK(full.output.find("ssgi: error: ") == 0);
  CHECK(full.output.find("d.exr") != std::string::npos);
  CHECK(std::count(full.output.begin(), full.output.end(), '\n') == 1);
  CHECK(empty);
}

TEST_CASE("commands: bad EXRs, wrong layers and unreadable inputs are one line with nothing written", "[cli]") {
  ScratchDir dir("cli-commands-corpus");
  const Dumps d(dir);
  WriteText(dir / "text.exr", "not an image\n");
  {
    // A real EXR cut short inside its pixels.
    std::ifstream in(d.oracle, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "cut.exr", std::ios::binary) << bytes.substr(0, 16000);
  }
  const std::string out = Quote(dir / "out.exr");
  const std::string oracle = Quote(d.oracle);
  CheckRefusals(dir, {"oracle.exr", "oracle.png", "text.exr", "cut.exr"},
                {{"compare " + Quote(dir / "text.exr") + " " + oracle, "text.exr", 1},
                 {"compare " + Quote(dir / "cut.exr") + " " + oracle, "cut.exr", 1},
                 {"compare " + oracle + " " + oracle + " --layer nothing", "nothing", 1},
                 {"compare " + oracle + " " + Quote(d.image) + " --layer shadow.visibility", "oracle.png", 1},
                 {"passes " + Quote(dir / "text.exr") + " -o " + out, "text.exr", 1},
                 {"passes " + Quote(dir / "cut.exr") + " --from hiz -o " + out, "cut.exr", 1},
                 {"passes " + Quote(d.image) + " -o " + out, "not an EXR", 1},
                 {"passes " + Quote(dir / "missing.exr") + " -o " + out, "missing.exr: no such file", 1},
                 {"diff " + oracle + " " + Quote(dir / "text.exr"), "text.exr", 2},
                 {"diff " + Quote(dir / "cut.exr") + " " + oracle, "cut.exr", 2},
                 {"diff " + oracle + " " + oracle + " --thresholds " + Quote(dir / "text.exr"), "text.exr", 2},
                 {"figures " + Quote(dir / "figs") + " --scene " + Quote(dir / "text.exr"), "text.exr", 1},
                 {"reference " + Quote(dir / "missing.json") + " -o " + out, "missing.json: no such file", 1},
                 {"reference --size 16x16 -o " + Quote(dir / "ref.png"), "use a .exr name", 1},
                 {"reference --size 16x16 -o " + out + " --png " + Quote(dir / "ref.jpg"), "ref.jpg", 1}});
}

TEST_CASE("reference: --png is the EXR's image under the frame's exposure and display curve", "[cli][reference]") {
  ScratchDir dir("cli-reference-png");
  const fs::path exr = dir / "ref.exr", png = dir / "ref.png";
  REQUIRE(RunCli("reference " + DefaultSceneArg() + " --size 24x16 --spp 2 --exposure 1.5 -o " + Quote(exr) +
                 " --png " + Quote(png))
              .exitCode == 0);
  const FloatImage linear = SelectLayer(ReadFloatImage(exr), "", exr);
  const FloatImage codes = ReadFloatImage(png);
  REQUIRE(codes.integerCodes);
  REQUIRE((codes.width == 24 && codes.height == 16 && codes.Channels() == 3));
  Plane3<float> radiance = MakePlane3<float>(24, 16, 0.0f);
  for (size_t y = 0; y < 16; ++y)
    for (size_t x = 0; x < 24; ++x)
      for (int c = 0; c < 3; ++c) radiance.c[c].MutableRow(y)[x] = linear.pixels[(y * 24 + x) * 3 + size_t(c)];
  TonemapOutputs display;
  RunTonemap(radiance, TonemapParams{1.5f, Tonemap::kAces}, display);
  size_t differing = 0;
  for (size_t i = 0; i < display.rgb.size(); ++i)
    differing += display.rgb[i] != uint8_t(std::lround(codes.pixels[i] * 255.0f)) ? 1 : 0;
  CHECK(differing == 0);
}

TEST_CASE("commands: the small things", "[cli]") {
  ScratchDir dir("cli-commands-small");
  const CommandResult version = RunCli("--version");
  CHECK(version.exitCode == 0);
  CHECK(version.output.rfind("ssgi 0.", 0) == 0);
  CHECK(version.output.find("(commit ") != std::string::npos);
  CheckCliErrors({
      {"render --background -1,0,0", "--background: components must be >= 0, got '-1,0,0'", 2},
      {"render --threads two", "--threads: must be a whole number of threads", 2},
      {"render --max-memory 12X", "--max-memory: must be a size like", 2},
  });
  // A negative number is still a value where an option takes one.
  CHECK(RunCli("render " + DefaultSceneArg() + " --size 16x16 --exposure -1.5 -o " + Quote(dir / "e.png")).exitCode ==
        0);
  // Counts agree with their numbers.
  WriteText(dir / "one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const CommandResult one =
      RunCli("render " + Quote(dir / "one.obj") + " --size 16x16 --stats -o " + Quote(dir / "o.png"));
  CHECK(one.output.find("1 triangle, 1 material, 0 textures") != std::string::npos);
  // A model whose every triangle has zero area renders, with a warning that nothing is visible.
  WriteText(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  const CommandResult flat = RunCli("render " + Quote(dir / "flat.obj") + " --size 16x16 -o " + Quote(dir / "f.png"));
  CHECK(flat.exitCode == 0);
  CHECK(flat.output.find("ssgi: warning: ") != std::string::npos);
  CHECK(flat.output.find("no triangle covers a pixel") != std::string::npos);
  // Rendering onto the default output name again says it replaced the file.
  const std::string inDir =
      "cd " + Quote(dir.path()) + " && '" + CliPath().string() + "' render " + DefaultSceneArg() + " --size 16x16 2>&1";
  CHECK(std::system(inDir.c_str()) == 0);
  FILE* again = ::popen(inDir.c_str(), "r");
  REQUIRE(again != nullptr);
  char line[512] = {};
  std::string text;
  while (std::fgets(line, sizeof(line), again)) text += line;
  ::pclose(again);
  CHECK(text.find("wrote default.png, over the file of that name that was there") != std::string::npos);
  // --stats lists only the stages that ran: passes from the Hi-Z on have no G-buffer rows.
  const CommandResult dumped = RunCli("render " + DefaultSceneArg() + " --size 32x32 --dump " + Quote(dir / "d.exr") +
                                      " -o " + Quote(dir / "d.png"));
  REQUIRE(dumped.exitCode == 0);
  const CommandResult passes =
      RunCli("passes " + Quote(dir / "d.exr") + " --from hiz --stats -o " + Quote(dir / "p.exr"));
  CAPTURE(passes.output);
  CHECK(passes.exitCode == 0);
  CHECK(passes.output.find("g-buffer raster") == std::string::npos);
  CHECK(passes.output.find("direct light") == std::string::npos);
  CHECK(passes.output.find("ssr trace") != std::string::npos);
}

}  // namespace
}  // namespace ssgi::test
