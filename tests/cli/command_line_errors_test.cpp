// Command-line errors: one style ("ssgi: error: ..." on one printable line) for the parser's errors
// and the program's own, the word that was not understood named, and the near miss suggested.
#include <algorithm>

#include <catch2/catch.hpp>

#include "cli/command_line_errors.h"
#include "tests/test_support.h"

namespace ssgi::test {
namespace {

// The whole output is one line starting with the common prefix.
void CheckOneErrorLine(const CommandResult& r) {
  CAPTURE(r.output);
  CHECK(r.output.rfind("ssgi: error: ", 0) == 0);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
}

TEST_CASE("NearestWord suggests a typo's word and nothing for another word", "[cli][errors]") {
  const std::vector<std::string> commands = {"render", "figures", "reference", "compare"};
  CHECK(cli::NearestWord("rendr", commands) == "render");
  CHECK(cli::NearestWord("redner", commands) == "render");  // a swap of neighbours is one edit
  CHECK(cli::NearestWord("comprae", commands) == "compare");
  CHECK(cli::NearestWord("figure", commands) == "figures");
  CHECK(cli::NearestWord("draw", commands).empty());
  CHECK(cli::NearestWord("x", commands).empty());
  CHECK(cli::NearestWord("--stast", {"--stats", "--size", "--threads"}) == "--stats");
}

TEST_CASE("Printable escapes control bytes and malformed UTF-8, keeps text and UTF-8", "[cli][errors]") {
  CHECK(cli::Printable("plain text: 1.5") == "plain text: 1.5");
  CHECK(cli::Printable("v 0 \x1d 1") == "v 0 \\x1D 1");
  CHECK(cli::Printable("\x1b[31mred") == "\\x1B[31mred");
  CHECK(cli::Printable("two\nlines\ttab") == "two\\x0Alines\\x09tab");
  CHECK(cli::Printable("caf\xc3\xa9 \xe2\x82\xac") == "caf\xc3\xa9 \xe2\x82\xac");  // é and € pass
  CHECK(cli::Printable("\xc2\x9b") == "\\xC2\\x9B");                              // C1 CSI
  CHECK(cli::Printable("\xc3") == "\\xC3");                                       // cut short
  CHECK(cli::Printable("\xc0\xaf") == "\\xC0\\xAF");                              // overlong '/'
  CHECK(cli::Printable("\xed\xa0\x80") == "\\xED\\xA0\\x80");                     // a surrogate
  CHECK(cli::Printable(std::string("a\0b", 3)) == "a\\x00b");
}

TEST_CASE("ssgi: unknown commands and options are named, with the near miss", "[cli][errors]") {
  const CommandResult typo = RunCli("rendr");
  CHECK(typo.exitCode == 2);
  CheckOneErrorLine(typo);
  CHECK_THAT(typo.output, Catch::Contains("unknown command 'rendr' (did you mean 'render'?)"));

  const CommandResult unrelated = RunCli("draw scene.json");
  CHECK(unrelated.exitCode == 2);
  CheckOneErrorLine(unrelated);
  CHECK_THAT(unrelated.output,
             Catch::Contains("unknown command 'draw'") && Catch::Contains("render, render-views, figures"));
  CHECK(unrelated.output.find("did you mean") == std::string::npos);

  const CommandResult none = RunCli("");
  CHECK(none.exitCode == 2);
  CheckOneErrorLine(none);
  CHECK_THAT(none.output, Catch::Contains("a command is required: render"));

  const CommandResult option = RunCli("render --stast --size 8x8");
  CHECK(option.exitCode == 2);
  CheckOneErrorLine(option);
  CHECK_THAT(option.output,
             Catch::Contains("unknown option '--stast' for 'ssgi render' (did you mean '--stats'?)"));
  const CommandResult withValue = RunCli("compare a.exr b.exr --layr=direct");
  CHECK(withValue.exitCode == 2);
  CHECK_THAT(withValue.output, Catch::Contains("unknown option '--layr'") && Catch::Contains("'--layer'"));

  // A negative number is a value, not an option; the bad value is what gets reported.
  const CommandResult value = RunCli("render --exposure -1 --quality hgh");
  CHECK(value.exitCode == 2);
  CheckOneErrorLine(value);
  CHECK_THAT(value.output, Catch::Contains("--quality of 'ssgi render': 'hgh' is not one of low, medium, high, "
                                           "ultra (did you mean 'high'?)"));

  const CommandResult missing = RunCli("compare only-one.exr");
  CHECK(missing.exitCode == 2);
  CheckOneErrorLine(missing);
  CHECK_THAT(missing.output, Catch::Contains("'ssgi compare': reference is required"));

  CHECK(RunCli("--help").exitCode == 0);
  CHECK(RunCli("render --help").exitCode == 0);
}

TEST_CASE("ssgi: bytes of the input echoed in an error are escaped", "[cli][errors]") {
  ScratchDir dir("cli-escaped");
  WriteText(dir / "control.obj", "v 0 0 0\nv 1 \x1d 0\nv 0 1 0\nf 1 2 3\n");
  const CommandResult r = RunCli("render " + Quote(dir / "control.obj") + " -o " + Quote(dir / "out.png"));
  CHECK(r.exitCode == 1);
  CheckOneErrorLine(r);
  CHECK_THAT(r.output, Catch::Contains("control.obj:2:"));
  CHECK(r.output.find('\x1d') == std::string::npos);
  CHECK(!std::filesystem::exists(dir / "out.png"));
}

}  // namespace
}  // namespace ssgi::test
