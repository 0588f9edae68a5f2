// `ssgi diff`'s comparison (passes/frame/diff.h): tolerances, the first failing pass in pipeline
// order, percent and hard limits, coverage differences judged by their distance to an edge, and
// the thresholds file.
#include "passes/frame/diff.h"

#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "passes/frame/dump.h"
#include "tests/passes/test_scenes.h"
#include "tests/test_support.h"

namespace ssgi {
namespace {

namespace fs = std::filesystem;

DiffThresholds ShippedThresholds() { return LoadDiffThresholds(test::SourceDir() / "data" / "diff_thresholds.json"); }

const ExrFile& OracleDump() {
  static const ExrFile dump = [] {
    test::ScratchDir dir("diff-oracle");
    const test::DefaultScene scene = test::LoadDefaultScene();
    WriteFrameDump(dir / "oracle.exr", scene.Render(67, 45), DumpMetadata("", scene.config));
    return ReadExrFile(dir / "oracle.exr");
  }();
  return dump;
}

ExrLayer& LayerOf(ExrFile& dump, const std::string& part, const std::string& name) {
  for (ExrLayer& layer : dump.layers)
    if (layer.part == part && layer.name == name) return layer;
  FAIL("no layer " << part << ":" << name);
  return dump.layers.front();
}

void AddToFloat(ExrLayer& layer, size_t i, float delta) {
  float value;
  std::memcpy(&value, &layer.samples[i], 4);
  value += delta;
  std::memcpy(&layer.samples[i], &value, 4);
}

const LayerDiff& Find(const DiffReport& report, const std::string& id) {
  for (const LayerDiff& layer : report.layers)
    if (layer.id == id) return layer;
  FAIL("no layer " << id << " in the report");
  return report.layers.front();
}

TEST_CASE("diff: a dump against itself passes on every layer", "[diff]") {
  const DiffReport report = DiffDumps(OracleDump(), OracleDump(), ShippedThresholds(), std::nullopt);
  CHECK(report.ok);
  CHECK_FALSE(report.firstFailingPass);
  CHECK(report.layers.size() == OracleDump().layers.size());
  for (const LayerDiff& layer : report.layers) {
    CAPTURE(layer.id);
    CHECK(layer.compared);
    CHECK(layer.maxAbsolute == 0.0);
  }
  // Pipeline order, levels grouped: hiz.0 before pyramid.0, pyramid.0's R, G, B together.
  CHECK(report.layers.front().id == "gbuffer.word0");
  CHECK(report.layers.back().id == "display.B");
  size_t pyramidR = 0;
  while (report.layers[pyramidR].id != "pyramid.0:R") ++pyramidR;
  CHECK(report.layers[pyramidR + 1].id == "pyramid.0:G");
  CHECK(report.layers[pyramidR - 1].id.rfind("hiz.", 0) == 0);
}

TEST_CASE("diff: tolerances, the first failing pass, percent and hard limits", "[diff]") {
  const DiffThresholds thresholds = ShippedThresholds();
  SECTION("a last-bit difference in the direct light is within its tolerance") {
    ExrFile port = OracleDump();
    LayerOf(port, "frame", "direct.R").samples[100] += 1;
    const DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK(report.ok);
    CHECK(Find(report, "direct.R").maxUlp == 1);
  }
  SECTION("a large difference fails, and the earliest pass in the pipeline is named") {
    ExrFile port = OracleDump();
    AddToFloat(LayerOf(port, "frame", "result.G"), 3, 5.0f);
    AddToFloat(LayerOf(port, "hiz.1", "Y"), 7, 0.5f);
    const DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK_FALSE(report.ok);
    REQUIRE(report.firstFailingPass);
    CHECK(*report.firstFailingPass == FramePass::kHiZ);
    const LayerDiff& hiz = Find(report, "hiz.1:Y");
    CHECK_FALSE(hiz.ok);
    CHECK(hiz.overTolerance == 1);
    CHECK(hiz.worstX == 7 % 33);
    CHECK(hiz.worstY == 7 / 33);
  }
  SECTION("an integer word differs: exact layers fail on one bit") {
    ExrFile port = OracleDump();
    LayerOf(port, "frame", "gbuffer.word1").samples[67 * 20 + 30] ^= 1u;
    const DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK(*report.firstFailingPass == FramePass::kGBuffer);
  }
  SECTION("percent: a few hits elsewhere pass, more than the share fail; a hard limit fails at once") {
    DiffThresholds rules;
    LayerTolerance hits;
    hits.absolute = 0.001;
    hits.percent = 1.0;  // 30 of 3015 samples
    rules.rules.emplace_back("ssr.hit*", hits);
    rules.rules.emplace_back("*", LayerTolerance{});
    ExrFile port = OracleDump();
    for (size_t i = 0; i < 30; ++i) AddToFloat(LayerOf(port, "frame", "ssr.hitX"), i * 97, 3.0f);
    CHECK(DiffDumps(OracleDump(), port, rules, std::nullopt).ok);
    AddToFloat(LayerOf(port, "frame", "ssr.hitX"), 2999, 3.0f);
    CHECK_FALSE(DiffDumps(OracleDump(), port, rules, std::nullopt).ok);
    rules.rules.front().second.percent = 100.0;
    rules.rules.front().second.hardFail = 2.0;
    const DiffReport hard = DiffDumps(OracleDump(), port, rules, std::nullopt);
    CHECK_FALSE(hard.ok);
    CHECK(Find(hard, "ssr.hitX").problem.find("hard limit") != std::string::npos);
  }
  SECTION("layers the port lacks are not compared and do not fail; one of another size fails") {
    ExrFile port;
    port.layers.push_back(*OracleDump().Find("frame", "direct.R"));
    port.layers.back().part = "";  // a single-part port file
    CHECK(DiffDumps(OracleDump(), port, thresholds, std::nullopt).ok);
    port.layers.back().width = 45;
    port.layers.back().height = 67;
    const DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK_FALSE(report.ok);
    CHECK(Find(report, "direct.R").problem.find("size differs") == 0);
  }
}

// A 40x30 image whose one triangle has a vertical edge exactly through the pixel centres of column
// 10 (x = 10.5) and another edge far from them; with identity view and projection, mesh positions
// are NDC.
TEST_CASE("diff: coverage differences within rounding distance of an edge are allowed, others fail",
          "[diff][coverage]") {
  constexpr int kWidth = 40, kHeight = 30;
  Mesh mesh;
  const auto ndcX = [](double px) { return float(px / kWidth * 2.0 - 1.0); };
  mesh.positions = {{ndcX(10.5), 1.0f, 0.5f}, {ndcX(10.5), -1.0f, 0.5f}, {ndcX(39.0), -1.0f, 0.5f}};
  mesh.indices = {0, 1, 2};
  mesh.materials = {0};
  ViewProjection view;
  view.width = kWidth;
  view.height = kHeight;
  const auto layer = [&](const std::string& name, uint32_t fill) {
    return ExrLayer{"frame", name, kWidth, kHeight, true, std::vector<uint32_t>(kWidth * kHeight, fill)};
  };
  ExrFile oracle, port;
  oracle.layers = {layer("raster.triangle", 0), layer("gbuffer.word0", 7)};
  port.layers = oracle.layers;
  const CoverageGeometry geometry{mesh, view};
  const DiffThresholds thresholds = ShippedThresholds();
  // Pixel (10, 15): its centre is on the edge. Pixel (20, 5): well inside, far from every edge.
  const size_t onEdge = 15 * kWidth + 10, inside = 5 * kWidth + 20;
  port.layers[0].samples[onEdge] = 0xFFFFFFFFu;
  port.layers[1].samples[onEdge] = 0;
  DiffReport report = DiffDumps(oracle, port, thresholds, geometry);
  CHECK(report.ok);
  CHECK(Find(report, "raster.triangle").edgePixels == 1);
  CHECK(Find(report, "gbuffer.word0").edgePixels == 1);
  // Without the geometry the same difference is an error.
  CHECK_FALSE(DiffDumps(oracle, port, thresholds, std::nullopt).ok);
  port.layers[0].samples[inside] = 0xFFFFFFFFu;
  report = DiffDumps(oracle, port, thresholds, geometry);
  CHECK_FALSE(report.ok);
  CHECK(Find(report, "raster.triangle").overTolerance == 1);
  CHECK(Find(report, "raster.triangle").worstX == 20);
  // A pixel half a pixel from the edge is no rounding case either.
  port.layers[0].samples[inside] = 0;
  port.layers[0].samples[15 * kWidth + 11] = 0xFFFFFFFFu;
  CHECK_FALSE(DiffDumps(oracle, port, thresholds, geometry).ok);
}

TEST_CASE("diff: a thresholds file extends another: its own rules first, then the other's", "[diff]") {
  const test::ScratchDir scratch("diff-extends");
  test::WriteText(scratch / "base.json",
                  R"({"layers": [{"match": "direct.*", "relative": 0.5}, {"match": "hiz.*", "ulp": 4}]})");
  test::WriteText(scratch / "mine.json",
                  R"({"extends": "base.json", "layers": [{"match": "direct.R", "absolute": 2}]})");
  const DiffThresholds rules = LoadDiffThresholds(scratch / "mine.json");
  REQUIRE(rules.rules.size() == 3);
  CHECK(rules.For("direct.R").absolute == 2.0);
  CHECK(rules.For("direct.G").relative == 0.5);
  CHECK(rules.For("hiz.0:Y").ulp == 4);
  // The shipped file for conventional G-buffers extends the shipped rules.
  const DiffThresholds conventional =
      LoadDiffThresholds(test::SourceDir() / "data" / "diff_thresholds_conventional.json");
  CHECK(conventional.rules.size() > ShippedThresholds().rules.size());
  test::WriteText(scratch / "loop.json", R"({"extends": "loop.json", "layers": []})");
  CHECK_THROWS_AS(LoadDiffThresholds(scratch / "loop.json"), InputError);
  test::WriteText(scratch / "bad.json", R"({"extends": 3, "layers": []})");
  CHECK_THROWS_AS(LoadDiffThresholds(scratch / "bad.json"), InputError);
}

// The rule's distance follows the rasterizer's sub-pixel precision: an edge 0.03 px beside the
// centres of column 10 is beyond two 8-bit steps (1/128 px), within two 4-bit ones (1/8 px).
TEST_CASE("diff: the coverage distance is two steps of the port's sub-pixel grid", "[diff][coverage]") {
  constexpr int kWidth = 40, kHeight = 30;
  Mesh mesh;
  const auto ndcX = [](double px) { return float(px / kWidth * 2.0 - 1.0); };
  mesh.positions = {{ndcX(10.53), 1.0f, 0.5f}, {ndcX(10.53), -1.0f, 0.5f}, {ndcX(39.0), -1.0f, 0.5f}};
  mesh.indices = {0, 1, 2};
  mesh.materials = {0};
  ViewProjection view;
  view.width = kWidth;
  view.height = kHeight;
  ExrFile oracle, port;
  oracle.layers = {
      ExrLayer{"frame", "raster.triangle", kWidth, kHeight, true, std::vector<uint32_t>(kWidth * kHeight, 0)}};
  port.layers = oracle.layers;
  port.layers[0].samples[15 * kWidth + 10] = 0xFFFFFFFFu;
  CHECK(CoverageRounding(8) == kCoverageRounding);
  CHECK(CoverageRounding(4) == 0.125);
  CHECK_FALSE(DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, view}).ok);
  const DiffReport coarse =
      DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, view, CoverageRounding(4)});
  CHECK(coarse.ok);
  CHECK(Find(coarse, "raster.triangle").maxEdgeDistance == Approx(0.03).margin(1e-5));
}

// A triangle with a vertex behind the camera is judged by the edges of its part in front of the
// near plane (it was once not judged at all): a pixel deep inside it may not differ.
TEST_CASE("diff: pixels of a triangle clipped at the near plane are judged by its clipped edges", "[diff][coverage]") {
  constexpr int kWidth = 40, kHeight = 30;
  CameraDesc camera;
  camera.position = {0.0f, 0.0f, 0.0f};
  camera.target = {0.0f, 0.0f, -1.0f};
  camera.nearPlane = 0.1f;
  const ViewProjection view = MakePerspective(camera, kWidth, kHeight);
  Mesh mesh;
  // A floor below the eye reaching behind it: its far edge crosses the image, its near vertex is
  // behind the camera.
  mesh.positions = {{-50.0f, -1.0f, -20.0f}, {0.0f, -1.0f, 5.0f}, {50.0f, -1.0f, -20.0f}};
  mesh.indices = {0, 1, 2};
  mesh.materials = {0};
  ExrFile oracle, port;
  oracle.layers = {
      ExrLayer{"frame", "raster.triangle", kWidth, kHeight, true, std::vector<uint32_t>(kWidth * kHeight, 0)}};
  port.layers = oracle.layers;
  port.layers[0].samples[(kHeight - 2) * kWidth + kWidth / 2] = 0xFFFFFFFFu;  // deep inside, near the bottom
  const DiffReport report = DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, view});
  CHECK_FALSE(report.ok);
  CHECK(Find(report, "raster.triangle").overTolerance == 1);
}

// The shadow map has no triangle index: its texels are judged against every triangle seen from the
// light (CoverageGeometry::shadowView).
TEST_CASE("diff: shadow-map texels differing at a triangle's edge are allowed, others fail", "[diff][coverage]") {
  constexpr int kSize = 32;
  Mesh mesh;
  const auto ndc = [](double texel) { return float(texel / kSize * 2.0 - 1.0); };
  // An edge through the centres of texel column 8; a vertex far off to the right.
  mesh.positions = {{ndc(8.5), 1.0f, 0.5f}, {ndc(8.5), -1.0f, 0.5f}, {ndc(30.0), -1.0f, 0.5f}};
  mesh.indices = {0, 1, 2};
  mesh.materials = {0};
  ViewProjection image, light;
  image.width = image.height = light.width = light.height = kSize;
  ExrFile oracle, port;
  oracle.layers = {ExrLayer{"shadowmap", "depthKey", kSize, kSize, false, std::vector<uint32_t>(kSize * kSize, 0)}};
  port.layers = oracle.layers;
  const float key = 0.5f;
  std::memcpy(&port.layers[0].samples[4 * kSize + 8], &key, sizeof(key));
  CHECK_FALSE(DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, image}).ok);
  const DiffReport judged =
      DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, image, kCoverageRounding, &light});
  CHECK(judged.ok);
  CHECK(Find(judged, "shadowmap:depthKey").edgePixels == 1);
  std::memcpy(&port.layers[0].samples[4 * kSize + 20], &key, sizeof(key));  // inside the triangle
  CHECK_FALSE(
      DiffDumps(oracle, port, ShippedThresholds(), CoverageGeometry{mesh, image, kCoverageRounding, &light}).ok);
}

TEST_CASE("diff: the thresholds file", "[diff][errors]") {
  const DiffThresholds shipped = ShippedThresholds();
  CHECK(shipped.For("gbuffer.word2").exact);
  CHECK(shipped.For("gbuffer.word2").coverage);
  CHECK(shipped.For("direct.G").relative > 0.0);
  CHECK(shipped.For("hiz.4:Y").ulp > 0);
  CHECK(shipped.For("no.such.layer").exact);
  // Every float layer the oracle writes has a rule of its own.
  for (const ExrLayer& layer : OracleDump().layers) {
    const std::string id = layer.part == "frame" ? layer.name : layer.part + ":" + layer.name;
    bool ruled = false;
    for (const auto& rule : shipped.rules)
      ruled = ruled || rule.first == id || (rule.first.back() == '*' && id.rfind(rule.first.substr(0, rule.first.size() - 1), 0) == 0);
    CAPTURE(id);
    CHECK(ruled);
  }
  test::ScratchDir dir("diff-thresholds");
  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "t.json") << text;
    return dir / "t.json";
  };
  const auto error = [&](const std::string& text) {
    try {
      LoadDiffThresholds(write(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(error("{\"layers\": [{\"match\": \"x\", \"ulps\": 3}]}").find("unknown key 'ulps'") != std::string::npos);
  CHECK(error("{\"layers\": [{\"match\": \"x\", \"ulp\": -1}]}").find("layers[0].ulp: must be a number >= 0") !=
        std::string::npos);
  CHECK(error("{\"layers\": [{\"ulp\": 1}]}").find("string \"match\"") != std::string::npos);
  CHECK(error("{\"layers\": [").find("not valid JSON") != std::string::npos);
  CHECK(error("[]").find("t.json: must be an object with an array \"layers\"") != std::string::npos);
}

TEST_CASE("diff: a thresholds file's errors name its line", "[diff][errors]") {
  test::ScratchDir dir("diff-thresholds-lines");
  const auto error = [&](const std::string& text) {
    std::ofstream(dir / "t.json") << text;
    const std::string message = test::InputErrorOf([&] { LoadDiffThresholds(dir / "t.json"); });
    CHECK(message.find('\n') == std::string::npos);  // one line
    return message;
  };
  // A syntax error: the line of the offending byte, not nlohmann's own prefix.
  const std::string syntax = error("{\n  \"layers\": [\n    {\"match\": \"x\" \"ulp\": 3}\n  ]\n}\n");
  CHECK(syntax.find("t.json:3: not valid JSON: syntax error") != std::string::npos);
  CHECK(syntax.find("json.exception") == std::string::npos);
  CHECK(error("{\"layers\": [\n\n").find("t.json:3: not valid JSON") != std::string::npos);
  // A bad rule: the line its object starts on, whatever the strings before it hold.
  const std::string rules =
      "{\n  \"about\": \"braces { [ and \\\"quotes\\\" in a string\",\n  \"layers\": [\n"
      "    {\"match\": \"a\", \"ulp\": 1},\n    {\"match\": \"b\",\n     \"ulps\": 1}\n  ]\n}\n";
  CHECK(error(rules).find("t.json:5: layers[1]: unknown key 'ulps'") != std::string::npos);
  CHECK(error("{\"layers\": [{\"match\": \"a\"},\n 7]}").find("t.json:2: layers[1]: must be an object") !=
        std::string::npos);
  CHECK(error("{\"layers\": [{\"match\": \"a\", \"percent\": -1}]}").find("t.json:1: layers[0].percent") !=
        std::string::npos);
}

TEST_CASE("diff: a layer close to its tolerance", "[diff]") {
  const DiffThresholds thresholds = ShippedThresholds();
  SECTION("a sample over half of its most lenient bound: direct light 0.075% off of 0.1% relative") {
    ExrFile port = OracleDump();
    ExrLayer& direct = LayerOf(port, "frame", "direct.G");
    size_t i = 0;
    while (direct.Float(i) < 0.01f) ++i;  // a lit pixel, where 1e-3 relative is far more than 16 ULP
    const float oracle = direct.Float(i);
    const auto set = [&](float value) { std::memcpy(&direct.samples[i], &value, 4); };
    set(oracle * (1.0f + 0.75e-3f));
    DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK(report.ok);
    CHECK(Find(report, "direct.G").close);
    CHECK(Find(report, "direct.G").toleranceUsed == Approx(0.75).epsilon(0.01));
    set(oracle * (1.0f + 0.25e-3f));
    report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK_FALSE(Find(report, "direct.G").close);
    CHECK(Find(report, "direct.G").toleranceUsed == Approx(0.25).epsilon(0.01));
    CHECK_FALSE(Find(report, "direct.R").close);
  }
  SECTION("over half of the share allowed beyond it: 0.15% of hits of 0.2%") {
    ExrFile port = OracleDump();
    // 3015 samples: 4 are 0.13%, 5 are 0.17%, 7 are 0.23%.
    for (size_t i = 0; i < 5; ++i) AddToFloat(LayerOf(port, "frame", "ssr.hitY"), i * 401, 3.0f);
    DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK(Find(report, "ssr.hitY").ok);
    CHECK(Find(report, "ssr.hitY").close);
    for (size_t i = 5; i < 7; ++i) AddToFloat(LayerOf(port, "frame", "ssr.hitY"), i * 401, 3.0f);
    report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
    CHECK_FALSE(Find(report, "ssr.hitY").ok);
    CHECK_FALSE(Find(report, "ssr.hitY").close);  // failing, not close
  }
}

TEST_CASE("diff: ULPs are not measured between two values within the absolute tolerance of zero", "[diff]") {
  const DiffThresholds thresholds = ShippedThresholds();
  ExrFile port = OracleDump();
  ExrLayer& confidence = LayerOf(port, "frame", "ssr.confidence");  // 1e-4 absolute
  size_t zero = 0;
  while (confidence.samples[zero] != 0) ++zero;
  const float tiny = 1e-6f;  // a billion ULP from 0, a hundredth of the tolerance
  std::memcpy(&confidence.samples[zero], &tiny, 4);
  DiffReport report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
  CHECK(Find(report, "ssr.confidence").ok);
  CHECK(Find(report, "ssr.confidence").maxAbsolute > 0.0);
  CHECK_FALSE(Find(report, "ssr.confidence").ulpMeasured);
  CHECK(Find(report, "ssr.hitX").ulpMeasured);             // equal: 0 ULP
  CHECK_FALSE(Find(report, "gbuffer.word0").ulpMeasured);  // integers
  // A difference away from zero is measured as before.
  size_t lit = 0;
  while (confidence.Float(lit) < 0.5f) ++lit;
  confidence.samples[lit] += 3;
  report = DiffDumps(OracleDump(), port, thresholds, std::nullopt);
  CHECK(Find(report, "ssr.confidence").ulpMeasured);
  CHECK(Find(report, "ssr.confidence").maxUlp == 3);
  CHECK(nlohmann::json::parse(DiffReportJson(report))["layers"].size() == report.layers.size());
}

TEST_CASE("diff: a layer of another type is counted apart and fails", "[diff]") {
  ExrFile port = OracleDump();
  LayerOf(port, "frame", "display.G").isUint = false;
  const DiffReport report = DiffDumps(OracleDump(), port, ShippedThresholds(), std::nullopt);
  CHECK_FALSE(report.ok);
  const LayerDiff& display = Find(report, "display.G");
  CHECK(display.typeDiffers);
  CHECK_FALSE(display.compared);
  CHECK(display.problem == "type differs: float, the oracle's uint32");
  CHECK_FALSE(Find(report, "display.R").typeDiffers);
}

TEST_CASE("diff: the report is the same at 1 and 2 threads", "[diff]") {
  ExrFile port = OracleDump();
  for (size_t i = 0; i < 3000; i += 7) AddToFloat(LayerOf(port, "frame", "result.R"), i, 1e-3f * float(i % 13));
  LayerOf(port, "frame", "raster.triangle").samples[1234] ^= 5u;
  AddToFloat(LayerOf(port, "pyramid.2", "B"), 11, 0.25f);
  std::vector<std::string> reports;
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    reports.push_back(DiffReportJson(DiffDumps(OracleDump(), port, ShippedThresholds(), std::nullopt)));
  }
  CHECK(reports[0] == reports[1]);
  CHECK(reports[0].find("\"rmse\"") != std::string::npos);
}

TEST_CASE("diff: the oracle's layers read are those the port holds and the triangle index", "[diff]") {
  ExrFile port;
  port.layers.push_back(*OracleDump().Find("frame", "direct.R"));
  port.layers.back().part = "";  // a single-part port file
  port.layers.push_back(*OracleDump().Find("hiz.2", "Y"));
  const ExrChannelFilter read = OracleLayersToRead(port);
  CHECK(read("frame", "direct.R"));
  CHECK(read("hiz.2", "Y"));
  CHECK(read("frame", "raster.triangle"));
  CHECK_FALSE(read("frame", "direct.G"));
  CHECK_FALSE(read("hiz.3", "Y"));
  // What it leaves out the diff does not read: those layers are listed, not compared.
  ExrFile oracle = OracleDump();
  for (ExrLayer& layer : oracle.layers)
    if (!read(layer.part, layer.name)) layer.samples.clear();
  const DiffReport report = DiffDumps(oracle, port, ShippedThresholds(), std::nullopt);
  CHECK(report.ok);
  size_t compared = 0;
  for (const LayerDiff& layer : report.layers) compared += layer.compared ? 1 : 0;
  CHECK(compared == 2);
  CHECK(Find(report, "direct.G").presence == LayerPresence::kOracleOnly);
}

TEST_CASE("diff: the JSON report", "[diff]") {
  ExrFile port = OracleDump();
  AddToFloat(LayerOf(port, "frame", "shadow.visibility"), 0, 0.5f);
  const nlohmann::json json =
      nlohmann::json::parse(DiffReportJson(DiffDumps(OracleDump(), port, ShippedThresholds(), std::nullopt)));
  CHECK(json["ok"] == false);
  CHECK(json["firstFailingPass"] == "shadow_filter");
  bool found = false;
  for (const auto& layer : json["layers"]) {
    if (layer["id"] != "shadow.visibility") continue;
    found = true;
    CHECK(layer["ok"] == false);
    CHECK(layer["overTolerance"] == 1);
    CHECK(layer["worst"] == nlohmann::json::array({0, 0}));
  }
  CHECK(found);
}

}  // namespace
}  // namespace ssgi
