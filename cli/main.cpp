// The ssgi command line. The only place an error becomes a message and an exit code (docs/design.md §12).
// Every error is one printable line "ssgi: error: ..." on stderr; the exit code says whose it is:
// 0 success, 1 bad input (scene, model, texture, output path, option value), 2 a command line that
// does not parse (unknown command or option, missing or malformed value), 3 an internal failure.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/command_line_errors.h"
#include "core/error.h"
#include "core/image_compare.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/reference/reference.h"
#include "core/stopwatch.h"
#include "passes/frame/frame.h"
#include "passes/frame/diff.h"
#include "passes/frame/dump.h"
#include "passes/frame/memory.h"

namespace fs = std::filesystem;

namespace {

// A file of the project's data folder: $SSGI_DATA_DIR, then data/ beside the executable's folder (a
// build tree inside the source tree, or an install prefix's share/ssgi), then the source tree it
// was built from.
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

// How --help shows a setting's value: "INT in [16, 16384]", "R,G,B".
std::string ValueTypeName(const ssgi::FrameSetting& setting) {
  auto bound = [](double v) { return ssgi::FormatSettingValue(v); };
  switch (setting.kind) {
    case ssgi::SettingKind::kInteger:
      return "INT in [" + bound(setting.min) + ", " + bound(setting.max) + "]";
    case ssgi::SettingKind::kNumber:
      return "NUMBER";
    case ssgi::SettingKind::kChoice:
      return "TEXT";
    case ssgi::SettingKind::kColor:
      return "R,G,B";
    case ssgi::SettingKind::kImageSize:
      return "WIDTHxHEIGHT";
  }
  return "TEXT";
}

// The frame settings given on a command line, each an option derived from the settings table
// (passes/frame/config.h); they override the scene file's render block.
struct SettingOptions {
  std::vector<std::pair<const ssgi::FrameSetting*, CLI::Option*>> options;

  // Registers the settings named in `only`, or every setting with an option when `only` is empty.
  void Register(CLI::App& command, std::initializer_list<std::string_view> only = {}) {
    const ssgi::FrameConfig defaults;
    for (const ssgi::FrameSetting& setting : ssgi::FrameSettings()) {
      if (setting.option.empty()) continue;
      if (only.size() > 0 && std::find(only.begin(), only.end(), setting.name) == only.end()) continue;
      std::string help(setting.help);
      if (setting.get) help += " Default: " + ssgi::FormatSettingValue(setting.get(defaults)) + ".";
      if (setting.inSceneFile) help += " Overrides the scene file's render." + std::string(setting.name) + ".";
      CLI::Option* option = command.add_option(std::string(setting.option))->description(help);
      option->type_name(ValueTypeName(setting));
      if (setting.kind == ssgi::SettingKind::kChoice) {
        option->check(CLI::IsMember(std::vector<std::string>(setting.choices.begin(), setting.choices.end())));
      } else {
        option->check(CLI::Validator(
            [&setting](std::string& text) {
              try {
                ssgi::ParseSettingText(setting, text);
                return std::string();
              } catch (const ssgi::InputError& e) {
                return std::string(e.what());
              }
            },
            "", std::string(setting.name)));
      }
      options.emplace_back(&setting, option);
    }
  }

  // The given options on top of `config`, in the table's order (the preset before its knobs).
  void ApplyTo(ssgi::FrameConfig& config) const {
    for (const auto& [setting, option] : options)
      if (option->count() > 0) ssgi::ApplySetting(config, setting->name, option->as<std::string>());
  }
};

struct RenderOptions {
  std::string scene;
  std::string output;
  int threads = 0;
  bool stats = false;
  bool explain = false;
  std::string maxMemory;
  std::string dumpBuffers;
  SettingOptions settings;
};

// The scene and how to render it: the scene file's render block, then the command line's settings.
struct SceneAndConfig {
  ssgi::Scene scene;
  ssgi::FrameConfig config;
};
SceneAndConfig LoadSceneAndConfig(const fs::path& path, const SettingOptions& settings) {
  ssgi::SceneFile file = ssgi::LoadSceneFile(path);
  ssgi::FrameConfig config = ssgi::FrameConfigFromSceneFile(file);
  settings.ApplyTo(config);
  return {std::move(file.scene), config};
}

void PrintStats(const std::vector<ssgi::StageStats>& stats, int width, int height, int threads) {
  std::printf("%dx%d, %d thread%s\n", width, height, threads, threads == 1 ? "" : "s");
  std::printf("  %-20s %10s  %s\n", "stage", "ms", "throughput");
  for (const ssgi::StageStats& s : stats) {
    std::printf("  %-20s %10.3f", s.name.c_str(), s.ms);
    if (s.items > 0.0 && s.ms > 0.0)
      std::printf("  %8.2f M %s/s (%.0f %s)", s.items / (s.ms * 1e3), s.itemUnit.c_str(), s.items, s.itemUnit.c_str());
    else if (!s.itemUnit.empty())
      std::printf("  %10s (%.0f %s)", s.items > 0.0 ? "" : "none", s.items, s.itemUnit.c_str());
    std::printf("\n");
  }
}

int Render(const RenderOptions& options) {
  const ssgi::ThreadLimit threadLimit(options.threads);
  const int threads = options.threads > 0 ? options.threads : ssgi::HardwareThreads();
  const fs::path scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  const fs::path output = options.output.empty() ? fs::path(scenePath.stem().string() + ".png") : fs::path(options.output);
  // Every check that can fail on the command line happens before the (possibly long) render.
  const ssgi::ImageFileKind kind = ssgi::CheckOutputPath(output);
  if (!options.dumpBuffers.empty() && ssgi::CheckOutputPath(options.dumpBuffers) != ssgi::ImageFileKind::kExr)
    throw ssgi::InputError(options.dumpBuffers, "--dump writes a multi-part EXR: use a .exr name");

  ssgi::Stopwatch load;
  const auto [scene, config] = LoadSceneAndConfig(scenePath, options.settings);
  const double loadMs = load.Lap();

  // Refused before anything is allocated, rather than ending in bad_alloc or the OOM killer.
  const size_t before = ssgi::ResidentBytes();
  // Without a dump, each buffer lives only until its last reader.
  const ssgi::BufferLifetime lifetime =
      options.dumpBuffers.empty() ? ssgi::BufferLifetime::kUntilLastReader : ssgi::BufferLifetime::kKeepAll;
  const ssgi::FrameMemoryEstimate memory =
      ssgi::EstimateFrameMemory(scene, config, lifetime, !options.dumpBuffers.empty());
  const std::string size = std::to_string(config.width) + "x" + std::to_string(config.height);
  if (!options.maxMemory.empty()) {
    const size_t limit = ssgi::ParseByteCount(options.maxMemory);
    if (before + memory.bytes > limit)
      throw ssgi::InputError("a " + size + " frame needs about " + ssgi::FormatBytes(before + memory.bytes) +
                             " (estimate), more than --max-memory " + ssgi::FormatBytes(limit));
  } else if (const size_t available = ssgi::AvailableMemoryBytes(); available > 0 && memory.bytes > available) {
    throw ssgi::InputError("a " + size + " frame needs about " + ssgi::FormatBytes(memory.bytes) +
                           " more (estimate), more than the " + ssgi::FormatBytes(available) +
                           " this machine has available; render smaller or set a smaller --shadow-map-size");
  }

  ssgi::Frame frame = ssgi::RenderFrame(scene, config, lifetime);
  // What of the frame's peak the kernel could not have reclaimed: the file-backed pages (library
  // code, about 85 MiB) change little after start-up, so the peak less them is the anonymous peak.
  const size_t framePeak = ssgi::PeakResidentBytes();
  const size_t fileBacked = std::min(ssgi::ResidentFileBytes(), framePeak);
  ssgi::Stopwatch write;
  const int w = config.width, h = config.height;
  if (kind == ssgi::ImageFileKind::kPng) {
    ssgi::WritePng(output, w, h, frame.display.rgb);
  } else {
    const ssgi::Plane3<float>& result = frame.Result();
    ssgi::WriteExr(output, w, h,
                   {{"R", false, result.c[0].ConstRow(0), size_t(result.c[0].PixelsPerRow())},
                    {"G", false, result.c[1].ConstRow(0), size_t(result.c[1].PixelsPerRow())},
                    {"B", false, result.c[2].ConstRow(0), size_t(result.c[2].PixelsPerRow())}});
  }
  if (!options.dumpBuffers.empty())
    ssgi::WriteFrameDump(options.dumpBuffers, frame, ssgi::DumpMetadata(fs::absolute(scenePath).string(), config));
  const double writeMs = write.Lap();

  if (options.explain)
    std::printf("%s", ssgi::ExplainPlan(ssgi::PlanFrame(scene, config, frame.gbuffer.gbuffer, frame.view, true)).c_str());
  if (options.stats) {
    std::printf("scene %s: %zu triangles, %zu materials, %zu textures, load %.1f ms\n", scenePath.string().c_str(),
                scene.mesh.TriangleCount(), scene.materials.size(), scene.textures.size(), loadMs);
    if (scene.reorientedTriangles > 0)
      std::printf("  %zu triangles wound against their neighbours were turned to match\n", scene.reorientedTriangles);
    PrintStats(ssgi::StageRows(frame.stats), w, h, threads);
    if (const auto& f = frame.stats.shadowFilter; f && f->tiles > 0)
      std::printf("  shadow blur ran on %zu of %zu tiles (%.1f%%)\n", f->tilesBlurred, f->tiles,
                  100.0 * double(f->tilesBlurred) / double(f->tiles));
    if (const auto& t = frame.stats.ssrTrace)
      std::printf("  ssr traced %zu rays (%.1f Hi-Z steps each) in %zu of %zu tiles (%.1f%%)\n", t->rays,
                  t->meanIterations, t->tilesTraced, t->tiles, 100.0 * double(t->tilesTraced) / double(t->tiles));
    std::printf("  %-20s %10.3f\n", "write image", writeMs);
    // The process before the frame (about 130 MiB, most of it the shared libraries OpenImageIO
    // loads) is a fixed cost; what grows with the image is the frame's own share.
    const size_t peak = ssgi::PeakResidentBytes();
    const size_t frameBytes = peak > before ? peak - before : 0;
    const double pixels = double(w) * double(h);
    std::printf("memory: peak %s resident (%.1f bytes per pixel), the frame's %s (%.1f bytes per pixel); "
                "estimate %s (%s before the frame + %s of buffers)\n",
                ssgi::FormatBytes(peak).c_str(), double(peak) / pixels, ssgi::FormatBytes(frameBytes).c_str(),
                double(frameBytes) / pixels, ssgi::FormatBytes(before + memory.bytes).c_str(),
                ssgi::FormatBytes(before).c_str(), ssgi::FormatBytes(memory.bytes).c_str());
    std::printf("  of the peak, %s anonymous (%.1f bytes per pixel) and %s file-backed: library code, which the "
                "kernel can drop and read again\n",
                ssgi::FormatBytes(framePeak - fileBacked).c_str(), double(framePeak - fileBacked) / pixels,
                ssgi::FormatBytes(fileBacked).c_str());
  }
  std::printf("wrote %s\n", output.string().c_str());
  return 0;
}

struct FiguresOptions {
  std::string folder;
  std::string scene;
  int threads = 0;
  SettingOptions settings;
};

// A horizontal strip of the same crop of several RGB images, separated by white bars.
std::vector<uint8_t> SideBySide(const std::vector<const std::vector<uint8_t>*>& images, int width, int x0, int y0,
                                int cropWidth, int cropHeight, int& stripWidth) {
  constexpr int kGap = 4;
  stripWidth = int(images.size()) * cropWidth + (int(images.size()) - 1) * kGap;
  std::vector<uint8_t> strip(size_t(stripWidth) * cropHeight * 3, 255);
  for (size_t i = 0; i < images.size(); ++i)
    for (int y = 0; y < cropHeight; ++y)
      std::copy_n(images[i]->data() + (size_t(y0 + y) * width + x0) * 3, size_t(cropWidth) * 3,
                  strip.data() + (size_t(y) * stripWidth + i * (cropWidth + kGap)) * 3);
  return strip;
}

// The paper's image sequence for one scene: albedo, direct light without shadows, direct light with
// SSABSS soft shadows (Figs. 4-6), the final image with indirect light at board roughness 0, 0.3 and
// 0.9 (Figs. 7-9; the default scene's board materials), a crop comparing the hard, SSPCSS and SSABSS
// shadow filters, and Table 1: the median frame time of direct only / + shadows / + shadows + GI.
int Figures(const FiguresOptions& options) {
  ssgi::RetainFreedMemory();  // Table 1 times frames rendered one after another, like a running renderer
  const ssgi::ThreadLimit threadLimit(options.threads);
  const int threads = options.threads > 0 ? options.threads : ssgi::HardwareThreads();
  const fs::path folder(options.folder);
  std::error_code error;
  fs::create_directories(folder, error);
  if (error) throw ssgi::InputError(folder, "cannot create the folder: " + error.message());
  ssgi::CheckOutputPath(folder / "albedo.png");
  auto [scene, config] = LoadSceneAndConfig(options.scene.empty() ? DefaultScenePath() : fs::path(options.scene),
                                            options.settings);
  const int width = config.width, height = config.height;

  auto configure = [&](ssgi::EffectMode shadows, ssgi::EffectMode reflections, ssgi::ShadowFilter filter) {
    ssgi::FrameConfig figure = config;
    figure.shadows = shadows;
    figure.reflections = reflections;
    figure.shadowFilter.filter = filter;
    return figure;
  };
  auto render = [&](ssgi::EffectMode shadows, ssgi::EffectMode reflections, ssgi::ShadowFilter filter) {
    return ssgi::RenderFrame(scene, configure(shadows, reflections, filter));
  };
  auto write = [&](const std::string& name, int w, int h, const std::vector<uint8_t>& rgb) {
    ssgi::WritePng(folder / name, w, h, rgb);
    std::printf("wrote %s\n", (folder / name).string().c_str());
  };
  using ssgi::EffectMode;
  using ssgi::ShadowFilter;
  const ssgi::Frame unshadowed = render(EffectMode::kOff, EffectMode::kOff, ShadowFilter::kSsabss);
  write("albedo.png", width, height, ssgi::AlbedoImage(unshadowed.gbuffer.gbuffer));
  write("direct.png", width, height, unshadowed.display.rgb);
  const ssgi::Frame hard = render(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kHard);
  const ssgi::Frame sspcss = render(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kSspcss);
  const ssgi::Frame ssabss = render(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kSsabss);
  write("direct_shadows.png", width, height, ssabss.display.rgb);
  // The crop of the default scene's blue sphere and its shadow on the board, as fractions of the image.
  const int x0 = int(0.30 * width), y0 = int(0.55 * height);
  const int cropWidth = std::max(1, int(0.30 * width)), cropHeight = std::max(1, int(0.22 * height));
  int stripWidth = 0;
  const std::vector<uint8_t> strip = SideBySide({&hard.display.rgb, &sspcss.display.rgb, &ssabss.display.rgb}, width,
                                                x0, y0, cropWidth, cropHeight, stripWidth);
  write("shadow_filters.png", stripWidth, cropHeight, strip);

  std::vector<ssgi::Material*> board;
  for (ssgi::Material& m : scene.materials)
    if (m.name == "board_light" || m.name == "board_dark") board.push_back(&m);
  const std::vector<float> boardRoughness = board.empty() ? std::vector<float>{} : std::vector<float>{0.0f, 0.3f, 0.9f};
  std::vector<float> sceneRoughness;
  for (const ssgi::Material* m : board) sceneRoughness.push_back(m->roughness);
  for (float roughness : boardRoughness) {
    for (ssgi::Material* m : board) m->roughness = roughness;
    char name[64];
    std::snprintf(name, sizeof(name), "gi_board_roughness_%.1f.png", double(roughness));
    write(name, width, height, render(EffectMode::kAuto, EffectMode::kAuto, ShadowFilter::kSsabss).display.rgb);
  }
  // Table 1 times the scene as it is, not as the last figure left it.
  for (size_t i = 0; i < board.size(); ++i) board[i]->roughness = sceneRoughness[i];
  if (board.empty()) write("gi.png", width, height, render(EffectMode::kAuto, EffectMode::kAuto, ShadowFilter::kSsabss).display.rgb);

  // Table 1: median frame time over repeated renders of each configuration.
  constexpr int kRepeats = 5;
  struct Row {
    const char* name;
    EffectMode shadows, reflections;
  };
  const Row rows[] = {{"direct only", EffectMode::kOff, EffectMode::kOff},
                      {"+ shadows", EffectMode::kAuto, EffectMode::kOff},
                      {"+ shadows + GI", EffectMode::kAuto, EffectMode::kAuto}};
  std::string table = "| " + std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(threads) +
                      " threads | frame time (median of " + std::to_string(kRepeats) +
                      ", ms) | paper, RTX 2080 Ti (ms) |\n|---|---|---|\n";
  const char* paper[] = {"15.08", "15.79", "16.69"};
  for (size_t r = 0; r < std::size(rows); ++r) {
    // Each frame rendered into the last one's buffers, as a running renderer renders.
    const ssgi::FrameConfig rowConfig = configure(rows[r].shadows, rows[r].reflections, ShadowFilter::kSsabss);
    ssgi::Frame frame;
    std::vector<double> times;
    for (int i = 0; i < kRepeats; ++i) {
      ssgi::RunFramePasses(scene, rowConfig, ssgi::FramePass::kGBuffer, ssgi::FramePass::kTonemap, frame,
                           ssgi::BufferLifetime::kKeepForReuse);
      times.push_back(frame.stats.totalMs);
    }
    std::sort(times.begin(), times.end());
    char line[160];
    std::snprintf(line, sizeof(line), "| %s | %.1f | %s |\n", rows[r].name, times[kRepeats / 2], paper[r]);
    table += line;
  }
  std::printf("%s", table.c_str());
  const fs::path tablePath = folder / "table1.md";
  std::FILE* file = std::fopen(tablePath.c_str(), "w");
  if (!file || std::fputs(table.c_str(), file) < 0 || std::fclose(file) != 0)
    throw ssgi::InputError(tablePath, "cannot write the table");
  std::printf("wrote %s\n", tablePath.string().c_str());
  return 0;
}

struct ReferenceOptions {
  std::string scene;
  std::string output = "reference.exr";
  SettingOptions settings;
  int spp = 64;
  int threads = 0;
};

// The Embree ground truth (docs/design.md §10): one EXR holding the final image as R, G, B and the
// matching buffers under the names --dump uses, so `ssgi compare --layer` pairs them.
int Reference(const ReferenceOptions& options) {
  const ssgi::ThreadLimit threadLimit(options.threads);
  if (ssgi::CheckOutputPath(options.output) != ssgi::ImageFileKind::kExr)
    throw ssgi::InputError(options.output, "the reference is written as a multi-channel EXR: use a .exr name");
  const auto [scene, config] =
      LoadSceneAndConfig(options.scene.empty() ? DefaultScenePath() : fs::path(options.scene), options.settings);
  ssgi::ReferenceParams params = ssgi::ReferenceParamsForSpp(options.spp);
  params.width = config.width;
  params.height = config.height;
  params.background = config.directLight.background;
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  ssgi::Stopwatch stopwatch;
  const ssgi::ReferenceOutputs ref = ssgi::RenderReference(
      scene, params, [&](size_t done, size_t rows) {
        if (!terminal) return;
        const int width = 40, filled = int(width * done / std::max<size_t>(rows, 1));
        std::fprintf(stderr, "\r[%s%s] %3zu%%", std::string(size_t(filled), '#').c_str(),
                     std::string(size_t(width - filled), '.').c_str(), done * 100 / std::max<size_t>(rows, 1));
        if (done == rows) std::fprintf(stderr, "\n");
      });
  const double ms = stopwatch.Lap();
  std::vector<ssgi::ExrChannel> channels;
  auto add = [&](const std::string& name, const ssgi::Plane<float>& plane) {
    channels.push_back({name, false, plane.ConstRow(0), size_t(plane.PixelsPerRow())});
  };
  const char* rgb[] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) add(rgb[c], ref.result.c[c]);
  for (int c = 0; c < 3; ++c) {
    add(std::string("result.") + rgb[c], ref.result.c[c]);
    add(std::string("direct.") + rgb[c], ref.direct.c[c]);
    add(std::string("indirect.") + rgb[c], ref.indirect.c[c]);
  }
  add("shadow.visibility", ref.lightVisibility);
  add("depth", ref.depth);
  ssgi::WriteExr(options.output, config.width, config.height, channels);
  std::printf("reference %dx%d, %d spp: %.1f ms (%zu rays, BVH %.1f ms)\nwrote %s\n", config.width,
              config.height, options.spp, ms, size_t(ref.stats.rays), ref.stats.buildMs, options.output.c_str());
  return 0;
}

struct CompareOptions {
  std::string test;
  std::string reference;
  std::string layer;
  std::string heatmap;
  double heatmapScale = 0.0;
};

// Error of a test image against a reference (docs/design.md §10): RMSE and PSNR on linear values, the
// largest error and where, and mean SSIM of the tonemapped luminance as the perceptual score.
int Compare(const CompareOptions& options) {
  if (!options.heatmap.empty() && ssgi::CheckOutputPath(options.heatmap) != ssgi::ImageFileKind::kPng)
    throw ssgi::InputError(options.heatmap, "--heatmap writes a PNG: use a .png name");
  const ssgi::FloatImage test =
      ssgi::SelectLayer(ssgi::ReadFloatImage(options.test), options.layer, options.test);
  const ssgi::FloatImage reference =
      ssgi::SelectLayer(ssgi::ReadFloatImage(options.reference), options.layer, options.reference);
  if (test.width != reference.width || test.height != reference.height || test.Channels() != reference.Channels())
    throw ssgi::InputError(options.test, "is " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                                             " with " + std::to_string(test.Channels()) + " channels, the reference " +
                                             std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                                             " with " + std::to_string(reference.Channels()));
  const ssgi::ImageDifference d = ssgi::CompareImages(test, reference);
  std::printf("%s vs %s (layer %s: %dx%d, %zu channels)\n", options.test.c_str(), options.reference.c_str(),
              options.layer.empty() ? "RGB" : options.layer.c_str(), test.width, test.height, test.Channels());
  std::printf("  RMSE       %.6g (linear), %.6g (of x/(1+x))\n", d.rmse, d.rmseDisplay);
  std::printf("  PSNR       %.2f dB (peak %.6g, the reference's largest value)\n", d.psnr, d.peak);
  std::printf("  max error  %.6g at (%d, %d)\n", d.maxError, d.maxX, d.maxY);
  std::printf("  SSIM       %.5f (mean SSIM of x/(1+x) tonemapped luminance; FLIP has no Debian 12 package)\n", d.ssim);
  if (d.nonFinite > 0) std::printf("  non-finite %zu samples (excluded)\n", d.nonFinite);
  if (!options.heatmap.empty()) {
    ssgi::WritePng(options.heatmap, test.width, test.height, ssgi::ErrorHeatmap(test, reference, options.heatmapScale));
    std::printf("wrote %s\n", options.heatmap.c_str());
  }
  return 0;
}

struct PassesOptions {
  std::string input;
  std::string scene;
  std::string from = "gbuffer";
  std::string to = "tonemap";
  std::string output;
  int threads = 0;
  bool stats = false;
};

// Runs passes --from .. --to of the frame on the buffers of a dump (the oracle's, or a port's in
// the dump's layer names) and writes the frame's buffers as a dump.
int Passes(const PassesOptions& options) {
  const ssgi::ThreadLimit threadLimit(options.threads);
  if (ssgi::CheckOutputPath(options.output) != ssgi::ImageFileKind::kExr)
    throw ssgi::InputError(options.output, "the passes' buffers are written as a multi-part EXR: use a .exr name");
  const ssgi::FramePass from = ssgi::ParseFramePass(options.from);
  const ssgi::FramePass to = ssgi::ParseFramePass(options.to);
  if (to < from)
    throw ssgi::InputError("--to " + options.to + " comes before --from " + options.from + " in the pipeline");
  const ssgi::ExrFile dump = ssgi::ReadExrFile(options.input);
  const auto [scene, config] = ssgi::LoadDumpScene(dump, options.input, options.scene);
  ssgi::Frame frame;
  ssgi::LoadFrameDump(dump, options.input, scene, config, from, to, frame);
  ssgi::RunFramePasses(scene, config, from, to, frame);
  const std::string sceneName =
      options.scene.empty() ? dump.metadata.at("ssgi:scene") : fs::absolute(options.scene).string();
  ssgi::WriteFrameDump(options.output, frame, ssgi::DumpMetadata(sceneName, config));
  if (options.stats) {
    const int threads = options.threads > 0 ? options.threads : ssgi::HardwareThreads();
    PrintStats(ssgi::StageRows(frame.stats), config.width, config.height, threads);
  }
  std::printf("ran %s .. %s on %s\nwrote %s\n", options.from.c_str(), options.to.c_str(), options.input.c_str(),
              options.output.c_str());
  return 0;
}

struct DiffOptions {
  std::string oracle;
  std::string port;
  std::string thresholds;
  std::string json;
  std::string heatmaps;
  std::string scene;
};

std::string FormatDifference(double value) {
  if (!std::isfinite(value)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

// One verdict over all passes: each layer both dumps hold, against its tolerance (docs/pipeline.md
// 'Matching rules'). Exit 0 when every layer is within tolerance, 1 when one is not; 2 for a command
// line or a file that cannot be used.
int Diff(const DiffOptions& options) {
  const ssgi::ExrFile oracle = ssgi::ReadExrFile(options.oracle);
  const ssgi::ExrFile port = ssgi::ReadExrFile(options.port);
  const fs::path thresholdsPath = options.thresholds.empty() ? DataFilePath("diff_thresholds.json") : fs::path(options.thresholds);
  const ssgi::DiffThresholds thresholds = ssgi::LoadDiffThresholds(thresholdsPath);
  // The scene's geometry judges coverage differences; without a scene they are compared as values.
  std::optional<ssgi::DumpScene> scene;
  std::optional<ssgi::ViewProjection> view;
  if (!options.scene.empty() || oracle.metadata.count("ssgi:scene")) {
    scene = ssgi::LoadDumpScene(oracle, options.oracle, options.scene);
    view = ssgi::MakePerspective(scene->scene.camera, scene->config.width, scene->config.height);
  }
  std::optional<ssgi::CoverageGeometry> geometry;
  if (scene) geometry.emplace(ssgi::CoverageGeometry{scene->scene.mesh, *view});
  const ssgi::DiffReport report = ssgi::DiffDumps(oracle, port, thresholds, geometry);

  std::printf("%s (port) against %s (oracle), thresholds %s\n", options.port.c_str(), options.oracle.c_str(),
              thresholdsPath.string().c_str());
  std::printf("  %-20s %-14s %10s %12s %10s %9s %7s  %-12s %s\n", "layer", "pass", "max abs", "max ulp", "rmse", "over",
              "edge", "worst", "");
  for (const ssgi::LayerDiff& layer : report.layers) {
    std::printf("  %-20s %-14s", layer.id.c_str(), std::string(ssgi::FramePassName(layer.pass)).c_str());
    if (!layer.compared) {
      std::printf(" %s%s\n", layer.ok ? "not compared: " : "FAIL: ", layer.problem.c_str());
      continue;
    }
    const std::string worst =
        layer.worstX >= 0 ? "(" + std::to_string(layer.worstX) + ", " + std::to_string(layer.worstY) + ")" : "-";
    std::printf(" %10s %12llu %10s %9zu %7zu  %-12s %s%s\n", FormatDifference(layer.maxAbsolute).c_str(),
                static_cast<unsigned long long>(layer.maxUlp), FormatDifference(layer.rmse).c_str(), layer.overTolerance,
                layer.edgePixels, worst.c_str(), layer.ok ? "ok" : "FAIL", layer.problem.empty() ? "" : (": " + layer.problem).c_str());
  }
  size_t compared = 0, absent = 0;
  for (const ssgi::LayerDiff& layer : report.layers) (layer.compared ? compared : absent) += 1;
  std::printf("%zu layers compared, %zu in one file only\n", compared, absent);
  if (report.ok)
    std::printf("verdict: PASS, every compared layer within tolerance\n");
  else
    std::printf("verdict: FAIL, first failing pass: %s\n", std::string(ssgi::FramePassName(*report.firstFailingPass)).c_str());

  if (!options.json.empty()) {
    const std::string text = ssgi::DiffReportJson(report) + "\n";
    std::FILE* file = std::fopen(options.json.c_str(), "w");
    if (!file || std::fputs(text.c_str(), file) < 0 || std::fclose(file) != 0)
      throw ssgi::InputError(options.json, "cannot write the JSON report");
    std::printf("wrote %s\n", options.json.c_str());
  }
  if (!options.heatmaps.empty()) {
    std::error_code error;
    fs::create_directories(options.heatmaps, error);
    if (error) throw ssgi::InputError(options.heatmaps, "cannot create the folder: " + error.message());
    for (const ssgi::LayerDiff& layer : report.layers) {
      if (layer.ok || !layer.compared) continue;
      int width = 0, height = 0;
      const std::vector<uint8_t> heat = ssgi::LayerDiffHeatmap(oracle, port, layer.id, width, height);
      std::string name = layer.id;
      std::replace(name.begin(), name.end(), ':', '_');
      const fs::path path = fs::path(options.heatmaps) / (name + ".png");
      ssgi::WritePng(path, width, height, heat);
      std::printf("wrote %s\n", path.string().c_str());
    }
  }
  return report.ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ssgi: a CPU reference renderer for screen-space global illumination (Yang & Saito): "
               "deferred shading on a packed 128-bit G-buffer, SSABSS soft shadows and Hi-Z cone-traced "
               "screen-space reflections."};
  app.require_subcommand(1);
  RenderOptions render;
  CLI::App* renderCommand = app.add_subcommand("render", "Render a scene (.json) or a bare model (.obj) to an image.");
  renderCommand->add_option("scene", render.scene,
                            "Scene file (.json, see README 'Scene files') or OBJ model (framed automatically, "
                            "default light). Default: the built-in default scene.");
  renderCommand->add_option("-o,--output", render.output,
                            "Output image: .png (8-bit sRGB after exposure and tonemap) or .exr (linear float "
                            "RGB radiance). Default: <scene name>.png in the current folder.");
  renderCommand->add_option("--threads", render.threads, "Worker threads (0 = all hardware threads). The image is "
                                                         "byte-identical for any count.")
      ->check(CLI::Range(0, 1024));
  renderCommand->add_flag("--stats", render.stats, "Print each stage's time in ms and its throughput.");
  renderCommand->add_option("--max-memory", render.maxMemory,
                            "Refuse, before rendering, a frame whose estimated memory exceeds this (e.g. 8G, "
                            "512M). Default: the memory the system has available.");
  renderCommand->add_flag("--explain", render.explain,
                          "Print the frame plan: each effect run or skipped and why, and the share of tiles and "
                          "pixels that need it.");
  renderCommand->add_option("--dump,--dump-gbuffer", render.dumpBuffers,
                            "Also write every buffer of the frame to this multi-part .exr, as named layers in "
                            "pipeline order (docs/pipeline.md 'Dumps'): the oracle's buffers for `ssgi passes` "
                            "and `ssgi diff`.");
  render.settings.Register(*renderCommand);

  FiguresOptions figures;
  CLI::App* figuresCommand = app.add_subcommand(
      "figures", "Render the paper's figures into a folder: albedo.png, direct.png (no shadows), "
                 "direct_shadows.png (SSABSS), gi_board_roughness_{0.0,0.3,0.9}.png (final image, direct + "
                 "indirect), shadow_filters.png (hard | SSPCSS | SSABSS, cropped) and table1.md (frame times).");
  figuresCommand->add_option("folder", figures.folder, "Output folder (created if missing).")->required();
  figuresCommand->add_option("--scene", figures.scene, "Scene file or OBJ. Default: the built-in default scene.");
  figures.settings.Register(*figuresCommand, {"size"});
  figuresCommand->add_option("--threads", figures.threads, "Worker threads (0 = all).")->check(CLI::Range(0, 1024));

  ReferenceOptions reference;
  CLI::App* referenceCommand = app.add_subcommand(
      "reference", "Ray trace the same light transport with Embree: the ground truth for `ssgi compare`.");
  referenceCommand->add_option("scene", reference.scene, "Scene file or OBJ. Default: the built-in default scene.");
  referenceCommand->add_option("-o,--output", reference.output,
                               "Multi-channel EXR: R, G, B (the final image) and result.*, direct.*, indirect.*, "
                               "shadow.visibility, depth (default reference.exr).");
  reference.settings.Register(*referenceCommand, {"size", "background"});
  referenceCommand->add_option("--spp", reference.spp,
                               "Light and bounce samples per pixel (default 64; error falls as 1/sqrt(spp)).")
      ->check(CLI::Range(1, 65536));
  referenceCommand->add_option("--threads", reference.threads, "Worker threads (0 = all). Output is identical for any count.")
      ->check(CLI::Range(0, 1024));

  CompareOptions compare;
  CLI::App* compareCommand = app.add_subcommand(
      "compare", "Compare a test image with a reference: RMSE, PSNR (linear HDR), max error and where, SSIM.");
  compareCommand->add_option("test", compare.test, "Test image (.exr, .png, ...).")->required();
  compareCommand->add_option("reference", compare.reference, "Reference image, same size.")->required();
  compareCommand->add_option("--layer", compare.layer,
                             "Channels to compare in both files: LAYER.R/G/B, or the single channel LAYER "
                             "(e.g. result, direct, indirect, shadow.visibility of a --dump EXR). "
                             "Default: R, G, B.");
  compareCommand->add_option("--heatmap", compare.heatmap, "Write the per-pixel error as a heat map PNG.");
  compareCommand->add_option("--heatmap-scale", compare.heatmapScale,
                             "Error shown as white in the heat map (default: the largest error).");

  PassesOptions passes;
  CLI::App* passesCommand = app.add_subcommand(
      "passes", "Run passes of the pipeline on buffers from outside (a --dump of the oracle, or a GPU port's "
                "buffers in the dump's layer names) and write the frame's buffers as a dump.");
  passesCommand->add_option("input", passes.input, "Dump (.exr) holding the buffers the passes read.")->required();
  passesCommand->add_option("-o,--output", passes.output, "Dump (.exr) to write.")->required();
  passesCommand->add_option("--scene", passes.scene,
                            "Scene file (camera, lights, materials, settings). Default: the scene the dump names.");
  passesCommand->add_option("--from", passes.from,
                            "First pass to run (default gbuffer): " + ssgi::FramePassNames() + ".");
  passesCommand->add_option("--to", passes.to, "Last pass to run (default tonemap).");
  passesCommand->add_option("--threads", passes.threads, "Worker threads (0 = all).")->check(CLI::Range(0, 1024));
  passesCommand->add_flag("--stats", passes.stats, "Print each pass's time.");
  std::string passList = "\nThe passes, in pipeline order:\n";
  for (const ssgi::PassDeclaration& pass : ssgi::FramePasses())
    passList += "  " + std::string(pass.name) + std::string(16 - std::min<size_t>(pass.name.size(), 15), ' ') +
                std::string(pass.summary) + "\n";
  passesCommand->footer(passList);

  DiffOptions diff;
  CLI::App* diffCommand = app.add_subcommand(
      "diff", "Compare a port's dump with the oracle's, layer by layer in pipeline order, against named "
              "tolerances: one line per layer and a verdict naming the first failing pass. Exit 0 pass, 1 fail, "
              "2 usage or unreadable input.");
  diffCommand->add_option("oracle", diff.oracle, "The oracle's dump (ssgi render --dump).")->required();
  diffCommand->add_option("port", diff.port, "The port's dump, in the same layer names.")->required();
  diffCommand->add_option("--thresholds", diff.thresholds,
                          "Tolerances per layer (JSON). Default: data/diff_thresholds.json.");
  diffCommand->add_option("--json", diff.json, "Also write the report as JSON, for CI.");
  diffCommand->add_option("--heatmaps", diff.heatmaps, "Write a heat map PNG of each failing layer into this folder.");
  diffCommand->add_option("--scene", diff.scene,
                          "Scene whose geometry judges coverage differences at triangle edges. Default: the scene "
                          "the oracle's dump names.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "ssgi: error: %s\n", ssgi::cli::DescribeParseError(app, e, argc, argv).c_str());
    return 2;
  }
  try {
    if (*renderCommand) return Render(render);
    if (*figuresCommand) return Figures(figures);
    if (*compareCommand) return Compare(compare);
    if (*referenceCommand) return Reference(reference);
    if (*passesCommand) return Passes(passes);
    if (*diffCommand) {
      try {
        return Diff(diff);
      } catch (const ssgi::InputError& e) {
        // Exit 1 is the verdict "fail": input the diff cannot use is a usage error.
        std::fprintf(stderr, "ssgi: error: %s\n", ssgi::cli::Printable(e.what()).c_str());
        return 2;
      }
    }
  } catch (const ssgi::InputError& e) {
    std::fprintf(stderr, "ssgi: error: %s\n", ssgi::cli::Printable(e.what()).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ssgi: internal error: %s\n", ssgi::cli::Printable(e.what()).c_str());
    return 3;
  }
  return 0;
}
