// End-to-end tests of the oracle's commands for GPU ports: `ssgi render --dump`, `ssgi passes` and
// `ssgi diff` (docs/user-guide.md "Checking a GPU port"): a port's buffers checked pass by pass, exit codes, the
// JSON report and heat maps, and one-line errors for unusable input.
#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/image_io.h"
#include "tests/test_support.h"

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;

// The default scene at 64x48 dumped into dir/oracle.exr.
// With the diffuse bounce on (the default scene's frame leaves it to the interreflection volume), so
// that every pass is in the dump.
fs::path DumpOracle(const ScratchDir& dir) {
  const CommandResult result =
      RunCli("render " + Quote(SourceDir() / "data" / "default.json") + " --size 64x48 --bounce on -o " +
             Quote(dir / "oracle.png") + " --dump " + Quote(dir / "oracle.exr"));
  CAPTURE(result.output);
  REQUIRE(result.exitCode == 0);
  return dir / "oracle.exr";
}

TEST_CASE("passes and diff: the oracle's passes rerun on its own buffers pass, and a broken pass is named",
          "[cli][oracle]") {
  ScratchDir dir("cli-oracle");
  const fs::path oracle = DumpOracle(dir);
  // The dump names its scene, so `passes` needs no --scene.
  const CommandResult rerun = RunCli("passes " + Quote(oracle) + " --from hiz -o " + Quote(dir / "port.exr"));
  CAPTURE(rerun.output);
  REQUIRE(rerun.exitCode == 0);
  const CommandResult same = RunCli("diff " + Quote(oracle) + " " + Quote(dir / "port.exr") + " --json " +
                                    Quote(dir / "report.json"));
  CAPTURE(same.output);
  CHECK(same.exitCode == 0);
  CHECK(same.output.find("verdict: PASS") != std::string::npos);
  std::ifstream reportFile(dir / "report.json");
  CHECK(nlohmann::json::parse(reportFile)["ok"] == true);

  // A "port" whose cone trace is off by a lot in a few pixels: the cone trace is the first to fail.
  ExrFile port = ReadExrFile(dir / "port.exr");
  for (ExrLayer& layer : port.layers) {
    if (layer.name != "ssr.reflected.G") continue;
    for (size_t i = 0; i < layer.samples.size(); i += 7) {
      const float wrong = 9.0f;
      std::memcpy(&layer.samples[i], &wrong, 4);
    }
  }
  WriteExrFile(dir / "broken.exr", port);
  const CommandResult broken = RunCli("diff " + Quote(oracle) + " " + Quote(dir / "broken.exr") + " --json " +
                                      Quote(dir / "report.json") + " --heatmaps " + Quote(dir / "heat"));
  CAPTURE(broken.output);
  CHECK(broken.exitCode == 1);
  CHECK(broken.output.find("verdict: FAIL, first failing pass: ssr_cone") != std::string::npos);
  CHECK(fs::exists(dir / "heat" / "ssr.reflected.G.png"));
  std::ifstream brokenReport(dir / "report.json");
  CHECK(nlohmann::json::parse(brokenReport)["firstFailingPass"] == "ssr_cone");
}

// The lines of `output` that start with "  " + `layer` + " ": the layer's row of the table.
size_t RowsOf(const std::string& output, const std::string& layer) {
  size_t rows = 0;
  for (size_t at = output.find("\n  " + layer + " "); at != std::string::npos;
       at = output.find("\n  " + layer + " ", at + 1))
    ++rows;
  return rows;
}

TEST_CASE("diff: rows only for layers that fail or are close, --verbose for all, and the counts a line each",
          "[cli][oracle]") {
  ScratchDir dir("cli-diff-output");
  const fs::path oracle = DumpOracle(dir);
  ExrFile port = ReadExrFile(oracle);
  const auto layer = [&](const std::string& part, const std::string& name) -> ExrLayer& {
    for (ExrLayer& l : port.layers)
      if (l.part == part && l.name == name) return l;
    FAIL("no layer " << name);
    return port.layers.front();
  };
  const auto setFloat = [](ExrLayer& l, size_t i, float value) { std::memcpy(&l.samples[i], &value, 4); };
  // Fails: the cone trace, far off in 20 pixels of 3072 (0.5% allowed).
  for (size_t i = 0; i < 20; ++i) setFloat(layer("frame", "ssr.reflected.G"), i * 101, 9.0f);
  // Close: the direct light 0.075% off in a lit pixel (0.1% relative allowed).
  ExrLayer& direct = layer("frame", "direct.B");
  size_t lit = 0;
  while (direct.Float(lit) < 0.01f) ++lit;
  setFloat(direct, lit, direct.Float(lit) * (1.0f + 0.75e-3f));
  // Within tolerance, near zero: a confidence of 0 read as 1e-6 (1e-4 allowed): no ULPs.
  ExrLayer& confidence = layer("frame", "ssr.confidence");
  size_t zero = 0;
  while (confidence.samples[zero] != 0) ++zero;
  setFloat(confidence, zero, 1e-6f);
  // Another type: the display's green as float. Not in the oracle's: a layer of the port's own.
  // Not in the port's: the Hi-Z and the colour pyramid.
  layer("frame", "display.G").isUint = false;
  port.layers.push_back(ExrLayer{"frame", "my.extra", 64, 48, false, std::vector<uint32_t>(64 * 48, 0)});
  std::erase_if(port.layers,
                [](const ExrLayer& l) { return l.part.rfind("hiz.", 0) == 0 || l.part.rfind("pyramid.", 0) == 0; });
  WriteExrFile(dir / "port.exr", port);

  const CommandResult terse = RunCli("diff " + Quote(oracle) + " " + Quote(dir / "port.exr"));
  CAPTURE(terse.output);
  CHECK(terse.exitCode == 1);
  CHECK(RowsOf(terse.output, "ssr.reflected.G") == 1);
  CHECK(RowsOf(terse.output, "direct.B") == 1);
  CHECK(RowsOf(terse.output, "display.G") == 1);
  CHECK(terse.output.find("close: a sample uses 75") != std::string::npos);
  CHECK(terse.output.find("% of the tolerance\n") != std::string::npos);
  CHECK(terse.output.find("FAIL: type differs: float, the oracle's uint32") != std::string::npos);
  for (const char* quiet : {"gbuffer.word0", "direct.R", "ssr.confidence", "hiz.0:Y", "my.extra", "result.R"})
    CHECK(RowsOf(terse.output, quiet) == 0);
  CHECK(terse.output.find("not compared:") == std::string::npos);
  // Counts agree with the rows: the oracle's 98 layers at 64x48 less the Hi-Z's and pyramid's 7 + 21,
  // less display.G.
  CHECK(terse.output.find("\n79 layers compared: 77 ok, 1 close, 1 FAIL (--verbose lists the ok ones)\n") !=
        std::string::npos);
  CHECK(terse.output.find("\n1 layer not comparable, failing: 1 type mismatch (uint32 against float)\n") !=
        std::string::npos);
  CHECK(terse.output.find("\n28 layers only in the oracle's file (passes hiz, color_pyramid), 1 only in the port's: "
                          "my.extra; not compared\n") != std::string::npos);
  CHECK(terse.output.find("verdict: FAIL, first failing pass: ssr_cone") != std::string::npos);

  const CommandResult verbose = RunCli("diff --verbose " + Quote(oracle) + " " + Quote(dir / "port.exr"));
  CAPTURE(verbose.output);
  CHECK(verbose.exitCode == 1);
  for (const char* every : {"gbuffer.word0", "direct.R", "ssr.confidence", "hiz.0:Y", "my.extra", "result.R"})
    CHECK(RowsOf(verbose.output, every) == 1);
  // The ULP column of a layer whose differences all lie within its absolute tolerance of zero.
  const size_t row = verbose.output.find("\n  ssr.confidence ");
  REQUIRE(row != std::string::npos);
  std::istringstream columns(verbose.output.substr(row, verbose.output.find('\n', row + 1) - row));
  std::string id, pass, maxAbs, maxUlp;
  columns >> id >> pass >> maxAbs >> maxUlp;
  CHECK(maxAbs == "1e-06");
  CHECK(maxUlp == "-");
  CHECK(verbose.output.find("\n79 layers compared: 77 ok, 1 close, 1 FAIL\n") != std::string::npos);
  CHECK(verbose.output.find("not compared: not in the port's file") != std::string::npos);

  // The same report at any thread count.
  CHECK(RunCli("diff --threads 1 " + Quote(oracle) + " " + Quote(dir / "port.exr")).output == terse.output);
  CHECK(RunCli("diff --threads 2 " + Quote(oracle) + " " + Quote(dir / "port.exr")).output == terse.output);
}

TEST_CASE("passes: from any pass, reading only the layers of the passes before it, gives the oracle's bytes",
          "[cli][oracle]") {
  ScratchDir dir("cli-passes-from");
  const fs::path oracle = DumpOracle(dir);
  WriteText(dir / "exact.json", "{\"layers\": []}");
  // A pass of each part's first reader: the shadow map's, the image's, the Hi-Z's and the pyramid's.
  for (const char* from : {"shadow_map", "direct_light", "ssr_trace", "ssr_cone"}) {
    CAPTURE(from);
    const CommandResult rerun =
        RunCli("passes " + Quote(oracle) + " --from " + from + " -o " + Quote(dir / "rerun.exr"));
    CAPTURE(rerun.output);
    REQUIRE(rerun.exitCode == 0);
    const CommandResult same =
        RunCli("diff " + Quote(oracle) + " " + Quote(dir / "rerun.exr") + " --thresholds " + Quote(dir / "exact.json"));
    CAPTURE(same.output);
    CHECK(same.exitCode == 0);
    CHECK(same.output.find("verdict: PASS") != std::string::npos);
  }
}

TEST_CASE("passes and diff: unusable input is one line and a non-zero exit", "[cli][oracle][errors]") {
  ScratchDir dir("cli-oracle-errors");
  const fs::path oracle = DumpOracle(dir);
  WriteText(dir / "text.exr", "not an image");
  WriteText(dir / "bad.json", "{\"layers\": [{\"match\": \"x\", \"ulps\": 1}]}");
  WriteText(dir / "broken.json", "{\n  \"layers\": [\n    {\"match\": \"x\",}\n  ]\n}\n");
  CheckCliErrors({
      {"passes " + Quote(oracle) + " --from hzi -o " + Quote(dir / "o.exr"), "'hzi' is not a pass", 1},
      {"passes " + Quote(oracle) + " --from composite --to hiz -o " + Quote(dir / "o.exr"), "comes before", 2},
      {"passes " + Quote(dir / "text.exr") + " -o " + Quote(dir / "o.exr"), "text.exr", 1},
      {"passes " + Quote(oracle) + " -o " + Quote(dir / "o.png"), "EXR", 1},
      {"passes " + Quote(dir / "oracle.png") + " --from hiz -o " + Quote(dir / "o.exr"), "not an EXR", 1},
      {"diff " + Quote(oracle) + " " + Quote(dir / "missing.exr"), "missing.exr", 2},
      {"diff " + Quote(oracle) + " " + Quote(dir / "text.exr"), "text.exr", 2},
      {"diff " + Quote(oracle) + " " + Quote(oracle) + " --thresholds " + Quote(dir / "bad.json"),
       "bad.json:1: layers[0]: unknown key 'ulps'", 2},
      {"diff " + Quote(oracle) + " " + Quote(oracle) + " --thresholds " + Quote(dir / "broken.json"),
       "broken.json:3: not valid JSON: syntax error", 2},
      {"diff " + Quote(oracle), "port", 2},
  });
  CHECK_FALSE(fs::exists(dir / "o.exr"));
  // A port's dump that lacks a buffer the pass to run reads.
  ExrFile partial = ReadExrFile(oracle);
  partial.layers.erase(std::remove_if(partial.layers.begin(), partial.layers.end(),
                                      [](const ExrLayer& l) { return l.part.rfind("pyramid.", 0) == 0; }),
                       partial.layers.end());
  WriteExrFile(dir / "partial.exr", partial);
  const CommandResult missing = RunCli("passes " + Quote(dir / "partial.exr") + " --from ssr_cone -o " + Quote(dir / "o.exr"));
  CAPTURE(missing.output);
  CHECK(missing.exitCode == 1);
  CHECK(missing.output.find("layer 'R' of part 'pyramid.0': missing") != std::string::npos);
}

}  // namespace
}  // namespace ssgi::test
