// The commands of `ssgi`, one file each (cli/<command>_command.cpp): each adds its subcommand and
// options to the application and returns what runs it.
#pragma once

#include <stdexcept>
#include <string>

#include "cli/common.h"

namespace ssgi::cli {

Command AddRenderCommand(CLI::App& app);
Command AddRenderViewsCommand(CLI::App& app);
Command AddFiguresCommand(CLI::App& app);
Command AddReferenceCommand(CLI::App& app);
Command AddCompareCommand(CLI::App& app);
Command AddPassesCommand(CLI::App& app);
Command AddDiffCommand(CLI::App& app);

// A command line that parses but asks for something impossible (`passes --to` before `--from`):
// exit code 2, as a command line that does not parse.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace ssgi::cli
