// The accuracy/time sweep (bench/sweep.cpp) end to end: against a small `ssgi reference`, its CSV
// has a row per requested setting with finite errors, the per-pass error columns filled where the
// pass ran, and resolution rows compared at the reference's size; a reference of the wrong size is
// a clear error.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/test_support.h"

namespace ssgi::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

TEST_CASE("sweep: presets and resolution rows against a reference, as CSV", "[bench][sweep]") {
#ifndef SSGI_SWEEP_PATH
  WARN("skipped: bench/ is not built (SSGI_BUILD_BENCH off)");
#else
  ScratchDir dir("sweep");
  const fs::path reference = dir / "ref.exr";
  const fs::path csv = dir / "sweep.csv";
  REQUIRE(RunCli("reference --size 64x48 --spp 4 -o " + Quote(reference)).exitCode == 0);
  const CommandResult run = RunProgram(SSGI_SWEEP_PATH, "--reference " + Quote(reference) +
                                                            " --size 64x48 --repeats 2 --knobs preset,resolution -o " +
                                                            Quote(csv));
  CAPTURE(run.output);
  REQUIRE(run.exitCode == 0);

  std::ifstream in(csv);
  std::string line;
  REQUIRE(std::getline(in, line));
  const std::vector<std::string> header = SplitCsvLine(line);
  auto column = [&](const std::string& name) {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    FAIL("no column " << name);
    return size_t(0);
  };
  const size_t knob = column("knob"), value = column("value"), frameMs = column("frame_ms");
  const size_t rmseDisplay = column("rmse_display"), visibility = column("rmse_visibility");
  const size_t indirect = column("rmse_display_indirect"), ssrMs = column("ms ssr trace");
  std::vector<std::string> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = SplitCsvLine(line);
    REQUIRE(f.size() == header.size());
    CAPTURE(line);
    rows.push_back(f[knob] + "=" + f[value]);
    CHECK(std::stod(f[frameMs]) > 0.0);
    CHECK(std::stod(f[ssrMs]) > 0.0);  // the default scene reflects: its SSR time is measured
    const double error = std::stod(f[rmseDisplay]);
    CHECK(std::isfinite(error));
    CHECK(error > 0.0);  // a screen-space frame never equals the traced one
    CHECK(error < 0.2);
    CHECK(std::stod(f[visibility]) < 0.5);  // filled: the default scene casts shadows
    CHECK(std::stod(f[indirect]) < 0.5);    // filled: and reflects
  }
  CHECK(rows == std::vector<std::string>{"preset=low", "preset=medium", "preset=high", "preset=ultra",
                                         "resolution=50%", "resolution=75%"});

  const CommandResult wrongSize =
      RunProgram(SSGI_SWEEP_PATH, "--reference " + Quote(reference) + " --size 32x24 -o " + Quote(dir / "x.csv"));
  CHECK(wrongSize.exitCode == 1);
  CHECK(wrongSize.output.find("ref.exr") != std::string::npos);
  CHECK(wrongSize.output.find("64x48") != std::string::npos);
  const CommandResult typo = RunProgram(SSGI_SWEEP_PATH, "--reference " + Quote(reference) +
                                                             " --size 64x48 --knobs presets -o " + Quote(dir / "y.csv"));
  CHECK(typo.exitCode == 1);
  CHECK(typo.output.find("presets") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.csv"));
  CHECK_FALSE(fs::exists(dir / "y.csv"));
#endif
}

}  // namespace
}  // namespace ssgi::test
