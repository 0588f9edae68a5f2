// `ssgi reference`'s transport options (cli/reference_command.cpp): the full transport by default,
// the paper transport on request, refusals of knobs a transport does not have, and the cost line.
#include <catch2/catch.hpp>
#include <string>

#include "tests/test_support.h"

namespace ssgi {
namespace {

using test::CommandResult;
using test::DefaultSceneArg;
using test::Quote;
using test::ReadStoredImage;
using test::RunCli;
using test::ScratchDir;
using test::StoredImage;

TEST_CASE("reference: --transport full (default) and paper, --bounces, --pixel-centre", "[cli][reference]") {
  ScratchDir dir("cli-reference-transport");
  const std::string common = "reference " + DefaultSceneArg() + " --size 24x16 --spp 2 ";
  const CommandResult full = RunCli(common + "-o " + Quote(dir / "full.exr"));
  CAPTURE(full.output);
  REQUIRE(full.exitCode == 0);
  CHECK_THAT(full.output, Catch::Contains("full transport"));
  CHECK_THAT(full.output, Catch::Contains("us per sample per pixel"));
  CHECK_THAT(full.output, Catch::Contains("noise: standard error"));
  const CommandResult paper = RunCli(common + "--transport paper -o " + Quote(dir / "paper.exr"));
  CAPTURE(paper.output);
  REQUIRE(paper.exitCode == 0);
  CHECK_THAT(paper.output, Catch::Contains("paper transport"));
  const CommandResult centre =
      RunCli(common + "--bounces 0 --pixel-centre --threads 1 -o " + Quote(dir / "centre.exr"));
  CAPTURE(centre.output);
  REQUIRE(centre.exitCode == 0);
  // Same layers in every transport, so `ssgi compare --layer` pairs any of them with a dump.
  for (const char* file : {"full.exr", "paper.exr", "centre.exr"}) {
    const StoredImage image = ReadStoredImage(dir / file);
    CHECK(image.channels == 14);  // R G B, result.*, direct.*, indirect.* (3 each), shadow.visibility, depth
  }
  // The two transports differ (the full one's environment light and interreflections).
  CHECK(ReadStoredImage(dir / "full.exr").bytes != ReadStoredImage(dir / "paper.exr").bytes);

  // Knobs the paper transport does not have are refused, not ignored; bad values name the option.
  for (const auto& [arguments, message] :
       {std::pair<std::string, std::string>{"--transport paper --bounces 3", "--bounces"},
        {"--transport paper --pixel-centre", "--pixel-centre"},
        {"--transport path", "--transport"},
        {"--bounces -1", "--bounces"}}) {
    const CommandResult refused = RunCli(common + arguments + " -o " + Quote(dir / "refused.exr"));
    CAPTURE(arguments, refused.output);
    CHECK(refused.exitCode == 2);
    CHECK_THAT(refused.output, Catch::Contains(message));
  }
}

}  // namespace
}  // namespace ssgi
