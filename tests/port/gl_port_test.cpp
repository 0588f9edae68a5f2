// The GLSL port (tests/port/, ssgi_gl_port) against the oracle, layer by layer: every layer bit for
// bit (tests/port/README.md). Skipped with a warning where the port is not built (no EGL/GL
// development files) or no EGL display with OpenGL 4.5 exists.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "passes/frame/config.h"
#include "passes/frame/diff.h"
#include "passes/frame/dump.h"
#include "passes/frame/frame.h"
#include "passes/gbuffer.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

// The port's executable; "" where it is not built (no EGL/OpenGL development files).
#ifdef SSGI_GL_PORT_PATH
constexpr const char* kGlPortPath = SSGI_GL_PORT_PATH;
#else
constexpr const char* kGlPortPath = "";
#endif

// Checks every layer of the port's output against the oracle's dump with `ssgi diff`'s comparison
// and no tolerance at all (every layer exact). Prints one line per layer the port wrote.
void CompareWithOracle(const ExrFile& oracle, const std::filesystem::path& ported) {
  const ExrFile port = ReadExrFile(ported);
  const DiffReport report = DiffDumps(oracle, port, DiffThresholds{}, std::nullopt);
  size_t compared = 0;
  for (const LayerDiff& layer : report.layers) {
    if (!layer.compared) continue;
    ++compared;
    std::printf("  %-20s max abs %-9.3g max ulp %-6llu differing %zu of %zu\n", layer.id.c_str(), layer.maxAbsolute,
                static_cast<unsigned long long>(layer.maxUlp), layer.overTolerance, layer.samples);
    INFO(layer.id << ": max abs " << layer.maxAbsolute << ", max ulp " << layer.maxUlp << ", " << layer.overTolerance
                  << " samples differ, the worst at (" << layer.worstX << ", " << layer.worstY << ")");
    CHECK(layer.ok);
  }
  // The port writes the direct light, every Hi-Z and pyramid level, the trace, cone and composite,
  // the bounce's layers and every half-resolution step where the oracle ran the bounce, and the
  // anti-aliased result where the oracle blended one.
  CHECK(compared >= 18);
  if (oracle.Find("frame", "bounce.visibility") != nullptr) {
    CHECK(port.Find("frame", "bounce.visibility") != nullptr);
    CHECK(port.Find("bounce.half", "filtered.visibility") != nullptr);
  }
  // And the anti-aliasing where the oracle ran it, exact like every layer here: the port's own
  // coverage words (the geometric edges' or the morphological steps') and the blend by them.
  for (const char* layer : {"aa.result.R", "aa.coverage", "mlaa.luma", "mlaa.edges", "mlaa.weights", "mlaa.coverage"})
    if (oracle.Find("frame", layer) != nullptr) {
      INFO(layer);
      CHECK(port.Find("frame", layer) != nullptr);
    }
  // How much the words hold: the pixels with an edge bit or a coverage word.
  for (const char* name : {"aa.coverage", "mlaa.edges", "mlaa.coverage"})
    if (const ExrLayer* layer = oracle.Find("frame", name))
      std::printf(
          "  %-20s %zu of %zu words not 0\n", name,
          size_t(std::count_if(layer->samples.begin(), layer->samples.end(), [](uint32_t w) { return w != 0; })),
          layer->samples.size());
  CHECK(report.ok);
}

// How the port is run: chained (each pass on the port's own earlier buffers), and also with
// --oracle-inputs (each pass on the oracle's). When every layer of the chained run is exact, each
// pass of the other run sees the same bits, so it is run where the mode itself is to be tested.
enum class PortRuns { kChained, kChainedAndOracleInputs };

// The oracle's frame with its default effects and the diffuse bounce on (in `auto` the interreflection
// volume stands for it where the sky light runs), or with the bounce off: the composite without its terms.
enum class Bounce { kOn, kOff };

// Renders `sceneFile` at width x height with the oracle, runs the port on its buffers as `runs`
// says and checks every layer the port writes against the oracle's. Every layer must be bit-exact: the
// spec pins each operation and its order, and the shaders' `precise` forbids the contractions GLSL
// otherwise allows (tests/port/README.md); a tolerance here would hide a departure from the spec.
// (Thresholds for GPUs with approximate division or sqrt are `ssgi diff`'s, data/diff_thresholds.json.)
void CheckPort(const std::filesystem::path& sceneFile, int width, int height, PortRuns runs = PortRuns::kChained,
               Bounce bounce = Bounce::kOn, Antialiasing antialiasing = Antialiasing::kEdge) {
  if (std::string(kGlPortPath).empty()) {
    WARN("the GLSL port is not built (no EGL/OpenGL development files): skipped");
    return;
  }
  const SceneFile scene = LoadSceneFile(sceneFile);
  FrameConfig config = FrameConfigFromSceneFile(scene);
  config.width = width;
  config.height = height;
  config.bounce = bounce == Bounce::kOn ? EffectMode::kOn : EffectMode::kOff;
  config.antialiasing = antialiasing;
  const Frame frame = RenderFrame(scene.scene, config);
  REQUIRE(frame.reflections);
  REQUIRE(frame.bounce == (bounce == Bounce::kOn));
  const test::ScratchDir scratch("gl-port");
  const std::filesystem::path input = scratch / "oracle.exr", ported = scratch / "port.exr";
  WriteFrameDump(input, frame, DumpMetadata(std::filesystem::absolute(sceneFile).string(), config));
  const ExrFile oracle = ReadExrFile(input);
  std::vector<std::string> modes = {""};
  if (runs == PortRuns::kChainedAndOracleInputs) modes.push_back(" --oracle-inputs");
  for (const std::string& mode : modes) {
    const test::CommandResult run = test::RunProgram(
        kGlPortPath,
        test::Quote(input) + " -o " + test::Quote(ported) + mode);
    if (run.exitCode == 77) {
      WARN("no EGL display with OpenGL 4.5 here, the port cannot run: skipped (" << run.output << ")");
      return;
    }
    INFO(run.output);
    REQUIRE(run.exitCode == 0);
    std::printf("port%s vs oracle, %s at %dx%d%s%s:\n", mode.c_str(), sceneFile.filename().c_str(), width, height,
                frame.bounce ? "" : ", bounce off", antialiasing == Antialiasing::kMlaa ? ", --aa mlaa" : "");
    CompareWithOracle(oracle, ported);
    // And as a port engineer checks it: `ssgi diff` with the shipped tolerances passes.
    const test::CommandResult diff = test::RunCli("diff " + test::Quote(input) + " " + test::Quote(ported));
    INFO(diff.output);
    CHECK(diff.exitCode == 0);
  }
}

// The oracle's default frame of `sceneFile` at width x height dumped to `input`, and the port run on
// it with --raster `raster` into `ported`: false, with a warning, where the port is not built or
// cannot run here. `skyDirections` > 0 replaces the scene's count of sky volume maps.
bool RenderAndRunRasterPort(const std::filesystem::path& sceneFile, int width, int height, const std::string& raster,
                            const std::filesystem::path& input, const std::filesystem::path& ported, Frame& frame,
                            FrameConfig& config, int skyDirections = 0) {
  if (std::string(kGlPortPath).empty()) {
    WARN("the GLSL port is not built (no EGL/OpenGL development files): skipped");
    return false;
  }
  config = FrameConfigFromSceneFile(LoadSceneFile(sceneFile));
  config.width = width;
  config.height = height;
  if (skyDirections > 0) config.skyVisibility.directions = skyDirections;
  frame = RenderFrame(LoadSceneFile(sceneFile).scene, config);
  WriteFrameDump(input, frame, DumpMetadata(std::filesystem::absolute(sceneFile).string(), config));
  const test::CommandResult run =
      test::RunProgram(kGlPortPath, test::Quote(input) + " -o " + test::Quote(ported) + " --raster " + raster);
  if (run.exitCode == 77) {
    WARN("no EGL display with OpenGL 4.5 here, the port cannot run: skipped (" << run.output << ")");
    return false;
  }
  INFO(run.output);
  REQUIRE(run.exitCode == 0);
  return true;
}

// The port's edge coverage words (--aa edge) from its own visibility buffer against the oracle's
// definition run on that buffer (EdgeCoverageRows): every word equal. The words that differ from
// the oracle's frame then differ only through the pixels GL's rasterizer covers otherwise.
void CheckEdgeCoverageOnPortRaster(const Scene& scene, const ViewProjection& view, const ExrFile& port) {
  const size_t width = size_t(view.width), height = size_t(view.height);
  const DumpSource source(port, "port", width, height);
  VisibilityBuffer visibility;
  source.Load(DumpPart::kImage, 0, "raster.triangle", visibility.triangle);
  source.Load(DumpPart::kImage, 0, "raster.depthKey", visibility.depthKey);
  Plane<uint32_t> expected = MakePlane<uint32_t>(width, height, 0u), ported = MakePlane<uint32_t>(width, height, 0u);
  const size_t edgePixels = EdgeCoverageRows(scene, view, visibility, 0, height, expected);
  source.Load(DumpPart::kImage, 0, "aa.coverage", ported);
  size_t differing = 0;
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) differing += expected.ConstRow(y)[x] != ported.ConstRow(y)[x] ? 1 : 0;
  std::printf(
      "  aa.coverage      %zu of %zu words differ from the oracle's on the port's visibility buffer (%zu edge "
      "words)\n",
      differing, width * height, edgePixels);
  CHECK(differing == 0);
}

// The port from the scene's triangles (--raster visibility: the G-buffer and the shadow map on GL's
// own rasterizer, the oracle's depth key and resolve). The G-buffer's layers are judged against the oracle's with
// `ssgi diff`'s shipped rules and the scene's geometry: every difference lies within the coverage
// rule's distance of a triangle edge. The passes after it are judged against the oracle run on the
// port's G-buffer (`ssgi passes --from shadow_map`), as the matching rules say: the edge pixels that
// legitimately differ change what every later pass sees. Prints the differing pixels per layer.
void CheckRasterPort(const std::filesystem::path& sceneFile, int width, int height, int skyDirections = 0) {
  const test::ScratchDir scratch("gl-port-raster");
  const std::filesystem::path input = scratch / "oracle.exr", ported = scratch / "port.exr";
  const std::filesystem::path onPort = scratch / "oracle_on_port.exr";
  Frame frame;
  FrameConfig config;
  if (!RenderAndRunRasterPort(sceneFile, width, height, "visibility", input, ported, frame, config, skyDirections))
    return;
  const SceneFile scene = LoadSceneFile(sceneFile);
  const DiffThresholds thresholds = LoadDiffThresholds(test::SourceDir() / "data" / "diff_thresholds.json");
  const ViewProjection view = MakePerspective(scene.scene.camera, width, height);
  const ExrFile port = ReadExrFile(ported);
  const ExrFile oracle = ReadExrFile(input);
  const DiffReport gbuffer = DiffDumps(oracle, port, thresholds, CoverageGeometry{scene.scene.mesh, view});
  std::printf("port from triangles vs oracle, %s at %dx%d (G-buffer; pixels differing, farthest from its edge):\n",
              sceneFile.filename().c_str(), width, height);
  size_t compared = 0;
  for (const LayerDiff& layer : gbuffer.layers) {
    if (!layer.compared || layer.pass != FramePass::kGBuffer) continue;
    ++compared;
    if (layer.edgePixels + layer.overTolerance > 0)
      std::printf("  %-16s %4zu, %zu away from every edge, farthest %.5f px\n", layer.id.c_str(),
                  layer.edgePixels + layer.overTolerance, layer.overTolerance, layer.maxEdgeDistance);
    INFO(layer.id << ": " << layer.overTolerance << " samples differ away from every edge, the worst at ("
                  << layer.worstX << ", " << layer.worstY << ")");
    CHECK(layer.ok);
    // The coverage words beside a pixel GL covered otherwise are other pairs' words, though that
    // pixel's neighbours lie farther from the edge: the shipped rule allows 1 % of them.
    if (layer.id != "aa.coverage") CHECK(layer.overTolerance == 0);
  }
  // Words 0-2, their nine decoded layers, the visibility buffer's two and the edge coverage words.
  CHECK(compared == 15);
  CheckEdgeCoverageOnPortRaster(scene.scene, view, port);
  // The port's sky visibility volume (its maps on GL's rasterizer) against the oracle's: the
  // coefficients of cells whose test reads a silhouette texel the two maps cover otherwise differ.
  bool volumeCompared = false;
  for (const LayerDiff& layer : gbuffer.layers) {
    if (layer.id != "skyvolume:k" || !layer.compared) continue;
    volumeCompared = true;
    size_t differing = 0;
    const ExrLayer* a = oracle.Find("skyvolume", "k");
    const ExrLayer* b = port.Find("skyvolume", "k");
    REQUIRE((a != nullptr && b != nullptr && a->samples.size() == b->samples.size()));
    for (size_t i = 0; i < a->samples.size(); ++i) differing += a->samples[i] != b->samples[i] ? 1 : 0;
    std::printf("  skyvolume:k      %zu of %zu coefficients differ (%.3f %%), largest %.4g, %zu beyond tolerance\n",
                differing, layer.samples, 100.0 * double(differing) / double(layer.samples), layer.maxAbsolute,
                layer.overTolerance);
    INFO("skyvolume:k: " << layer.overTolerance << " coefficients beyond tolerance");
    CHECK(layer.ok);
  }
  CHECK(volumeCompared == frame.sky);

  const test::CommandResult passes =
      test::RunCli("passes " + test::Quote(ported) + " --from shadow_map -o " + test::Quote(onPort));
  INFO(passes.output);
  REQUIRE(passes.exitCode == 0);
  const ExrFile oracleOnPort = ReadExrFile(onPort);
  const std::optional<ViewProjection> shadowView = DiffShadowView(oracleOnPort, port, scene.scene, config);
  CHECK(shadowView.has_value() == frame.shadows);
  const DiffReport after =
      DiffDumps(oracleOnPort, port, thresholds,
                CoverageGeometry{scene.scene.mesh, view, kCoverageRounding, shadowView ? &*shadowView : nullptr});
  for (const LayerDiff& layer : after.layers) {
    if (!layer.compared || layer.pass == FramePass::kGBuffer) continue;
    if (layer.edgePixels + layer.overTolerance > 0)
      std::printf("  vs the oracle on the port's G-buffer: %-18s %zu at edges (farthest %.5f), %zu beyond tolerance\n",
                  layer.id.c_str(), layer.edgePixels, layer.maxEdgeDistance, layer.overTolerance);
    INFO(layer.id << " against the oracle on the port's G-buffer: " << layer.overTolerance << " beyond tolerance");
    CHECK(layer.ok);
  }
  CHECK(after.ok);
}

// The conventional G-buffer (--raster conventional: the words from interpolated varyings, GL's own
// depth test) against the oracle's with the rules for it (data/diff_thresholds_conventional.json),
// which the port's measurements set. Prints each decoded layer's largest difference.
void CheckConventionalPort(const std::filesystem::path& sceneFile, int width, int height) {
  const test::ScratchDir scratch("gl-port-conventional");
  const std::filesystem::path input = scratch / "oracle.exr", ported = scratch / "port.exr";
  Frame frame;
  FrameConfig config;
  if (!RenderAndRunRasterPort(sceneFile, width, height, "conventional", input, ported, frame, config)) return;
  const SceneFile scene = LoadSceneFile(sceneFile);
  const ViewProjection view = MakePerspective(scene.scene.camera, width, height);
  const DiffReport report =
      DiffDumps(ReadExrFile(input), ReadExrFile(ported),
                LoadDiffThresholds(test::SourceDir() / "data" / "diff_thresholds_conventional.json"),
                CoverageGeometry{scene.scene.mesh, view});
  std::printf("conventional G-buffer vs oracle, %s at %dx%d (largest difference, samples beyond):\n",
              sceneFile.filename().c_str(), width, height);
  for (const LayerDiff& layer : report.layers) {
    if (!layer.compared || layer.pass != FramePass::kGBuffer || layer.id.rfind("gbuffer.word", 0) == 0) continue;
    if (layer.maxAbsolute > 0.0 || layer.overTolerance > 0)
      std::printf("  %-16s %-9.3g %zu\n", layer.id.c_str(), layer.maxAbsolute, layer.overTolerance);
    INFO(layer.id << ": " << layer.overTolerance << " samples beyond tolerance, the worst at (" << layer.worstX << ", "
                  << layer.worstY << ")");
    CHECK(layer.ok);
  }
  // The port's own sky visibility volume, under the shipped file's rule.
  for (const LayerDiff& layer : report.layers) {
    if (layer.id != "skyvolume:k") continue;
    INFO("skyvolume:k: " << layer.overTolerance << " coefficients beyond tolerance");
    CHECK(layer.compared == frame.sky);
    CHECK(layer.ok);
  }
}

TEST_CASE("the port's G-buffer pass on GL's rasterizer differs from the oracle only at edges", "[port]") {
  CheckRasterPort(test::SourceDir() / "data" / "default.json", 160, 120);
  // 16 sky volume maps: fewer to build, and a flipped direction weighs three times the default's.
  CheckRasterPort(test::SourceDir() / "data" / "default.json", 333, 197, 16);
  CheckConventionalPort(test::SourceDir() / "data" / "default.json", 160, 120);
  // Specular anti-aliasing on (the scene's render block): small curved metals.
  CheckRasterPort(test::SourceDir() / "data" / "specular_aa.json", 160, 120);
  CheckConventionalPort(test::SourceDir() / "data" / "specular_aa.json", 160, 120);
}

TEST_CASE("the GLSL port matches the oracle on the default scene", "[port]") {
  CheckPort(test::SourceDir() / "data" / "default.json", 160, 120, PortRuns::kChainedAndOracleInputs);
  CheckPort(test::SourceDir() / "data" / "default.json", 67, 45, PortRuns::kChainedAndOracleInputs);
  // Without the bounce: the composite is the same operations as before the bounce existed.
  CheckPort(test::SourceDir() / "data" / "default.json", 160, 120, PortRuns::kChainedAndOracleInputs, Bounce::kOff);
  // Degenerate pyramids: one level; a 3-wide footprint beside a 1-tall one.
  CheckPort(test::SourceDir() / "data" / "default.json", 1, 1);
  CheckPort(test::SourceDir() / "data" / "default.json", 33, 2);
  // Morphological anti-aliasing: the luma, edges, runs, weights and coverage words the port
  // computes from its own result.
  CheckPort(test::SourceDir() / "data" / "default.json", 160, 120, PortRuns::kChainedAndOracleInputs, Bounce::kOn,
            Antialiasing::kMlaa);
  CheckPort(test::SourceDir() / "data" / "default.json", 33, 2, PortRuns::kChained, Bounce::kOn,
            Antialiasing::kMlaa);
}

TEST_CASE("the GLSL port matches the oracle with a shadowed sun, an unshadowed spot, xyz8 normals and SSPCSS",
          "[port]") {
  // What the default scene does not have: a spot light (and a second light), the paper's normal
  // encoding, a smooth metal that reflects the spot's highlight, specular anti-aliasing.
  const test::ScratchDir scratch("gl-port-scene");
  const std::string data = (test::SourceDir() / "data").string();
  const std::string scene = R"({
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
  "render": )";
  test::WriteText(scratch / "scene.json", scene + R"({ "normal_encoding": "xyz8", "specular_aa": 0.18 } })");
  CheckPort(scratch / "scene.json", 96, 72);
  // The other filters, tap counts and an odd map size of the shadow passes, on the same scene.
  test::WriteText(
      scratch / "sspcss.json",
      scene + R"({ "shadow_filter": "sspcss", "blur_taps": 2, "blocker_taps": 16, "shadow_map_size": 517 } })");
  CheckPort(scratch / "sspcss.json", 96, 72);
  // MLAA sees the image through the tonemap's exposure: the luma's scale is not 1 here.
  test::WriteText(scratch / "exposure.json", scene + R"({ "exposure_ev": 1.7 } })");
  CheckPort(scratch / "exposure.json", 96, 72, PortRuns::kChained, Bounce::kOn, Antialiasing::kMlaa);
}

TEST_CASE("the GLSL port matches the oracle on Sponza and under Sibenik's shadowed spot", "[port][sponza]") {
  for (const char* scene : {"sponza", "sibenik"}) {
    const std::filesystem::path model =
        test::ThirdPartyScenesDir() /
        (scene == std::string("sponza") ? "dabrovic-sponza/sponza.obj" : "sibenik-cathedral/sibenik.obj");
    if (!std::filesystem::exists(model)) {
      WARN(test::MissingScenesMessage(model));
      continue;
    }
    CheckPort(test::SourceDir() / "data" / "scenes" / (std::string(scene) + ".json"), 256, 192);
    // Sibenik has the more luma edges (its spot's shadows): 9,033 pixels against Sponza's 3,500.
    if (scene == std::string("sibenik"))
      CheckPort(test::SourceDir() / "data" / "scenes" / "sibenik.json", 256, 192, PortRuns::kChained, Bounce::kOn,
                Antialiasing::kMlaa);
    CheckRasterPort(test::SourceDir() / "data" / "scenes" / (std::string(scene) + ".json"), 256, 192);
    CheckRasterPort(test::SourceDir() / "data" / "scenes" / (std::string(scene) + ".json"), 517, 391, 16);
    CheckConventionalPort(test::SourceDir() / "data" / "scenes" / (std::string(scene) + ".json"), 256, 192);
  }
}

}  // namespace
}  // namespace ssgi
