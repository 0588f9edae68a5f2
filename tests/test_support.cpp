#include "tests/test_support.h"

#include <OpenImageIO/imageio.h>
#include <hwy/targets.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace ssgi::test {

std::filesystem::path SourceDir() { return SSGI_SOURCE_DIR; }
std::filesystem::path CliPath() { return SSGI_CLI_PATH; }
std::filesystem::path ThirdPartyScenesDir() { return SourceDir() / "data" / "scenes" / "models"; }
std::string MissingScenesMessage(const std::filesystem::path& missing) {
  return "skipped: " + missing.string() +
         " is not present; fetch the third-party models with data/scenes/fetch.sh (downloads them) or "
         "data/scenes/fetch.sh --from DIR (copies a local mirror)";
}

ScratchDir::ScratchDir(const std::string& name) {
  path_ = std::filesystem::temp_directory_path() / ("ssgi-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

void WriteText(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string ReadFileBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

StoredImage ReadStoredImage(const std::filesystem::path& file) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) throw std::runtime_error("cannot read " + file.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  StoredImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.nchannels;
  image.channelNames = spec.channelnames;
  image.bytes.resize(spec.image_bytes(true));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UNKNOWN, image.bytes.data()))
    throw std::runtime_error("cannot read " + file.string() + ": " + in->geterror());
  return image;
}

size_t ForEachSimdTarget(const std::function<void(const char* targetName)>& body) {
  size_t targets = 0;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    try {
      body(hwy::TargetName(target));
    } catch (...) {
      hwy::SetSupportedTargetsForTest(0);
      throw;
    }
    ++targets;
  }
  hwy::SetSupportedTargetsForTest(0);
  return targets;
}

size_t FirstDifferentBits(const float* a, const float* b, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (std::memcmp(a + i, b + i, sizeof(float)) != 0) return i;
  return n;
}

std::vector<float> SpecialFloats() {
  using Limits = std::numeric_limits<float>;
  const uint32_t defaultNanBits = 0xFFC00000u;
  float defaultNan;
  std::memcpy(&defaultNan, &defaultNanBits, sizeof(defaultNan));
  return {0.0f,          -0.0f,          Limits::infinity(),   -Limits::infinity(),   defaultNan,
          -1.0f,         1.0f,           Limits::denorm_min(), -Limits::denorm_min(), Limits::min() / 3.0f,
          Limits::min(), -Limits::min(), Limits::max(),        -Limits::max(),        1e38f,
          65504.0f,      65505.0f,       1e-30f,               -1e30f};
}

CommandResult RunCli(const std::string& arguments) { return RunProgram(CliPath(), arguments); }

void CheckCliErrors(const std::vector<CliErrorCase>& cases) {
  for (const CliErrorCase& c : cases) {
    const CommandResult result = RunCli(c.arguments);
    CAPTURE(c.arguments, result.output);
    CHECK(result.exitCode == c.exitCode);
    CHECK(result.output.find(c.expected) != std::string::npos);
    CHECK(result.output.find("ssgi: error: ") == 0);
    CHECK(std::count(result.output.begin(), result.output.end(), '\n') == 1);
  }
}

std::string DefaultSceneArg() { return Quote(SourceDir() / "data" / "default.json"); }

void RequireOnlyFiles(const ScratchDir& dir, std::initializer_list<std::string> names) {
  size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++count;
    CAPTURE(entry.path().string());
    CHECK(std::find(names.begin(), names.end(), entry.path().filename().string()) != names.end());
  }
  CHECK(count == names.size());
}

CommandResult RunProgram(const std::filesystem::path& program, const std::string& arguments) {
  const std::string command = "'" + program.string() + "' " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed: " + command);
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace ssgi::test
