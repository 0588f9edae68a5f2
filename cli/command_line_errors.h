// Command-line errors in the one style of every ssgi error: "ssgi: error: <what>", one printable
// line, naming the word that was not understood and, for a near miss, the command or option meant.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace ssgi::cli {

// The message for a failed parse of argv by `app` (without the "ssgi: error: " prefix): an unknown
// or missing command, an unknown option of a command (with the nearest known one within a small
// edit distance), or else CLI11's own description, prefixed with the command it belongs to.
std::string DescribeParseError(const CLI::App& app, const CLI::ParseError& error, int argc, const char* const* argv);

// argv as CLI11 should parse it: a value that starts with '-' and a digit ("--background -1,0,0",
// "--exposure -.5") is joined to the option before it ("--background=-1,0,0"), which CLI11 would
// otherwise take for an unknown option; the option's own check then names what is wrong with it.
std::vector<std::string> JoinNegativeValues(const CLI::App& app, int argc, const char* const* argv);

// The known word closest to `word` by edit distance (insertions, deletions, substitutions and
// swaps of neighbours), or "" when none is close enough to be a typo of it.
std::string NearestWord(std::string_view word, const std::vector<std::string>& known);

// `text` safe to print on one terminal line: control bytes, DEL and bytes that are not valid UTF-8
// become \xNN (newline and tab included), so input echoed in a message cannot move the cursor,
// recolour the terminal or split the line.
std::string Printable(std::string_view text);

}  // namespace ssgi::cli
