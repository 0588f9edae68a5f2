// What the commands of the `ssgi` command line share: the data folder, the frame settings as
// options, loading a scene with its settings, the stats table, and the options every command that
// allocates takes (--threads, --max-memory).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/scene.h"
#include "core/system_memory.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"

namespace ssgi::cli {

namespace fs = std::filesystem;

// A command of the command line: its CLI11 subcommand and what runs it once parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// A file of the project's data folder: $SSGI_DATA_DIR, then data/ beside the executable's folder (a
// build tree inside the source tree, or an install prefix's share/ssgi), then the source tree it
// was built from.
fs::path DataFilePath(const std::string& name);
fs::path DefaultScenePath();

// The frame settings given on a command line, each an option derived from the settings table
// (passes/frame/config.h); they override the scene file's render block.
struct SettingOptions {
  std::vector<std::pair<const FrameSetting*, CLI::Option*>> options;

  // Registers the settings named in `only`, or every setting with an option when `only` is empty.
  void Register(CLI::App& command, std::initializer_list<std::string_view> only = {});
  // The given options on top of `config`, in the table's order (the preset before its knobs).
  void ApplyTo(FrameConfig& config) const;
};

// The scene and how to render it: the scene file's render block, then the command line's settings.
struct SceneAndConfig {
  Scene scene;
  FrameConfig config;
};
SceneAndConfig LoadSceneAndConfig(const fs::path& path, const SettingOptions& settings);

// "scene.json: 21356 triangles, 12 materials, 1 texture": the loaded scene in one line.
std::string DescribeScene(const fs::path& path, const Scene& scene);
// "1 material", "12 materials".
std::string CountOf(size_t count, const std::string& singular, const std::string& plural = "");

// The stats table of `--stats`.
void PrintStats(const std::vector<StageStats>& rows, int width, int height, int threads);

// --threads N: worker threads, 0 = all; a value that is not a whole number in range is refused
// naming the option.
void AddThreadsOption(CLI::App& command, int& threads, const std::string& help);
// The number of threads a --threads value means.
int ThreadCount(int threads);

// --max-memory SIZE (core/system_memory.h's units) and what a command may allocate: that, or the
// default budget (the smaller of the memory available and the cgroup's limit).
void AddMaxMemoryOption(CLI::App& command, std::string& maxMemory);
MemoryBudget BudgetFor(const std::string& maxMemory);

// What a command is about to allocate, refused before it does when over budget:
//   "a 16384x16384 frame needs about 11.2 GiB (estimate; plus 130 MiB for the process), more than
//    --max-memory 8.0 GiB".
// `fixedBytes` is what the process holds already that the kernel cannot drop (its anonymous
// resident set): counted against --max-memory, but not against the memory available, which
// already excludes it.
void CheckMemory(const std::string& what, size_t bytes, const MemoryBudget& budget, const std::string& hint = "");
// The process's anonymous resident set: what it holds that counts against a memory limit.
size_t FixedProcessBytes();

// An input file as a command reads it: refused with one line when missing or a directory.
void CheckInputFile(const fs::path& path, const std::string& what = "input");

}  // namespace ssgi::cli
