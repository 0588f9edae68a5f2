#include "cli/common.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "core/error.h"

namespace ssgi::cli {
namespace {

// How --help shows a setting's value: "INT in [16, 16384]", "R,G,B".
std::string ValueTypeName(const FrameSetting& setting) {
  auto bound = [](double v) { return FormatSettingValue(v); };
  switch (setting.kind) {
    case SettingKind::kInteger:
      return "INT in [" + bound(setting.min) + ", " + bound(setting.max) + "]";
    case SettingKind::kNumber:
      return "NUMBER";
    case SettingKind::kChoice:
      return "TEXT";
    case SettingKind::kColor:
      return "R,G,B";
    case SettingKind::kImageSize:
      return "WIDTHxHEIGHT";
  }
  return "TEXT";
}

}  // namespace

fs::path DataFilePath(const std::string& name) {
  if (const char* dir = std::getenv("SSGI_DATA_DIR")) return fs::path(dir) / name;
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (fs::path dir = exe.parent_path(); !dir.empty() && dir != dir.root_path(); dir = dir.parent_path()) {
      for (const fs::path& candidate : {dir / "data" / name, dir / "share" / "ssgi" / name})
        if (fs::exists(candidate, error)) return candidate;
    }
  }
  return fs::path(SSGI_SOURCE_DATA_DIR) / name;
}

fs::path DefaultScenePath() { return DataFilePath("default.json"); }

void SettingOptions::Register(CLI::App& command, std::initializer_list<std::string_view> only) {
  const FrameConfig defaults;
  for (const FrameSetting& setting : FrameSettings()) {
    if (setting.option.empty()) continue;
    if (only.size() > 0 && std::find(only.begin(), only.end(), setting.name) == only.end()) continue;
    std::string help(setting.help);
    if (setting.get) help += " Default: " + FormatSettingValue(setting.get(defaults)) + ".";
    if (setting.inSceneFile) help += " Overrides the scene file's render." + std::string(setting.name) + ".";
    CLI::Option* option = command.add_option(std::string(setting.option))->description(help);
    option->type_name(ValueTypeName(setting));
    if (setting.kind == SettingKind::kChoice) {
      option->check(CLI::IsMember(std::vector<std::string>(setting.choices.begin(), setting.choices.end())));
    } else {
      option->check(CLI::Validator(
          [&setting](std::string& text) {
            try {
              ParseSettingText(setting, text);
              return std::string();
            } catch (const InputError& e) {
              return std::string(e.what());
            }
          },
          "", std::string(setting.name)));
    }
    options.emplace_back(&setting, option);
  }
}

void SettingOptions::ApplyTo(FrameConfig& config) const {
  for (const auto& [setting, option] : options)
    if (option->count() > 0) ApplySetting(config, setting->name, option->as<std::string>());
}

SceneAndConfig LoadSceneAndConfig(const fs::path& path, const SettingOptions& settings) {
  CheckInputFile(path, "scene");
  SceneFile file = LoadSceneFile(path);
  for (const std::string& warning : file.scene.warnings) std::fprintf(stderr, "ssgi: warning: %s\n", warning.c_str());
  FrameConfig config = FrameConfigFromSceneFile(file);
  settings.ApplyTo(config);
  return {std::move(file.scene), config};
}

std::string CountOf(size_t count, const std::string& singular, const std::string& plural) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

std::string DescribeScene(const fs::path& path, const Scene& scene) {
  return "scene " + path.string() + ": " + CountOf(scene.mesh.TriangleCount(), "triangle") + ", " +
         CountOf(scene.materials.size(), "material") + ", " + CountOf(scene.textures.size(), "texture");
}

void PrintStats(const std::vector<StageStats>& rows, int width, int height, int threads) {
  std::printf("%dx%d, %s\n", width, height, CountOf(size_t(threads), "thread").c_str());
  std::printf("  %-20s %10s  %s\n", "stage", "ms", "throughput");
  for (const StageStats& s : rows) {
    std::printf("  %-20s %10.3f", s.name.c_str(), s.ms);
    if (s.items > 0.0 && s.ms > 0.0)
      std::printf("  %8.2f M %s/s (%.0f %s)", s.items / (s.ms * 1e3), s.itemUnit.c_str(), s.items, s.itemUnit.c_str());
    else if (!s.itemUnit.empty())
      std::printf("  %10s (%.0f %s)", s.items > 0.0 ? "" : "none", s.items, s.itemUnit.c_str());
    std::printf("\n");
  }
}

void AddThreadsOption(CLI::App& command, int& threads, const std::string& help) {
  command.add_option("--threads", threads, help)
      ->type_name("N")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            char* end = nullptr;
            const long value = std::strtol(text.c_str(), &end, 10);
            if (text.empty() || end == text.c_str() || *end != '\0' || value < 0 || value > 1024)
              return "must be a whole number of threads from 0 (all) to 1024, got '" + text + "'";
            return "";
          },
          "", "threads"));
}

int ThreadCount(int threads) { return threads > 0 ? threads : HardwareThreads(); }

void AddMaxMemoryOption(CLI::App& command, std::string& maxMemory) {
  command.add_option("--max-memory", maxMemory,
                     "Refuse, before allocating, work whose estimated memory (with what the process holds) "
                     "exceeds SIZE: 512M, 1.5G, 2GiB (powers of 1024) or 800MB, 2GB (powers of 1000). "
                     "Default: the smaller of the memory available and the cgroup's limit.")
      ->type_name("SIZE")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            try {
              ParseByteCount(text, "--max-memory");
              return "";
            } catch (const InputError& e) {
              const std::string message = e.what();
              return message.substr(message.find(": ") + 2);
            }
          },
          "", "size"));
}

MemoryBudget BudgetFor(const std::string& maxMemory) {
  if (maxMemory.empty()) return DefaultMemoryBudget();
  const size_t bytes = ParseByteCount(maxMemory, "--max-memory");
  return {bytes, "--max-memory " + FormatBytes(bytes), true};
}

size_t FixedProcessBytes() {
  const size_t resident = ResidentBytes(), file = ResidentFileBytes();
  return resident > file ? resident - file : 0;
}

void CheckMemory(const std::string& what, size_t bytes, const MemoryBudget& budget, const std::string& hint) {
  if (budget.bytes == 0) return;
  const size_t fixed = budget.coversProcess ? FixedProcessBytes() : 0;
  if (fixed + bytes <= budget.bytes) return;
  std::string message = what + " needs about " + FormatBytes(fixed + bytes);
  message += budget.coversProcess ? " (estimate: " + FormatBytes(bytes) + ", and " + FormatBytes(fixed) +
                                        " the process holds already)"
                                  : " more (estimate)";
  message += ", more than " + budget.source;
  if (!hint.empty()) message += "; " + hint;
  throw InputError(message);
}

void CheckInputFile(const fs::path& path, const std::string& what) {
  if (path.empty()) throw InputError("the " + what + " file name is empty");
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) throw InputError(path, "no such file");
  if (status.type() == fs::file_type::directory) throw InputError(path, "is a directory, not a " + what + " file");
}

}  // namespace ssgi::cli
