// Recoverable errors (docs/design.md §12, tier 2): bad input found at the edges (scene, OBJ/MTL, texture,
// command-line values, output path). Thrown where the problem is found, with the file and, where
// known, the line; only cli/ turns one into a message and an exit code.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace ssgi {

class InputError : public std::runtime_error {
 public:
  // Message format: "<file>:<line>: <problem>" or "<file>: <problem>" when line is 0.
  InputError(const std::filesystem::path& file, int line, const std::string& problem)
      : std::runtime_error(Format(file, line, problem)) {}
  InputError(const std::filesystem::path& file, const std::string& problem) : InputError(file, 0, problem) {}
  // For problems that belong to no file (a command-line value).
  explicit InputError(const std::string& problem) : std::runtime_error(problem) {}

 private:
  static std::string Format(const std::filesystem::path& file, int line, const std::string& problem) {
    std::string out = file.string();
    if (line > 0) out.append(":").append(std::to_string(line));
    out.append(": ").append(problem);
    return out;
  }
};

}  // namespace ssgi
