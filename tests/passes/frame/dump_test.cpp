// The frame dump (passes/frame/dump.h): every buffer written exactly, read back exactly, and the
// pipeline run from any pass on a dump's buffers giving the frame's bytes; bad dumps refused with
// the layer named.
#include "passes/frame/dump.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include <catch2/catch.hpp>

#include "core/error.h"
#include "passes/frame/diff.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

struct DumpedFrame {
  Scene scene;
  FrameConfig config;
  Frame frame;
  ExrFile dump;
};

DumpedFrame RenderAndDump(const fs::path& path, int width, int height,
                          std::optional<Antialiasing> antialiasing = std::nullopt) {
  const test::DefaultScene defaults = test::LoadDefaultScene();
  DumpedFrame d{defaults.scene, defaults.config, {}, {}};
  d.config.width = width;
  d.config.height = height;
  if (antialiasing) d.config.antialiasing = *antialiasing;
  d.frame = RenderFrame(d.scene, d.config);
  WriteFrameDump(path, d.frame, DumpMetadata("scene.json", d.config));
  d.dump = ReadExrFile(path);
  return d;
}

template <class T>
bool SameAsLayer(const ExrFile& dump, const std::string& part, const std::string& name, const Plane<T>& plane) {
  const ExrLayer* layer = dump.Find(part, name);
  if (layer == nullptr || size_t(layer->width) != plane.xsize() || size_t(layer->height) != plane.ysize()) return false;
  for (size_t y = 0; y < plane.ysize(); ++y)
    if (std::memcmp(layer->samples.data() + y * plane.xsize(), plane.ConstRow(y), plane.xsize() * 4) != 0) return false;
  return true;
}

// Every compared layer bit for bit equal, and how many were compared.
size_t ExactlyEqualLayers(const ExrFile& a, const ExrFile& b) {
  DiffThresholds exact;  // no rules: every layer exact
  const DiffReport report = DiffDumps(a, b, exact, std::nullopt);
  size_t compared = 0;
  for (const LayerDiff& layer : report.layers) {
    CAPTURE(layer.id, layer.problem, layer.maxAbsolute, layer.overTolerance);
    CHECK(layer.ok);
    if (layer.compared) ++compared;
  }
  CHECK(report.ok);
  return compared;
}

TEST_CASE("frame dump: every buffer of the frame as its catalogue layer, bit for bit", "[dump]") {
  test::ScratchDir dir("dump-layers");
  const DumpedFrame d = RenderAndDump(dir / "frame.exr", 67, 45);
  const Frame& f = d.frame;
  REQUIRE(f.shadows);
  REQUIRE(f.reflections);
  const GBuffer& g = f.gbuffer.gbuffer;
  for (int w = 0; w < 4; ++w) CHECK(SameAsLayer(d.dump, "frame", "gbuffer.word" + std::to_string(w), g.word[w]));
  CHECK(SameAsLayer(d.dump, "frame", "raster.triangle", f.gbuffer.visibility.triangle));
  CHECK(SameAsLayer(d.dump, "shadowmap", "depthKey", f.shadowMap->shadowMap.depthKey));
  CHECK(SameAsLayer(d.dump, "frame", "shadow.visibility", f.shadowVisibility.visibility));
  CHECK(SameAsLayer(d.dump, "frame", "direct.G", f.direct.radiance.c[1]));
  for (size_t k = 0; k < f.hiz.levels.size(); ++k)
    CHECK(SameAsLayer(d.dump, "hiz." + std::to_string(k), "Y", f.hiz.levels[k]));
  for (size_t k = 0; k < f.colorPyramid.levels.size(); ++k)
    CHECK(SameAsLayer(d.dump, "pyramid." + std::to_string(k), "B", f.colorPyramid.levels[k].c[2]));
  CHECK(SameAsLayer(d.dump, "frame", "ssr.hitX", f.ssrTrace.hitX));
  CHECK(SameAsLayer(d.dump, "frame", "ssr.reflected.R", f.ssrCone.reflected.c[0]));
  CHECK(SameAsLayer(d.dump, "frame", "result.B", f.composite.result.c[2]));
  const ExrLayer* display = d.dump.Find("frame", "display.G");
  REQUIRE(display != nullptr);
  CHECK(display->isUint);
  for (size_t i = 0; i < display->samples.size(); ++i) CHECK(display->samples[i] == f.display.rgb[i * 3 + 1]);
  // Every catalogue layer of the main part is in the file: this frame runs every pass but the
  // morphological one, the alternative to the G-buffer's edge coverage (checked below).
  for (const DumpLayer& layer : DumpLayers()) {
    if (layer.part != DumpPart::kImage || layer.pass == FramePass::kMlaa) continue;
    CAPTURE(layer.name);
    const ExrLayer* found = d.dump.Find("frame", std::string(layer.name));
    REQUIRE(found != nullptr);
    CHECK(found->isUint == layer.isUint);
  }
  CHECK(d.dump.metadata.at("ssgi:scene") == "scene.json");
  const DumpedFrame m = RenderAndDump(dir / "mlaa.exr", 67, 45, Antialiasing::kMlaa);
  CHECK(SameAsLayer(m.dump, "frame", "mlaa.luma", m.frame.mlaa.luma));
  CHECK(SameAsLayer(m.dump, "frame", "mlaa.edges", m.frame.mlaa.edges));
  CHECK(SameAsLayer(m.dump, "frame", "mlaa.weights", m.frame.mlaa.weights));
  CHECK(SameAsLayer(m.dump, "frame", "mlaa.coverage", m.frame.mlaa.coverage));
  CHECK(SameAsLayer(m.dump, "frame", "aa.result.R", m.frame.antialiased.c[0]));
  CHECK(m.dump.Find("frame", "aa.coverage") == nullptr);
}

TEST_CASE("frame dump: the pipeline run from any pass on the dump's buffers gives the frame's bytes", "[dump]") {
  test::ScratchDir dir("dump-passes");
  for (const auto& [width, height, antialiasing] :
       {std::tuple<int, int, std::optional<Antialiasing>>{67, 45, std::nullopt},
        {1, 1, std::nullopt},
        {67, 45, Antialiasing::kMlaa}}) {
    const DumpedFrame d = RenderAndDump(dir / "frame.exr", width, height, antialiasing);
    for (FramePass from : kFramePasses) {
      for (FramePass to : {from, FramePass::kTonemap}) {
        CAPTURE(width, height, FramePassName(from), FramePassName(to));
        Frame frame;
        LoadFrameDump(d.dump, dir / "frame.exr", d.scene, d.config, from, to, frame);
        RunFramePasses(d.scene, d.config, from, to, frame);
        WriteFrameDump(dir / "rerun.exr", frame, DumpMetadata("scene.json", d.config));
        CHECK(ExactlyEqualLayers(d.dump, ReadExrFile(dir / "rerun.exr")) > 0);
      }
    }
  }
}

// The message of the InputError LoadFrameDump throws for `dump`, run from `from`.
std::string LoadError(const DumpedFrame& d, const ExrFile& dump, FramePass from) {
  Frame frame;
  try {
    LoadFrameDump(dump, "port.exr", d.scene, d.config, from, FramePass::kTonemap, frame);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

ExrLayer& LayerOf(ExrFile& dump, const std::string& part, const std::string& name) {
  for (ExrLayer& layer : dump.layers)
    if (layer.part == part && layer.name == name) return layer;
  FAIL("no layer " << part << ":" << name);
  return dump.layers.front();
}

TEST_CASE("frame dump: a missing, misshapen or non-finite input is refused naming the layer", "[dump][errors]") {
  test::ScratchDir dir("dump-bad");
  const DumpedFrame d = RenderAndDump(dir / "frame.exr", 67, 45);
  {
    ExrFile dump = d.dump;
    dump.layers.erase(dump.layers.begin() + (&LayerOf(dump, "frame", "direct.G") - dump.layers.data()));
    const std::string message = LoadError(d, dump, FramePass::kSkyLight);
    CHECK(message == "port.exr: layer 'direct.G': missing, and a pass to run reads it");
    // Running from the direct light on, the layer is made, not read; from the colour pyramid on, the
    // passes read the lit image instead.
    CHECK(LoadError(d, dump, FramePass::kDirectLight).empty());
    CHECK(LoadError(d, dump, FramePass::kColorPyramid).empty());
  }
  {
    ExrFile dump = d.dump;
    LayerOf(dump, "hiz.2", "Y").width = 3;
    CHECK(LoadError(d, dump, FramePass::kSsrTrace) == "port.exr: layer 'Y' of part 'hiz.2': is 3x11, must be 16x11");
  }
  {
    ExrFile dump = d.dump;
    LayerOf(dump, "frame", "gbuffer.word1").isUint = false;
    CHECK(LoadError(d, dump, FramePass::kHiZ) == "port.exr: layer 'gbuffer.word1': is float, must be uint32");
  }
  {
    ExrFile dump = d.dump;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&LayerOf(dump, "frame", "ssr.confidence").samples[5 * 67 + 7], &nan, 4);
    CHECK(LoadError(d, dump, FramePass::kComposite) == "port.exr: layer 'ssr.confidence': pixel (7, 5) is NaN");
  }
}

TEST_CASE("EXR files: truncated and non-EXR files are refused with the file named", "[dump][errors]") {
  test::ScratchDir dir("dump-files");
  RenderAndDump(dir / "frame.exr", 8, 8);
  std::ifstream in(dir / "frame.exr", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(dir / "truncated.exr", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::ofstream(dir / "text.exr") << "not an image\n";
  for (const char* name : {"truncated.exr", "text.exr", "missing.exr"}) {
    CAPTURE(name);
    try {
      ReadExrFile(dir / name);
      FAIL("read");
    } catch (const InputError& e) {
      CHECK(std::string(e.what()).find(name) != std::string::npos);
    }
  }
  // What ReadExrFile read, WriteExrFile writes back.
  const ExrFile original = ReadExrFile(dir / "frame.exr");
  WriteExrFile(dir / "copy.exr", original);
  CHECK(ExactlyEqualLayers(original, ReadExrFile(dir / "copy.exr")) == original.layers.size());
}

TEST_CASE("frame dump: docs/pipeline.md's table names every layer of the catalogue", "[dump][docs]") {
  std::ifstream in(test::SourceDir() / "docs" / "pipeline.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t begin = doc.find("## Dumps"), end = doc.find("## Matching rules");
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  const std::string section = doc.substr(begin, end - begin);
  for (const DumpLayer& layer : DumpLayers()) {
    std::string name(layer.name);
    // "albedo.R" is documented as `albedo.R/G/B`, "normal.X" as `normal.X/Y/Z`.
    const size_t dot = name.rfind('.');
    if (dot != std::string::npos && name.size() - dot == 2) name = name.substr(0, dot + 1);
    if (layer.part == DumpPart::kShadowMap) name = "shadowmap:" + name;
    if (layer.part == DumpPart::kSkyVolume) name = "skyvolume:" + name;
    if (layer.part == DumpPart::kBounceHalf) name = "bounce.half:" + name;
    if (layer.part == DumpPart::kHiZLevels) name = "hiz.L:";
    if (layer.part == DumpPart::kPyramidLevels) name = "pyramid.L:";
    CAPTURE(layer.name, name);
    CHECK(section.find("`" + name) != std::string::npos);
    CHECK(section.find(std::string(FramePassName(layer.pass))) != std::string::npos);
  }
}

}  // namespace
}  // namespace ssgi
