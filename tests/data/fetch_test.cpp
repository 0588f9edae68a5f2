// data/scenes/fetch.sh, which gets the third-party models the scene files render: from a local mirror
// (as the tests here get them), checked file by file, installed whole or not at all; the armadillo's
// PLY-to-OBJ conversion; the download path with a file:// archive in place of GitHub's.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::Quote;
using test::ScratchDir;

const char* const kTeapotFiles[] = {"default.mtl", "default.png", "teapot.obj"};

fs::path FetchScript() { return test::SourceDir() / "data" / "scenes" / "fetch.sh"; }

CommandResult Fetch(const std::string& arguments) { return test::RunProgram(FetchScript(), arguments); }

bool HavePython() { return test::RunProgram("/bin/sh", "-c 'command -v python3' >/dev/null").exitCode == 0; }

void FlipLastByte(const fs::path& file) {
  std::string bytes = test::ReadFileBytes(file);
  bytes.back() = char(bytes.back() ^ 1);
  test::WriteText(file, bytes);
}

std::vector<std::string> Entries(const fs::path& folder) {
  std::vector<std::string> names;
  if (!fs::exists(folder)) return names;
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

size_t Lines(const std::string& text) { return size_t(std::count(text.begin(), text.end(), '\n')); }

// The fetched teapot (the smallest scene, 0.9 MB), or "" after a skip message where it or Python is
// absent.
fs::path FetchedTeapot() {
  if (!HavePython()) {
    WARN("skipped: no python3 to run data/scenes/fetch.sh");
    return {};
  }
  const fs::path teapot = test::ThirdPartyScenesDir() / "utah-teapot";
  if (!fs::exists(teapot / "teapot.obj")) {
    WARN(test::MissingScenesMessage(teapot));
    return {};
  }
  return teapot;
}

// A mirror laid out as `fetch.sh --from` reads it: <mirror>/utah-teapot/<files>.
fs::path MirrorOf(const fs::path& teapot, const ScratchDir& dir) {
  const fs::path folder = dir / "mirror" / "utah-teapot";
  fs::create_directories(folder);
  for (const char* name : kTeapotFiles) fs::copy_file(teapot / name, folder / name);
  return dir / "mirror";
}

TEST_CASE("fetch.sh: a mirror's scene is copied, verified and its licence shown, and a second run keeps it",
          "[data][fetch]") {
  const fs::path teapot = FetchedTeapot();
  if (teapot.empty()) return;
  ScratchDir dir("fetch-mirror");
  const fs::path mirror = MirrorOf(teapot, dir), dest = dir / "models";
  const CommandResult first = Fetch("--from " + Quote(mirror) + " --dest " + Quote(dest) + " teapot");
  CAPTURE(first.output);
  REQUIRE(first.exitCode == 0);
  CHECK(first.output.find("teapot: " + (dest / "utah-teapot").string() + " (3 files, fetched and verified)") !=
        std::string::npos);
  CHECK(first.output.find("licence: CC0") != std::string::npos);
  CHECK(Entries(dest) == std::vector<std::string>{"utah-teapot"});
  CHECK(Entries(dest / "utah-teapot") == std::vector<std::string>(std::begin(kTeapotFiles), std::end(kTeapotFiles)));
  for (const char* name : kTeapotFiles)
    CHECK(test::ReadFileBytes(dest / "utah-teapot" / name) == test::ReadFileBytes(teapot / name));

  const CommandResult again = Fetch("--from " + Quote(mirror) + " --dest " + Quote(dest) + " teapot --quiet");
  CAPTURE(again.output);
  CHECK(again.exitCode == 0);
  CHECK(Lines(again.output) == 1);
  CHECK(again.output.find("0 fetched, 1 already present") != std::string::npos);
  CHECK(again.output.find("teapot: CC0") != std::string::npos);
}

TEST_CASE("fetch.sh: a changed or missing file is an error naming it, and nothing half-written is left",
          "[data][fetch]") {
  const fs::path teapot = FetchedTeapot();
  if (teapot.empty()) return;
  ScratchDir dir("fetch-bad-mirror");
  const fs::path mirror = MirrorOf(teapot, dir), dest = dir / "models";
  FlipLastByte(mirror / "utah-teapot" / "default.mtl");

  auto checkError = [&](const std::string& file) {
    const CommandResult r = Fetch("--from " + Quote(mirror) + " --dest " + Quote(dest) + " teapot");
    CAPTURE(r.output);
    CHECK(r.exitCode == 1);
    CHECK(Lines(r.output) == 1);
    CHECK(r.output.rfind("fetch.sh: error: ", 0) == 0);
    CHECK(r.output.find((mirror / "utah-teapot" / file).string()) != std::string::npos);
  };
  // Into an empty destination: no scene folder, no temporary one.
  checkError("default.mtl");
  CHECK(Entries(dest).empty());

  // Over an earlier copy that no longer verifies: that copy stays as it was until a good one replaces it.
  fs::create_directories(dest / "utah-teapot");
  for (const char* name : kTeapotFiles) fs::copy_file(teapot / name, dest / "utah-teapot" / name);
  FlipLastByte(dest / "utah-teapot" / "teapot.obj");
  const std::string earlier = test::ReadFileBytes(dest / "utah-teapot" / "teapot.obj");
  checkError("default.mtl");
  CHECK(Entries(dest) == std::vector<std::string>{"utah-teapot"});
  CHECK(test::ReadFileBytes(dest / "utah-teapot" / "teapot.obj") == earlier);

  fs::remove(mirror / "utah-teapot" / "default.mtl");
  checkError("default.mtl");
  fs::copy_file(teapot / "default.mtl", mirror / "utah-teapot" / "default.mtl");
  const CommandResult good = Fetch("--from " + Quote(mirror) + " --dest " + Quote(dest) + " teapot");
  CAPTURE(good.output);
  CHECK(good.exitCode == 0);
  CHECK(Entries(dest) == std::vector<std::string>{"utah-teapot"});
  for (const char* name : kTeapotFiles)
    CHECK(test::ReadFileBytes(dest / "utah-teapot" / name) == test::ReadFileBytes(teapot / name));
}

TEST_CASE("fetch.sh: command lines it refuses, and its help", "[data][fetch]") {
  if (!HavePython()) {
    WARN("skipped: no python3 to run data/scenes/fetch.sh");
    return;
  }
  const CommandResult unknown = Fetch("teapot kettle");
  CHECK(unknown.exitCode == 2);
  CHECK(unknown.output.find("unknown scene kettle") != std::string::npos);
  const CommandResult noFolder = Fetch("--from /nonexistent/ssgi-mirror");
  CHECK(noFolder.exitCode == 2);
  CHECK(noFolder.output.find("/nonexistent/ssgi-mirror: not a folder") != std::string::npos);
  const CommandResult help = Fetch("--help");
  CAPTURE(help.output);
  CHECK(help.exitCode == 0);
  for (const char* text : {"--from DIR", "sponza", "CC BY-NC", "Stanford 3D Scanning Repository terms", "CC0"})
    CHECK(help.output.find(text) != std::string::npos);
}

TEST_CASE("fetch.sh: the download path checks the zip, then every file, with a file:// archive",
          "[data][fetch]") {
  const fs::path teapot = FetchedTeapot();
  if (teapot.empty()) return;
  ScratchDir dir("fetch-download");
  const CommandResult r = test::RunProgram(
      "python3", Quote(test::SourceDir() / "tests" / "data" / "fetch_download_check.py") + " " +
                     Quote(test::SourceDir() / "data" / "scenes" / "fetch.py") + " " + Quote(teapot) + " " +
                     Quote(dir.path()));
  INFO(r.output);
  CHECK(r.exitCode == 0);
  CHECK(r.output.find("FAILED") == std::string::npos);
}

TEST_CASE("fetch.sh: the armadillo's upstream PLY converts to the listed OBJ byte for byte", "[data][fetch]") {
  if (!HavePython()) {
    WARN("skipped: no python3 to run data/scenes/fetch.sh");
    return;
  }
  const fs::path armadillo = test::ThirdPartyScenesDir() / "stanford-armadillo" / "armadillo.obj";
  if (!fs::exists(armadillo)) {
    WARN(test::MissingScenesMessage(armadillo));
    return;
  }
  // The upstream zip holds only Armadillo.ply; obj_to_ply.py writes it back from the OBJ (fetch.sh
  // checks that it has the upstream file's SHA-256 before converting), then fetch.sh converts it.
  ScratchDir dir("fetch-armadillo");
  const fs::path mirror = dir / "mirror", dest = dir / "models";
  fs::create_directories(mirror / "stanford-armadillo");
  const CommandResult ply = test::RunProgram(
      "python3", Quote(test::SourceDir() / "tests" / "data" / "obj_to_ply.py") + " " + Quote(armadillo) + " " +
                     Quote(mirror / "stanford-armadillo" / "Armadillo.ply"));
  INFO(ply.output);
  REQUIRE(ply.exitCode == 0);
  const CommandResult r = Fetch("--from " + Quote(mirror) + " --dest " + Quote(dest) + " armadillo");
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  CHECK(Entries(dest / "stanford-armadillo") == std::vector<std::string>{"armadillo.obj"});
  CHECK(test::ReadFileBytes(dest / "stanford-armadillo" / "armadillo.obj") == test::ReadFileBytes(armadillo));
}

}  // namespace
}  // namespace ssgi
