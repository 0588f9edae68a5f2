// The ssgi command line. The only place an error becomes a message and an exit code (docs/design.md §12).
// Every error is one printable line "ssgi: error: ..." on stderr; the exit code says whose it is:
// 0 success, 1 bad input (scene, model, texture, output path, option value), 2 a command line that
// does not parse or asks for the impossible (unknown command or option, malformed value, passes in the
// wrong order), 3 an internal failure. Each command is a file of its own (cli/commands.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cli/command_line_errors.h"
#include "cli/commands.h"
#include "cli/version.h"
#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"ssgi: a CPU reference renderer for screen-space global illumination (Yang & Saito): deferred "
               "shading on a packed 128-bit G-buffer, SSABSS soft shadows and Hi-Z cone-traced screen-space "
               "reflections."};
  app.set_version_flag("--version", std::string("ssgi ") + SSGI_VERSION + " (commit " + SSGI_COMMIT + ")");
  app.require_subcommand(1);
  const ssgi::cli::Command commands[] = {ssgi::cli::AddRenderCommand(app),  ssgi::cli::AddRenderViewsCommand(app),
                                         ssgi::cli::AddFiguresCommand(app), ssgi::cli::AddReferenceCommand(app),
                                         ssgi::cli::AddCompareCommand(app), ssgi::cli::AddPassesCommand(app),
                                         ssgi::cli::AddDiffCommand(app)};
  const auto fail = [](const char* kind, const char* what, int code) {
    std::fprintf(stderr, "ssgi: %s: %s\n", kind, ssgi::cli::Printable(what).c_str());
    return code;
  };
  const std::vector<std::string> joined = ssgi::cli::JoinNegativeValues(app, argc, argv);
  std::vector<const char*> args = {argv[0]};
  for (const std::string& word : joined) args.push_back(word.c_str());
  try {
    app.parse(int(args.size()), args.data());
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail("error", ssgi::cli::DescribeParseError(app, e, int(args.size()), args.data()).c_str(), 2);
  }
  try {
    for (const ssgi::cli::Command& command : commands)
      if (*command.app) return command.run();
  } catch (const ssgi::cli::UsageError& e) {
    return fail("error", e.what(), 2);
  } catch (const ssgi::InputError& e) {
    return fail("error", e.what(), 1);
  } catch (const std::bad_alloc&) {
    return fail("error", "out of memory: give a smaller size or --max-memory below what the machine has", 1);
  } catch (const std::exception& e) {
    return fail("internal error", e.what(), 3);
  }
  return 0;
}
