// The GLSL port (tests/port/, ssgi_gl_port) against the oracle, layer by layer: every layer bit for
// bit (tests/port/README.md). Skipped with a warning where the port is not built (no EGL/GL
// development files) or no EGL display with OpenGL 4.5 exists.
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/scene.h"
#include "passes/frame.h"
#include "passes/frame_config.h"
#include "tests/port/port_exr.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

using port::Layer;
using port::Part;

// The port's executable; "" where it is not built (no EGL/OpenGL development files).
#ifdef SSGI_GL_PORT_PATH
constexpr const char* kGlPortPath = SSGI_GL_PORT_PATH;
#else
constexpr const char* kGlPortPath = "";
#endif

// Units in the last place between two floats (same sign order as the integers); both NaN: 0.
int64_t UlpDistance(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b) ? 0 : INT64_MAX;
  const auto ordered = [](float v) {
    const int32_t bits = std::bit_cast<int32_t>(v);
    return bits < 0 ? int64_t(INT32_MIN) - int64_t(bits) : int64_t(bits);
  };
  return std::llabs(ordered(a) - ordered(b));
}

// How one layer of the port differs from the oracle's (float layers; the port writes no integer one).
struct LayerDiff {
  double maxAbs = 0.0;
  int64_t maxUlp = 0;
  size_t differing = 0;  // samples whose bits differ
  size_t worst = 0;      // index of the largest ULP distance
};

LayerDiff CompareLayer(const Layer& oracle, const Layer& port) {
  LayerDiff diff;
  for (size_t i = 0; i < oracle.samples.size(); ++i) {
    if (oracle.samples[i] == port.samples[i]) continue;
    ++diff.differing;
    const float a = std::bit_cast<float>(oracle.samples[i]), b = std::bit_cast<float>(port.samples[i]);
    const int64_t ulp = UlpDistance(a, b);
    if (ulp > diff.maxUlp) {
      diff.maxUlp = ulp;
      diff.worst = i;
    }
    diff.maxAbs = std::max(diff.maxAbs, std::fabs(double(a) - double(b)));
  }
  return diff;
}

const Part* FindPart(const std::vector<Part>& parts, const std::string& name) {
  for (const Part& part : parts)
    if (part.name == name) return &part;
  return nullptr;
}

const Layer* FindChannel(const Part& part, const std::string& name) {
  for (const auto& [channelName, layer] : part.channels)
    if (channelName == name) return &layer;
  return nullptr;
}

Layer FloatLayer(const Plane<float>& plane) {
  Layer layer;
  for (size_t y = 0; y < plane.ysize(); ++y)
    for (size_t x = 0; x < plane.xsize(); ++x) layer.samples.push_back(std::bit_cast<uint32_t>(plane.ConstRow(y)[x]));
  return layer;
}

// The oracle's layers: its dump, and the Hi-Z and colour-pyramid levels of the same frame as parts
// "hiz.L" (Y) and "pyramid.L" (R, G, B), the names the port writes them under.
std::vector<Part> OracleParts(const Frame& frame, const std::filesystem::path& dump) {
  std::vector<Part> parts = port::ReadExrParts(dump);
  parts[0].name = "frame";  // the image part's name in issue 13's multi-part dump, which the port writes
  for (size_t k = 0; k < frame.hiz.levels.size(); ++k) {
    const Plane<float>& level = frame.hiz.levels[k];
    parts.push_back({"hiz." + std::to_string(k), int(level.xsize()), int(level.ysize()), {{"Y", FloatLayer(level)}}});
  }
  for (size_t k = 0; k < frame.colorPyramid.levels.size(); ++k) {
    const Plane3<float>& level = frame.colorPyramid.levels[k];
    parts.push_back({"pyramid." + std::to_string(k), int(level.c[0].xsize()), int(level.c[0].ysize()),
                     {{"R", FloatLayer(level.c[0])}, {"G", FloatLayer(level.c[1])}, {"B", FloatLayer(level.c[2])}}});
  }
  return parts;
}

// Checks every layer of the port's output `ported` against the oracle's. Prints one line per layer.
void CompareWithOracle(const std::vector<Part>& oracle, const std::filesystem::path& ported) {
  for (const Part& part : port::ReadExrParts(ported)) {
    const Part* oraclePart = FindPart(oracle, part.name);
    INFO("part '" << part.name << "'");
    REQUIRE(oraclePart != nullptr);
    REQUIRE(oraclePart->width == part.width);
    REQUIRE(oraclePart->height == part.height);
    for (const auto& [channel, layer] : part.channels) {
      // Named as `ssgi diff` names layers: the channel in part "frame", else part:channel.
      const std::string name = part.name == "frame" ? channel : part.name + ":" + channel;
      const Layer* oracleLayer = FindChannel(*oraclePart, channel);
      if (oracleLayer == nullptr) {
        std::printf("  %-20s not in the oracle's dump\n", name.c_str());
        continue;
      }
      const LayerDiff diff = CompareLayer(*oracleLayer, layer);
      std::printf("  %-20s max abs %-9.3g max ulp %-6lld differing %zu of %zu\n", name.c_str(), diff.maxAbs,
                  (long long)diff.maxUlp, diff.differing, layer.samples.size());
      INFO(name << ": max abs " << diff.maxAbs << ", max ulp " << diff.maxUlp << ", " << diff.differing
                << " samples differ, the worst at (" << diff.worst % size_t(part.width) << ", "
                << diff.worst / size_t(part.width) << ")");
      CHECK(diff.differing == 0);
    }
  }
}

// How the port is run: chained (each pass on the port's own earlier buffers), and also with
// --oracle-inputs (each pass on the oracle's). When every layer of the chained run is exact, each
// pass of the other run sees the same bits, so it is run where the mode itself is to be tested.
enum class PortRuns { kChained, kChainedAndOracleInputs };

// Renders `sceneFile` at width x height with the oracle, runs the port on its buffers as `runs`
// says and checks every layer the port writes against the oracle's. Every layer must be bit-exact: the
// spec pins each operation and its order, and the shaders' `precise` forbids the contractions GLSL
// otherwise allows (tests/port/README.md); a tolerance here would hide a departure from the spec.
// (Thresholds for GPUs with approximate division or sqrt are `ssgi diff`'s, issue 13.)
void CheckPort(const std::filesystem::path& sceneFile, int width, int height, PortRuns runs = PortRuns::kChained) {
  if (std::string(kGlPortPath).empty()) {
    WARN("the GLSL port is not built (no EGL/OpenGL development files): skipped");
    return;
  }
  const SceneFile scene = LoadSceneFile(sceneFile);
  FrameConfig config = FrameConfigFromSceneFile(scene);
  config.width = width;
  config.height = height;
  const Frame frame = RenderFrame(scene.scene, config);
  REQUIRE(frame.reflections);
  const test::ScratchDir scratch("gl-port");
  const std::filesystem::path dump = scratch / "dump.exr", input = scratch / "oracle.exr",
                              ported = scratch / "port.exr";
  WriteFrameBuffers(dump, frame);
  // The port's input: the dump and the Hi-Z and colour-pyramid levels --oracle-inputs reads.
  const std::vector<Part> oracle = OracleParts(frame, dump);
  port::WriteExrParts(input, oracle);
  std::vector<std::string> modes = {""};
  if (runs == PortRuns::kChainedAndOracleInputs) modes.push_back(" --oracle-inputs");
  for (const std::string& mode : modes) {
    const test::CommandResult run = test::RunProgram(
        kGlPortPath,
        "--scene " + test::Quote(sceneFile) + " " + test::Quote(input) + " -o " + test::Quote(ported) + mode);
    if (run.exitCode == 77) {
      WARN("no EGL display with OpenGL 4.5 here, the port cannot run: skipped (" << run.output << ")");
      return;
    }
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    std::printf("port%s vs oracle, %s at %dx%d:\n", mode.c_str(), sceneFile.filename().c_str(), width, height);
    CompareWithOracle(oracle, ported);
  }
}

TEST_CASE("the GLSL port matches the oracle on the default scene", "[port]") {
  CheckPort(test::SourceDir() / "data" / "default.json", 160, 120, PortRuns::kChainedAndOracleInputs);
  CheckPort(test::SourceDir() / "data" / "default.json", 67, 45, PortRuns::kChainedAndOracleInputs);
  // Degenerate pyramids: one level; a 3-wide footprint beside a 1-tall one.
  CheckPort(test::SourceDir() / "data" / "default.json", 1, 1);
  CheckPort(test::SourceDir() / "data" / "default.json", 33, 2);
}

TEST_CASE("the GLSL port matches the oracle with a shadowed sun, an unshadowed spot and xyz8 normals", "[port]") {
  // What the default scene does not have: a spot light (and a second light), the paper's normal
  // encoding, a smooth metal that reflects the spot's highlight.
  const test::ScratchDir scratch("gl-port-scene");
  const std::string data = (test::SourceDir() / "data").string();
  test::WriteText(scratch / "scene.json", R"({
  "camera": { "position": [0, 2.2, 4.2], "target": [0, 0.3, 0], "up": [0, 1, 0], "fov_y_deg": 45, "near": 0.05 },
  "lights": [
    { "type": "directional", "direction": [-0.5, -1, -0.3], "irradiance": [2.5, 2.4, 2.2],
      "angular_diameter_deg": 2, "cast_shadows": true },
    { "type": "spot", "position": [1.2, 2.0, 1.0], "direction": [-0.5, -1, -0.5], "inner_cone_deg": 15,
      "outer_cone_deg": 30, "radius": 0.1, "intensity": [30, 27, 22], "cast_shadows": false }
  ],
  "objects": [
    { "obj": ")" + data + R"(/board.obj" },
    { "obj": ")" + data + R"(/sphere.obj", "transform": { "translate": [0.3, 0.45, 0], "scale": 0.45 },
      "materials": { "*": { "base_color": [0.95, 0.9, 0.85], "metallic": 1, "roughness": 0.08 } } },
    { "obj": ")" + data + R"(/box.obj", "transform": { "translate": [-0.6, 0.3, -0.4], "scale": 0.6 },
      "materials": { "*": { "base_color": [0.3, 0.5, 0.8], "metallic": 0, "roughness": 0.35 } } }
  ],
  "render": { "normal_encoding": "xyz8" }
})");
  CheckPort(scratch / "scene.json", 96, 72);
}

TEST_CASE("the GLSL port matches the oracle on Sponza and under Sibenik's shadowed spot", "[port][sponza]") {
  for (const char* scene : {"sponza", "sibenik"}) {
    const std::filesystem::path folder =
        test::ThirdPartyScenesDir() / (scene == std::string("sponza") ? "dabrovic-sponza" : "sibenik-cathedral");
    if (!std::filesystem::exists(folder)) {
      WARN("skipped: " << folder << " is not present");
      continue;
    }
    CheckPort(test::SourceDir() / "data" / "scenes" / (std::string(scene) + ".json"), 256, 192);
  }
}

}  // namespace
}  // namespace ssgi
