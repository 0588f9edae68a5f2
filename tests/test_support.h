// Helpers shared by the tests: scratch folders, files written from strings, running the CLI.
#pragma once

#include <filesystem>
#include <functional>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/kernel_path.h"

namespace ssgi::test {

// The project's source folder (for data/) and the built ssgi executable.
std::filesystem::path SourceDir();
std::filesystem::path CliPath();
// The third-party models (Sponza, Sibenik, bunny, ...) in data/scenes/models/<folder>/, where the
// scene files in data/scenes find them and data/scenes/fetch.sh puts them; not part of the
// repository, so tests that need them skip with MissingScenesMessage where they are absent.
std::filesystem::path ThirdPartyScenesDir();
// "skipped: <missing> is not present; ..." and how to fetch the models, for a test's WARN.
std::string MissingScenesMessage(const std::filesystem::path& missing);

// A fresh empty folder under the system temp folder, removed when the object dies.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

void WriteText(const std::filesystem::path& file, const std::string& text);
// A file's bytes ("" when it cannot be read).
std::string ReadFileBytes(const std::filesystem::path& file);

struct CommandResult {
  int exitCode = -1;
  std::string output;  // stdout and stderr together
};
// An image file's pixels as stored (8-bit for PNG, 32-bit words for EXR channels), all channels
// interleaved, for byte-exact comparisons.
struct StoredImage {
  int width = 0, height = 0, channels = 0;
  std::vector<std::string> channelNames;
  std::vector<uint8_t> bytes;
};
StoredImage ReadStoredImage(const std::filesystem::path& file);

// The message of the InputError that `action` throws ("" when it throws none).
template <class Action>
std::string InputErrorOf(Action&& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// `path` in single quotes, for a command line.
inline std::string Quote(const std::filesystem::path& path) { return "'" + path.string() + "'"; }

// Runs `program` with `arguments` (already shell-quoted where needed).
CommandResult RunProgram(const std::filesystem::path& program, const std::string& arguments);

// Calls body(targetName) once for every SIMD target that Highway compiled and this machine supports,
// with dispatch restricted to that target, then restores normal dispatch. Returns the number of
// targets (docs/design.md §11: each Highway twin must equal its scalar definition on every one).
size_t ForEachSimdTarget(const std::function<void(const char* targetName)>& body);

// The first index at which a and b hold different bits (NaN payloads and signed zeros count), or n
// when all n floats are the same: for SIMD twins, which must equal their scalar definitions exactly.
size_t FirstDifferentBits(const float* a, const float* b, size_t n);

// For a row kernel writing one float row: calls scalar(args..., out) and simd(args..., out), each on
// an output row of `width` floats and one more, all -1 before (the one past the row must stay so),
// and returns the first index at which the two hold different bits: width + 1 when the twins agree.
template <class... Params, class... Args>
size_t FirstDifferenceOfTwins(size_t width, void (*scalar)(Params...), void (*simd)(Params...), Args... args) {
  std::vector<float> expected(width + 1, -1.0f), actual(width + 1, -1.0f);
  scalar(args..., expected.data());
  simd(args..., actual.data());
  return FirstDifferentBits(actual.data(), expected.data(), width + 1);
}

// For a pass with both kernel paths: runs run(KernelPath::kScalar) once and run(KernelPath::kSimd)
// on every compiled and supported target, and returns the names of the targets on which
// same(simd output, scalar output) is false, comma-separated: "" when the twins give the scalar
// bytes everywhere ("no SIMD target" when none ran).
template <class Run, class Same>
std::string TargetsWhereKernelPathsDiffer(const Run& run, const Same& same) {
  const auto scalar = run(KernelPath::kScalar);
  std::string differing;
  const size_t targets = ForEachSimdTarget([&](const char* target) {
    if (!same(run(KernelPath::kSimd), scalar)) differing += (differing.empty() ? "" : ", ") + std::string(target);
  });
  return targets == 0 ? "no SIMD target" : differing;
}

// Floats a SIMD twin must treat exactly as its scalar definition does: both zeros, both infinities,
// NaN, negatives, denormals, the smallest and largest normals, values past a half float's range.
// The one NaN is x86's default NaN (0xFFC00000), the one every invalid operation (inf - inf,
// 0 * inf) makes: where two different NaNs meet in a sum, which one it keeps depends on the operand
// order the compiler picked, in scalar and SIMD code alike.
std::vector<float> SpecialFloats();

// Runs the ssgi CLI with `arguments` (already shell-quoted where needed).
CommandResult RunCli(const std::string& arguments);
// data/default.json, quoted for a command line.
std::string DefaultSceneArg();
// Checks that `dir` holds exactly the named files: no output and no temporary may survive a failed
// command.
void RequireOnlyFiles(const ScratchDir& dir, std::initializer_list<std::string> names);

// A command line the CLI must refuse: its exit code and a piece of its one-line message.
struct CliErrorCase {
  std::string arguments;
  std::string expected;
  int exitCode;  // 2: a command line that does not parse (or input `diff` cannot use); 1: bad input
};
// Checks each case: that exit code, one line starting "ssgi: error: " that holds `expected`.
void CheckCliErrors(const std::vector<CliErrorCase>& cases);

}  // namespace ssgi::test
