// End-to-end tests of the oracle's commands for GPU ports: `ssgi render --dump`, `ssgi passes` and
// `ssgi diff` (docs/user-guide.md "Checking a GPU port"): a port's buffers checked pass by pass, exit codes, the
// JSON report and heat maps, and one-line errors for unusable input.
#include <cstring>
#include <fstream>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "tests/test_support.h"

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;

// The default scene at 64x48 dumped into dir/oracle.exr.
fs::path DumpOracle(const ScratchDir& dir) {
  const CommandResult result = RunCli("render " + Quote(SourceDir() / "data" / "default.json") + " --size 64x48 -o " +
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

TEST_CASE("passes and diff: unusable input is one line and a non-zero exit", "[cli][oracle][errors]") {
  ScratchDir dir("cli-oracle-errors");
  const fs::path oracle = DumpOracle(dir);
  WriteText(dir / "text.exr", "not an image");
  WriteText(dir / "bad.json", "{\"layers\": [{\"match\": \"x\", \"ulps\": 1}]}");
  CheckCliErrors({
      {"passes " + Quote(oracle) + " --from hzi -o " + Quote(dir / "o.exr"), "'hzi' is not a pass", 1},
      {"passes " + Quote(oracle) + " --from composite --to hiz -o " + Quote(dir / "o.exr"), "comes before", 2},
      {"passes " + Quote(dir / "text.exr") + " -o " + Quote(dir / "o.exr"), "text.exr", 1},
      {"passes " + Quote(oracle) + " -o " + Quote(dir / "o.png"), "EXR", 1},
      {"passes " + Quote(dir / "oracle.png") + " --from hiz -o " + Quote(dir / "o.exr"), "not an EXR", 1},
      {"diff " + Quote(oracle) + " " + Quote(dir / "missing.exr"), "missing.exr", 2},
      {"diff " + Quote(oracle) + " " + Quote(dir / "text.exr"), "text.exr", 2},
      {"diff " + Quote(oracle) + " " + Quote(oracle) + " --thresholds " + Quote(dir / "bad.json"), "unknown key 'ulps'",
       2},
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
