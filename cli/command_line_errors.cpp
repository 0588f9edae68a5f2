#include "cli/command_line_errors.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <sstream>
#include <vector>

namespace ssgi::cli {
namespace {

// Optimal string alignment distance (Damerau-Levenshtein without repeated edits of one substring):
// "rendr" -> "render" is 1, "--stast" -> "--stats" is 1.
size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

std::string Quoted(std::string_view word) { return "'" + Printable(word) + "'"; }

std::string DidYouMean(std::string_view word, const std::vector<std::string>& known) {
  const std::string nearest = NearestWord(word, known);
  return nearest.empty() ? "" : " (did you mean " + Quoted(nearest) + "?)";
}

std::string JoinWords(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

// A number given as an option's value ("--exposure -1.5") is not an option.
bool IsNumber(const std::string& word) {
  char* end = nullptr;
  std::strtod(word.c_str(), &end);
  return end != word.c_str() && *end == '\0';
}

// Each option of `command` as it is written on a command line: "--stats", "-o".
std::vector<std::string> OptionSpellings(const CLI::App& command) {
  std::vector<std::string> spellings;
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) spellings.push_back("--" + name);
    for (const std::string& name : option->get_snames()) spellings.push_back("-" + name);
  }
  return spellings;
}

}  // namespace

std::vector<std::string> JoinNegativeValues(const CLI::App& app, int argc, const char* const* argv) {
  std::vector<std::string> args;
  const CLI::App* command = &app;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (command == &app)
      for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        if (sub->get_name() == word) command = sub;
    const bool negative =
        word.size() > 1 && word[0] == '-' && (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.');
    if (negative && !args.empty() && args.back().rfind("--", 0) == 0 && args.back().find('=') == std::string::npos) {
      const CLI::Option* option = command->get_option_no_throw(args.back());
      if (option != nullptr && option->get_type_size() != 0) {
        args.back() += "=" + word;
        continue;
      }
    }
    args.push_back(word);
  }
  return args;
}

std::string NearestWord(std::string_view word, const std::vector<std::string>& known) {
  // A typo changes a letter or two; beyond a third of the word it is another word.
  const size_t allowed = std::max<size_t>(1, std::min<size_t>(2, word.size() / 3));
  std::string best;
  size_t bestDistance = allowed + 1;
  for (const std::string& candidate : known) {
    const size_t distance = EditDistance(word, candidate);
    if (distance < bestDistance) {
      bestDistance = distance;
      best = candidate;
    }
  }
  return best;
}

std::string DescribeParseError(const CLI::App& app, const CLI::ParseError& error, int argc, const char* const* argv) {
  std::vector<std::string> commands;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    commands.push_back(command->get_name());
  int commandIndex = 1;
  while (commandIndex < argc && argv[commandIndex][0] == '-') ++commandIndex;
  if (commandIndex >= argc) {
    if (commandIndex > 1) return "unknown option " + Quoted(argv[1]) + " before the command; commands: " + JoinWords(commands);
    return "a command is required: " + JoinWords(commands) + " ('ssgi --help' describes them)";
  }
  const std::string commandWord = argv[commandIndex];
  const auto known = std::find(commands.begin(), commands.end(), commandWord);
  if (known == commands.end())
    return "unknown command " + Quoted(commandWord) + DidYouMean(commandWord, commands) + "; commands: " +
           JoinWords(commands);

  const CLI::App& command = *app.get_subcommand(commandWord);
  const std::vector<std::string> spellings = OptionSpellings(command);
  for (int i = commandIndex + 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word == "--") break;
    if (word.size() < 2 || word[0] != '-' || IsNumber(word)) continue;
    if (const size_t equals = word.find('='); equals != std::string::npos) word.resize(equals);
    if (std::find(spellings.begin(), spellings.end(), word) == spellings.end())
      return "unknown option " + Quoted(word) + " for 'ssgi " + commandWord + "'" + DidYouMean(word, spellings) +
             "; 'ssgi " + commandWord + " --help' lists them";
  }
  // CLI11's IsMember check says "--quality: hgh not in {low,medium,high,ultra}": name the choices
  // and the one meant.
  const std::string message = error.what();
  static const std::regex kNotMember(R"(^(\S+): (.*) not in \{(.*)\}$)");
  if (std::smatch m; std::regex_match(message, m, kNotMember)) {
    std::vector<std::string> choices;
    std::stringstream list(m[3].str());
    for (std::string choice; std::getline(list, choice, ',');) choices.push_back(choice);
    return m[1].str() + " of 'ssgi " + commandWord + "': " + Quoted(m[2].str()) + " is not one of " +
           JoinWords(choices) + DidYouMean(m[2].str(), choices);
  }
  return "'ssgi " + commandWord + "': " + Printable(message);
}

std::string Printable(std::string_view text) {
  std::string out;
  auto escape = [&](unsigned char byte) {
    char hex[8];
    std::snprintf(hex, sizeof(hex), "\\x%02X", byte);
    out += hex;
  };
  for (size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20 && byte < 0x7F) {
      out += char(byte);
      ++i;
      continue;
    }
    // The length of a well-formed UTF-8 sequence starting here (RFC 3629: no overlong forms, no
    // surrogates, nothing above U+10FFFF), 0 when it is not one.
    size_t length = 0;
    uint32_t codePoint = 0;
    if (byte >= 0xC2 && byte <= 0xDF) length = 2, codePoint = byte & 0x1Fu;
    else if (byte >= 0xE0 && byte <= 0xEF) length = 3, codePoint = byte & 0x0Fu;
    else if (byte >= 0xF0 && byte <= 0xF4) length = 4, codePoint = byte & 0x07u;
    for (size_t k = 1; k < length; ++k) {
      const auto next = i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0;
      if ((next & 0xC0u) != 0x80u) {
        length = 0;
        break;
      }
      codePoint = (codePoint << 6) | (next & 0x3Fu);
    }
    const bool wellFormed = length > 0 && !(length == 3 && codePoint < 0x800) && !(length == 4 && codePoint < 0x10000) &&
                            !(codePoint >= 0xD800 && codePoint <= 0xDFFF) && codePoint <= 0x10FFFF;
    // C1 controls (U+0080..U+009F) act as escape sequences on some terminals.
    if (wellFormed && codePoint > 0x9F) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      escape(byte);
      ++i;
    }
  }
  return out;
}

}  // namespace ssgi::cli
