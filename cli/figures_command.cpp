// `ssgi figures`: the paper's image sequence for one scene and its Table 1 of frame times.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "passes/frame/memory.h"

namespace ssgi::cli {
namespace {

struct FiguresOptions {
  std::string folder;
  std::string scene;
  int threads = 0;
  std::string maxMemory;
  SettingOptions settings;
};

// Table 1's rows: the frame times of the paper's three configurations (the effects the paper does
// not have, the sky light and the diffuse bounce, switched off), and of every effect in `auto` (the sky
// light with its interreflection volume, which stands for the bounce).
struct TableRow {
  const char* name;
  EffectMode shadows, reflections, sky, bounce;
  const char* paperMs;  // the paper's RTX 2080 Ti
};
constexpr TableRow kTableRows[] = {
    {"direct only", EffectMode::kOff, EffectMode::kOff, EffectMode::kOff, EffectMode::kOff, "15.08"},
    {"+ shadows", EffectMode::kAuto, EffectMode::kOff, EffectMode::kOff, EffectMode::kOff, "15.79"},
    {"+ shadows + GI", EffectMode::kAuto, EffectMode::kAuto, EffectMode::kOff, EffectMode::kOff, "16.69"},
    {"+ sky light and interreflection", EffectMode::kAuto, EffectMode::kAuto, EffectMode::kAuto, EffectMode::kAuto,
     "-"}};
constexpr int kTableRepeats = 5;
constexpr float kBoardRoughness[] = {0.0f, 0.3f, 0.9f};

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
// Every file appears in the folder only once all are written.
int Figures(const FiguresOptions& options) {
  RetainFreedMemory();  // Table 1 times frames rendered one after another, like a running renderer
  const ThreadLimit threadLimit(options.threads);
  const int threads = ThreadCount(options.threads);
  const fs::path scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  CheckInputFile(scenePath, "scene");
  auto [scene, config] = LoadSceneAndConfig(scenePath, options.settings);
  const int width = config.width, height = config.height;
  std::vector<Material*> board;
  for (Material& m : scene.materials)
    if (m.name == "board_light" || m.name == "board_dark") board.push_back(&m);

  const fs::path folder(options.folder);
  CreatedFolder created(folder);
  OutputFiles outputs;
  std::vector<std::string> giNames;
  if (board.empty()) giNames.push_back("gi.png");
  for (float roughness : board.empty() ? std::vector<float>{} : std::vector<float>(std::begin(kBoardRoughness),
                                                                                  std::end(kBoardRoughness))) {
    char name[64];
    std::snprintf(name, sizeof(name), "gi_board_roughness_%.1f.png", double(roughness));
    giNames.push_back(name);
  }
  for (const char* name : {"albedo.png", "direct.png", "direct_shadows.png", "shadow_filters.png"})
    outputs.Add(folder / name);
  for (const std::string& name : giNames) outputs.Add(folder / name);
  outputs.Add(folder / "table1.md", true);

  // At most one frame with every buffer at a time, the 8-bit images of the figures, and a
  // reused frame for the table.
  FrameConfig everything = config;
  everything.shadows = EffectMode::kAuto;
  everything.reflections = EffectMode::kAuto;
  const size_t images = (4 + giNames.size() + 3) * size_t(width) * size_t(height) * 3;
  CheckMemory("figures of " + std::to_string(width) + "x" + std::to_string(height),
              EstimateFrameMemory(scene, everything, BufferLifetime::kKeepAll).bytes + images,
              BudgetFor(options.maxMemory), "give a smaller --size");

  Progress progress("figures");
  const double renders = double(3 + 1 + giNames.size() + std::size(kTableRows) * kTableRepeats);
  double rendered = 0.0;
  const auto configure = [&](EffectMode shadows, EffectMode reflections, ShadowFilter filter) {
    // The paper's figures show its pipeline: the effects it does not have stay off.
    FrameConfig figure = config;
    figure.shadows = shadows;
    figure.reflections = reflections;
    figure.sky = EffectMode::kOff;
    figure.bounce = EffectMode::kOff;
    figure.shadowFilter.filter = filter;
    return figure;
  };
  // The figures keep only the 8-bit images of their frames.
  const auto display = [&](EffectMode shadows, EffectMode reflections, ShadowFilter filter,
                           std::vector<uint8_t>* albedo = nullptr) {
    Frame frame = RenderFrame(scene, configure(shadows, reflections, filter));
    if (albedo) *albedo = AlbedoImage(frame.gbuffer.gbuffer);
    progress.Update(++rendered / renders, "figures");
    return std::move(frame.display.rgb);
  };
  const auto write = [&](const std::string& name, int w, int h, const std::vector<uint8_t>& rgb) {
    outputs.Write(folder / name, [&](const fs::path& path) { WritePng(path, w, h, rgb); });
  };
  std::vector<uint8_t> albedo;
  write("direct.png", width, height, display(EffectMode::kOff, EffectMode::kOff, ShadowFilter::kSsabss, &albedo));
  write("albedo.png", width, height, albedo);
  const std::vector<uint8_t> hard = display(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kHard);
  const std::vector<uint8_t> sspcss = display(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kSspcss);
  const std::vector<uint8_t> ssabss = display(EffectMode::kAuto, EffectMode::kOff, ShadowFilter::kSsabss);
  write("direct_shadows.png", width, height, ssabss);
  // The crop of the default scene's blue sphere and its shadow on the board, as fractions of the image.
  const int x0 = int(0.30 * width), y0 = int(0.55 * height);
  const int cropWidth = std::max(1, int(0.30 * width)), cropHeight = std::max(1, int(0.22 * height));
  int stripWidth = 0;
  const std::vector<uint8_t> strip =
      SideBySide({&hard, &sspcss, &ssabss}, width, x0, y0, cropWidth, cropHeight, stripWidth);
  write("shadow_filters.png", stripWidth, cropHeight, strip);

  std::vector<float> sceneRoughness;
  for (const Material* m : board) sceneRoughness.push_back(m->roughness);
  for (size_t i = 0; i < giNames.size(); ++i) {
    if (!board.empty())
      for (Material* m : board) m->roughness = kBoardRoughness[i];
    write(giNames[i], width, height, display(EffectMode::kAuto, EffectMode::kAuto, ShadowFilter::kSsabss));
  }
  // Table 1 times the scene as it is, not as the last figure left it.
  for (size_t i = 0; i < board.size(); ++i) board[i]->roughness = sceneRoughness[i];

  // Table 1: median frame time over repeated renders of each configuration, each frame rendered into
  // the last one's buffers, as a running renderer renders.
  std::string table = "| " + std::to_string(width) + "x" + std::to_string(height) + ", " +
                      CountOf(size_t(threads), "thread") + " | frame time (median of " +
                      std::to_string(kTableRepeats) + ", ms) | paper, RTX 2080 Ti (ms) |\n|---|---|---|\n";
  for (const TableRow& row : kTableRows) {
    FrameConfig rowConfig = configure(row.shadows, row.reflections, ShadowFilter::kSsabss);
    rowConfig.sky = row.sky;
    rowConfig.bounce = row.bounce;
    Frame frame;
    std::vector<double> times;
    for (int i = 0; i < kTableRepeats; ++i) {
      RunFramePasses(scene, rowConfig, FramePass::kGBuffer, FramePass::kTonemap, frame,
                     BufferLifetime::kKeepForReuse);
      times.push_back(frame.stats.totalMs);
      progress.Update(++rendered / renders, "Table 1");
    }
    std::sort(times.begin(), times.end());
    char line[160];
    std::snprintf(line, sizeof(line), "| %s | %.1f | %s |\n", row.name, times[kTableRepeats / 2], row.paperMs);
    table += line;
  }
  outputs.Write(folder / "table1.md", [&](const fs::path& path) {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file << table;
    file.close();
    if (!file) throw InputError(path, "cannot write the table");
  });
  outputs.Commit();
  created.Keep();
  std::printf("%s", table.c_str());
  for (const char* name : {"albedo.png", "direct.png", "direct_shadows.png", "shadow_filters.png"})
    std::printf("wrote %s\n", (folder / name).string().c_str());
  for (const std::string& name : giNames) std::printf("wrote %s\n", (folder / name).string().c_str());
  std::printf("wrote %s\n", (folder / "table1.md").string().c_str());
  return 0;
}

}  // namespace

Command AddFiguresCommand(CLI::App& app) {
  auto options = std::make_shared<FiguresOptions>();
  CLI::App* command = app.add_subcommand(
      "figures", "Render the paper's figures into a folder: albedo.png, direct.png (no shadows), "
                 "direct_shadows.png (SSABSS), gi_board_roughness_{0.0,0.3,0.9}.png (final image, direct + "
                 "indirect), shadow_filters.png (hard | SSPCSS | SSABSS, cropped) and table1.md (frame times). "
                 "The files appear together once all are written.");
  command->add_option("folder", options->folder, "Output folder (created if missing).")->required();
  command->add_option("--scene", options->scene, "Scene file or OBJ. Default: the built-in default scene.");
  options->settings.Register(*command, {"size"});
  AddThreadsOption(*command, options->threads, "Worker threads (0 = all).");
  AddMaxMemoryOption(*command, options->maxMemory);
  return {command, [options] { return Figures(*options); }};
}

}  // namespace ssgi::cli
