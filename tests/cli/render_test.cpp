// End-to-end tests of `ssgi render`: exit codes and messages for bad input, no output left behind
// on failure, byte-identical output at any thread count, and the golden image of the default scene.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <utility>

#include "core/image_compare.h"
#include "core/image_io.h"
#include "tests/test_support.h"

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;

TEST_CASE("render: bad command-line values fail with one clear line", "[cli]") {
  ScratchDir dir("cli-bad-args");
  const std::string out = Quote(dir / "out.png");
  CheckCliErrors({
      {"render " + DefaultSceneArg() + " --size 0x10 -o " + out, "--size", 2},
      {"render " + DefaultSceneArg() + " --size 20000x100 -o " + out, "[1, 16384]", 2},
      {"render " + DefaultSceneArg() + " --size banana -o " + out, "WIDTHxHEIGHT", 2},
      {"render " + DefaultSceneArg() + " --background 1,2 -o " + out, "R,G,B", 2},
      {"render " + DefaultSceneArg() + " -o " + Quote(dir / "out.jpg"), "unsupported output format", 1},
      {"render " + DefaultSceneArg() + " -o " + Quote(dir / "missing" / "out.png"), "does not exist", 1},
      {"render " + DefaultSceneArg() + " -o " + out + " --dump-gbuffer " + Quote(dir / "g.png"), "EXR", 1},
      {"render " + Quote(dir / "nowhere.json") + " -o " + out, "nowhere.json", 1},
  });
  RequireOnlyFiles(dir, {});
  // Quality knobs out of range are command-line errors (exit 2), caught before any work.
  const CommandResult knob = RunCli("render " + DefaultSceneArg() + " --ssr-iterations 0 -o " + out);
  CHECK(knob.exitCode == 2);
  CHECK(knob.output.find("--ssr-iterations") != std::string::npos);
  CHECK(RunCli("render " + DefaultSceneArg() + " --quality extreme -o " + out).exitCode == 2);
  for (const char* bad :
       {"--bounce maybe", "--bounce-slices 0", "--bounce-steps 40", "--bounce-radius -1", "--bounce-thickness nan"}) {
    const CommandResult bounce = RunCli("render " + DefaultSceneArg() + " " + bad + " -o " + out);
    CAPTURE(bad, bounce.output);
    CHECK(bounce.exitCode == 2);
    CHECK(bounce.output.find(std::string(bad).substr(0, std::string(bad).find(' '))) != std::string::npos);
    CHECK(std::count(bounce.output.begin(), bounce.output.end(), '\n') == 1);
  }
  RequireOnlyFiles(dir, {});
}

TEST_CASE("render: a malformed scene names the file and line and writes nothing", "[cli]") {
  ScratchDir dir("cli-bad-scene");
  WriteText(dir / "broken.json", "{\n  \"camera\": {\n    \"position\": [0, 1, 2,\n  }\n}\n");
  const CommandResult result = RunCli("render " + Quote(dir / "broken.json") + " -o " + Quote(dir / "out.png"));
  CAPTURE(result.output);
  CHECK(result.exitCode == 1);
  CHECK(result.output.find("broken.json:4") != std::string::npos);
  RequireOnlyFiles(dir, {"broken.json"});
}

TEST_CASE("render: an unwritable output path fails before rendering", "[cli]") {
  ScratchDir dir("cli-unwritable");
  WriteText(dir / "file", "not a folder");
  const CommandResult result = RunCli("render " + DefaultSceneArg() + " -o " + Quote(dir / "file" / "out.png"));
  CAPTURE(result.output);
  CHECK(result.exitCode == 1);
  CHECK(result.output.find("out.png") != std::string::npos);
  RequireOnlyFiles(dir, {"file"});
}

TEST_CASE("render: output and every buffer are byte-identical at 1, 2 and 3 threads", "[cli][determinism]") {
  ScratchDir dir("cli-threads");
  std::vector<StoredImage> images;
  std::vector<ExrFile> buffers;
  for (int threads : {1, 2, 3}) {
    const std::string tag = std::to_string(threads);
    const CommandResult result =
        RunCli("render " + DefaultSceneArg() + " --size 150x101 --bounce on --threads " + tag + " -o " +
               Quote(dir / (tag + ".png")) + " --dump " + Quote(dir / (tag + ".exr")));
    CAPTURE(result.output);
    REQUIRE(result.exitCode == 0);
    images.push_back(ReadStoredImage(dir / (tag + ".png")));
    buffers.push_back(ReadExrFile(dir / (tag + ".exr")));
  }
  REQUIRE(images[0].width == 150);
  REQUIRE(buffers[0].layers.size() > 60);  // every part: the image's layers, the shadow map, the pyramids
  // The bounce ran: its full-resolution layers and its half-resolution part.
  REQUIRE(buffers[0].Find("frame", "bounce.visibility") != nullptr);
  REQUIRE(buffers[0].Find("bounce.half", "march.R") != nullptr);
  for (int i = 1; i < 3; ++i) {
    CHECK(images[i].bytes == images[0].bytes);
    REQUIRE(buffers[i].layers.size() == buffers[0].layers.size());
    for (size_t k = 0; k < buffers[0].layers.size(); ++k) {
      CAPTURE(buffers[0].layers[k].part, buffers[0].layers[k].name);
      CHECK(buffers[i].layers[k].name == buffers[0].layers[k].name);
      CHECK(buffers[i].layers[k].samples == buffers[0].layers[k].samples);
    }
  }
}

TEST_CASE("render: --explain says whether the anti-aliasing runs and on how many edge pixels", "[cli]") {
  ScratchDir dir("cli-explain-aa");
  const CommandResult edge =
      RunCli("render " + DefaultSceneArg() + " --size 96x64 --explain -o " + Quote(dir / "edge.png"));
  REQUIRE(edge.exitCode == 0);
  CAPTURE(edge.output);
  CHECK(edge.output.find("antialias: run, pixels lie on geometric edges; needed in") != std::string::npos);
  const CommandResult off =
      RunCli("render " + DefaultSceneArg() + " --size 96x64 --aa off --explain -o " + Quote(dir / "off.png"));
  REQUIRE(off.exitCode == 0);
  CAPTURE(off.output);
  CHECK(off.output.find("antialias: skipped, switched off\n    antialias does not run\n") != std::string::npos);
}

// The default frame; the same without anti-aliasing, the image the frame gave before the
// anti-aliasing was part of it; and with the screen-space bounce on too, which the default frame leaves
// to the interreflection volume: with either changed every other pass keeps its bytes.
TEST_CASE("render: the default scene matches its golden images byte for byte", "[cli][golden]") {
  ScratchDir dir("cli-golden");
  for (const auto& [name, options] : {std::pair<std::string, std::string>{"default_160x120.png", ""},
                                      {"default_160x120_aa_off.png", " --aa off"},
                                      {"default_160x120_bounce_on.png", " --bounce on --aa off"}}) {
    CAPTURE(name);
    const fs::path golden = SourceDir() / "tests" / "golden" / name;
    const fs::path rendered = dir / name;
    const CommandResult result =
        RunCli("render " + DefaultSceneArg() + " --size 160x120" + options + " -o " + Quote(rendered));
    CAPTURE(result.output);
    REQUIRE(result.exitCode == 0);
    if (std::getenv("SSGI_UPDATE_GOLDEN")) fs::copy_file(rendered, golden, fs::copy_options::overwrite_existing);
    const StoredImage expected = ReadStoredImage(golden);
    const StoredImage actual = ReadStoredImage(rendered);
    REQUIRE(actual.width == expected.width);
    REQUIRE(actual.height == expected.height);
    size_t differing = 0;
    for (size_t i = 0; i < actual.bytes.size(); ++i) differing += actual.bytes[i] != expected.bytes[i];
    INFO("bytes differing from the golden image: " << differing
                                                   << " (SSGI_UPDATE_GOLDEN=1 rewrites it after an intended change)");
    CHECK(differing == 0);
  }
}

TEST_CASE("figures: one command writes the paper's image sequence", "[cli]") {
  ScratchDir dir("cli-figures");
  const CommandResult result = RunCli("figures " + Quote(dir / "out") + " --size 96x72");
  CAPTURE(result.output);
  REQUIRE(result.exitCode == 0);
  for (const char* name : {"albedo.png", "direct.png", "direct_shadows.png", "shadow_filters.png"}) {
    CAPTURE(name);
    CHECK(ReadStoredImage(dir / "out" / name).width > 0);
  }
  // The shadows darken the image: the shadowed render differs from the unshadowed one.
  CHECK(ReadStoredImage(dir / "out" / "direct.png").bytes != ReadStoredImage(dir / "out" / "direct_shadows.png").bytes);
}

TEST_CASE("render: shadow passes run only when the scene calls for them", "[cli]") {
  ScratchDir dir("cli-effects");
  const std::string out = " -o " + Quote(dir / "out.png") + " --size 64x48 --stats";
  const CommandResult withShadows = RunCli("render " + DefaultSceneArg() + out);
  REQUIRE(withShadows.exitCode == 0);
  CHECK(withShadows.output.find("shadow map") != std::string::npos);
  CHECK(withShadows.output.find("shadow filter") != std::string::npos);
  const CommandResult switchedOff = RunCli("render " + DefaultSceneArg() + out + " --shadows off");
  REQUIRE(switchedOff.exitCode == 0);
  CHECK(switchedOff.output.find("shadow") == std::string::npos);
  // A light that casts no shadows needs no shadow map, whatever --shadows says.
  const std::string sphere = (SourceDir() / "data" / "sphere.obj").string();
  WriteText(dir / "no_caster.json", "{\"objects\": [{\"obj\": \"" + sphere + "\"}], \"lights\": [{\"type\": "
                                     "\"directional\", \"direction\": [0, -1, 0], \"cast_shadows\": false}]}");
  const CommandResult noCaster = RunCli("render " + Quote(dir / "no_caster.json") + out + " --shadows on");
  CAPTURE(noCaster.output);
  REQUIRE(noCaster.exitCode == 0);
  CHECK(noCaster.output.find("shadow") == std::string::npos);
}

TEST_CASE("render --stats: every stage row says what it processed, a stage that processed nothing says none",
          "[cli]") {
  ScratchDir dir("cli-stats-rows");
  // The bare board: smooth enough to be traced, but no ray finds anything, so no cone runs.
  const CommandResult r = RunCli("render " + Quote(SourceDir() / "data" / "board.obj") + " --size 64x48 --stats -o " +
                                 Quote(dir / "board.png"));
  CAPTURE(r.output);
  REQUIRE(r.exitCode == 0);
  std::istringstream lines(r.output);
  int stageRows = 0;
  for (std::string line; std::getline(lines, line);) {
    for (const char* stage : {"g-buffer raster ", "g-buffer resolve ", "shadow map ", "blocker search ", "shadow filter ",
                              "direct light ", "hi-z ", "colour pyramid ", "ssr trace ", "cone trace ", "composite ",
                              "tonemap ", "frame total "}) {
      if (line.rfind(std::string("  ") + stage, 0) != 0) continue;
      CAPTURE(line);
      ++stageRows;
      CHECK((line.find("/s (") != std::string::npos || line.find("none (0 ") != std::string::npos));
    }
  }
  CHECK(stageRows == 13);
  CHECK_THAT(r.output, Catch::Contains("cone trace") && Catch::Contains("none (0 pixels)"));
}

TEST_CASE("compare: metrics of two renders, per layer, and a heat map", "[cli][compare]") {
  ScratchDir dir("cli-compare");
  for (const char* filter : {"hard", "ssabss"}) {
    const CommandResult r = RunCli("render " + DefaultSceneArg() + " --size 64x48 --shadow-filter " + filter + " -o " +
                                   Quote(dir / (std::string(filter) + ".exr")) + " --dump-gbuffer " +
                                   Quote(dir / (std::string(filter) + "_dump.exr")));
    REQUIRE(r.exitCode == 0);
  }
  const CommandResult same = RunCli("compare " + Quote(dir / "hard.exr") + " " + Quote(dir / "hard.exr"));
  CAPTURE(same.output);
  CHECK(same.exitCode == 0);
  CHECK(same.output.find("RMSE       0 (linear), 0 (of x/(1+x))\n") != std::string::npos);
  const CommandResult visibility = RunCli("compare " + Quote(dir / "hard_dump.exr") + " " +
                                          Quote(dir / "ssabss_dump.exr") + " --layer shadow.visibility --heatmap " +
                                          Quote(dir / "heat.png"));
  CAPTURE(visibility.output);
  CHECK(visibility.exitCode == 0);
  CHECK(visibility.output.find("1 channel)") != std::string::npos);
  // A dump against another: the error by region too.
  CHECK(visibility.output.find("by region (shadow.visibility, roughness, depth)") != std::string::npos);
  CHECK(visibility.output.find("in shadow") != std::string::npos);
  CHECK(ReadStoredImage(dir / "heat.png").width == 64);
  CHECK(ReadStoredImage(dir / "heat.png").height == 48 + kHeatmapLegendRows);
  const CommandResult missing = RunCli("compare " + Quote(dir / "hard.exr") + " " + Quote(dir / "nowhere.exr"));
  CHECK(missing.exitCode == 1);
  CHECK(missing.output.find("nowhere.exr") != std::string::npos);
}

TEST_CASE("render: the real-scene files render where their models are present", "[cli][real_scenes]") {
  ScratchDir dir("cli-real-scenes");
  const std::pair<const char*, const char*> scenes[] = {{"sponza", "dabrovic-sponza/sponza.obj"},
                                                        {"sibenik", "sibenik-cathedral/sibenik.obj"},
                                                        {"bunny", "stanford-bunny/bunny.obj"},
                                                        {"armadillo", "stanford-armadillo/armadillo.obj"},
                                                        {"teapot", "utah-teapot/teapot.obj"}};
  for (const auto& [name, model] : scenes) {
    if (!fs::exists(ThirdPartyScenesDir() / model)) {
      WARN(MissingScenesMessage(ThirdPartyScenesDir() / model));
      continue;
    }
    const fs::path png = dir / (std::string(name) + ".png");
    const CommandResult r = RunCli("render " + Quote(SourceDir() / "data" / "scenes" / (std::string(name) + ".json")) +
                                   " --size 64x48 -o " + Quote(png));
    CAPTURE(name, r.output);
    REQUIRE(r.exitCode == 0);
    // Lit, not black (a light that cannot reach the view) and not blown out (a wrong scale).
    const StoredImage image = ReadStoredImage(png);
    double sum = 0.0;
    for (uint8_t v : image.bytes) sum += v;
    const double mean = sum / double(image.bytes.size());
    CAPTURE(mean);
    CHECK(mean > 15.0);
    CHECK(mean < 220.0);
  }
}

TEST_CASE("reference: writes the final image and the matching buffers, comparable layer by layer", "[cli][reference]") {
  ScratchDir dir("cli-reference");
  const CommandResult ref =
      RunCli("reference " + DefaultSceneArg() + " --size 48x32 --spp 2 -o " + Quote(dir / "ref.exr"));
  CAPTURE(ref.output);
  REQUIRE(ref.exitCode == 0);
  const StoredImage image = ReadStoredImage(dir / "ref.exr");
  for (const char* name : {"R", "G", "B", "result.R", "direct.G", "indirect.B", "shadow.visibility", "depth"}) {
    CAPTURE(name);
    CHECK(std::find(image.channelNames.begin(), image.channelNames.end(), name) != image.channelNames.end());
  }
  REQUIRE(RunCli("render " + DefaultSceneArg() + " --size 48x32 -o " + Quote(dir / "ours.png") + " --dump-gbuffer " +
                 Quote(dir / "ours.exr"))
              .exitCode == 0);
  const CommandResult visibility = RunCli("compare " + Quote(dir / "ours.exr") + " " + Quote(dir / "ref.exr") +
                                          " --layer shadow.visibility");
  CAPTURE(visibility.output);
  CHECK(visibility.exitCode == 0);
  CHECK(RunCli("reference " + DefaultSceneArg() + " -o " + Quote(dir / "ref.png")).exitCode == 1);
}

TEST_CASE("render: with no scene renders the built-in default scene into the current folder", "[cli]") {
  ScratchDir dir("cli-default");
  const std::string command = "cd " + Quote(dir.path()) + " && '" + CliPath().string() + "' render --size 64x48 2>&1";
  CHECK(std::system(command.c_str()) == 0);
  CHECK(fs::exists(dir / "default.png"));
}

TEST_CASE("render: a frame larger than the memory allowed is refused before rendering", "[cli][memory]") {
  ScratchDir dir("cli-memory");
  const std::string out = Quote(dir / "out.png");
  const CommandResult refused = RunCli("render " + DefaultSceneArg() + " --size 2048x2048 --max-memory 200M -o " + out);
  CAPTURE(refused.output);
  CHECK(refused.exitCode == 1);
  CHECK(refused.output.find("ssgi: error: a 2048x2048 frame needs about ") == 0);
  // The frame's estimate and what the process holds already, each named, against the limit.
  CHECK(refused.output.find("(estimate: ") != std::string::npos);
  CHECK(refused.output.find(" the process holds already), more than --max-memory 200 MiB") != std::string::npos);
  CHECK(std::count(refused.output.begin(), refused.output.end(), '\n') == 1);
  const CommandResult badLimit = RunCli("render " + DefaultSceneArg() + " --max-memory lots -o " + out);
  CHECK(badLimit.exitCode == 2);  // a value that does not parse is a command-line error
  CHECK(badLimit.output.find("--max-memory: must be a size like 512M, 1.5G, 2GiB or 800MB, got 'lots'") !=
        std::string::npos);
  RequireOnlyFiles(dir, {});
  // The estimate against the measured peak resident set of the same render: a frame whose peak is
  // the SSR trace, and a small one whose peak is a large shadow map.
  for (const std::string options : {"--size 1536x1536", "--size 256x256 --shadow-map-size 4096"}) {
    const CommandResult rendered = RunCli("render " + DefaultSceneArg() + " " + options + " --stats -o " + out);
    CAPTURE(options, rendered.output);
    REQUIRE(rendered.exitCode == 0);
    const size_t line = rendered.output.find("memory: peak ");
    REQUIRE(line != std::string::npos);
    double peak = 0, frame = 0, estimate = 0, before = 0, buffers = 0;
    char peakUnit[8] = {}, frameUnit[8] = {}, estimateUnit[8] = {}, beforeUnit[8] = {}, buffersUnit[8] = {};
    REQUIRE(std::sscanf(rendered.output.c_str() + line,
                        "memory: peak %lf %3s resident (%*f bytes per pixel), the frame's %lf %3s (%*f bytes per "
                        "pixel); estimate %lf %3s (%lf %3s before the frame + %lf %3s of buffers)",
                        &peak, peakUnit, &frame, frameUnit, &estimate, estimateUnit, &before, beforeUnit, &buffers,
                        buffersUnit) == 10);
    const auto mib = [](double value, const std::string& unit) { return unit == "GiB" ? value * 1024.0 : value; };
    CHECK(std::abs(mib(estimate, estimateUnit) - mib(peak, peakUnit)) <= 0.1 * mib(peak, peakUnit));
    // The part that grows with the image on its own: the frame's buffers against their estimate.
    CHECK(std::abs(mib(buffers, buffersUnit) - mib(frame, frameUnit)) <= 0.1 * mib(frame, frameUnit));
    // The peak split into what the kernel cannot reclaim, which holds the frame's buffers, and
    // file-backed pages.
    double anonymous = 0, fileBacked = 0;
    char anonymousUnit[8] = {}, fileUnit[8] = {};
    const size_t split = rendered.output.find("  of the peak, ", line);
    REQUIRE(split != std::string::npos);
    REQUIRE(std::sscanf(rendered.output.c_str() + split, "  of the peak, %lf %3s anonymous (%*f bytes per pixel) and %lf %3s",
                        &anonymous, anonymousUnit, &fileBacked, fileUnit) == 4);
    CHECK(std::abs(mib(anonymous, anonymousUnit) + mib(fileBacked, fileUnit) - mib(peak, peakUnit)) <=
          0.05 * mib(peak, peakUnit));
    CHECK(mib(anonymous, anonymousUnit) >= 0.9 * mib(buffers, buffersUnit));
    CHECK(mib(fileBacked, fileUnit) > 0);
  }
}

}  // namespace
}  // namespace ssgi::test
