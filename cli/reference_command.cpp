// `ssgi reference`: the Embree ground truth of a scene, with the buffers `ssgi compare` pairs with a
// render's dump.
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/reference/reference.h"
#include "core/stopwatch.h"
#include "passes/tonemap.h"

namespace ssgi::cli {
namespace {

struct ReferenceOptions {
  std::string scene;
  std::string output = "reference.exr";
  std::string png;  // also the final image as the frame's PNG, when given
  SettingOptions settings;
  int spp = 64;
  std::string transport = "full";
  int bounces = kDefaultReferenceBounces;
  CLI::Option* bouncesOption = nullptr;
  bool pixelCentre = false;
  uint32_t seed = 0;
  int threads = 0;
  std::string maxMemory;
};

// The Embree ground truth (docs/design.md §10): one EXR holding the final image as R, G, B and the
// matching buffers under the names --dump uses, so `ssgi compare --layer` pairs them.
int Reference(const ReferenceOptions& options) {
  const bool paper = options.transport == "paper";
  // The paper transport has neither knob: refused rather than ignored.
  if (paper && options.bouncesOption->count() > 0)
    throw UsageError("--bounces: the paper transport has one specular bounce; give --transport full");
  if (paper && options.pixelCentre)
    throw UsageError("--pixel-centre: the paper transport always traces the pixel centre; give --transport full");
  const ThreadLimit threadLimit(options.threads);
  const fs::path scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  CheckInputFile(scenePath, "scene");
  OutputFiles outputs;
  outputs.Add(options.output);
  if (outputs.Kind(options.output) != ImageFileKind::kExr)
    throw InputError(options.output,
                     "the reference is written as a multi-channel EXR: use a .exr name (and --png for a picture)");
  if (!options.png.empty()) {
    outputs.Add(options.png);
    if (outputs.Kind(options.png) != ImageFileKind::kPng)
      throw InputError(options.png, "--png writes an 8-bit PNG: use a .png name");
  }
  const auto [scene, config] = LoadSceneAndConfig(scenePath, options.settings);
  ReferenceParams params =
      ReferenceParamsForSpp(options.spp, paper ? ReferenceTransport::kPaper : ReferenceTransport::kFull);
  params.bounces = options.bounces;
  params.pixelCentre = options.pixelCentre;
  params.seed = options.seed;
  params.width = config.width;
  params.height = config.height;
  params.environment = config.environment;
  CheckMemory("a " + std::to_string(config.width) + "x" + std::to_string(config.height) + " reference",
              EstimateReferenceMemory(scene, params), BudgetFor(options.maxMemory), "give a smaller --size");

  Stopwatch stopwatch;
  ReferenceOutputs ref;
  {
    Progress progress("reference");
    ref = RenderReference(scene, params, [&](size_t done, size_t rows) {
      progress.Update(double(done) / double(rows), CountOf(done, "row") + " of " + std::to_string(rows));
    });
  }
  const double ms = stopwatch.Lap();
  std::vector<ExrChannel> channels;
  const auto add = [&](const std::string& name, const Plane<float>& plane) {
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
  outputs.Write(options.output,
                [&](const fs::path& path) { WriteExr(path, config.width, config.height, channels); });
  if (!options.png.empty()) {
    // The display curve `ssgi render` gives the frame, so the two pictures compare by eye.
    TonemapOutputs display;
    RunTonemap(ref.result, config.tonemap, display);
    outputs.Write(options.png, [&](const fs::path& path) { WritePng(path, config.width, config.height, display.rgb); });
  }
  outputs.Commit();
  // The cost of one sample of one pixel, over every pixel (background ones too): what --spp and
  // --size multiply.
  const double samples = double(config.width) * double(config.height) * double(options.spp);
  std::printf(
      "reference %dx%d, %s transport, %d spp: %.1f ms, %.3g us per sample per pixel (%zu rays, BVH %.1f ms, %s)\n",
      config.width, config.height, paper ? "paper" : "full", options.spp, ms, ref.stats.traceMs * 1000.0 / samples,
      size_t(ref.stats.rays), ref.stats.buildMs, FormatBytes(ref.stats.bvhBytes).c_str());
  if (!paper) {
    // The Monte Carlo noise: the root mean over covered pixels and channels of each pixel's
    // estimated variance, the standard error of one pixel of `result`.
    double sum = 0.0;
    size_t count = 0;
    for (size_t y = 0; y < ref.depth.ysize(); ++y) {
      for (size_t x = 0; x < ref.depth.xsize(); ++x) {
        if (!(ref.depth.ConstRow(y)[x] < kBackgroundDepth)) continue;
        for (int c = 0; c < 3; ++c) sum += double(ref.resultVariance.c[c].ConstRow(y)[x]);
        count += 3;
      }
    }
    std::printf("noise: standard error %.3g (root mean variance of result over %zu covered pixels)\n",
                count > 0 ? std::sqrt(sum / double(count)) : 0.0, count / 3);
  }
  std::printf("wrote %s\n", options.output.c_str());
  return 0;
}

}  // namespace

Command AddReferenceCommand(CLI::App& app) {
  auto options = std::make_shared<ReferenceOptions>();
  CLI::App* command = app.add_subcommand(
      "reference", "Ray trace the same light transport with Embree: the ground truth for `ssgi compare`.");
  command->add_option("scene", options->scene, "Scene file or OBJ. Default: the built-in default scene.");
  command->add_option("-o,--output", options->output,
                      "Multi-channel EXR: R, G, B (the final image) and result.*, direct.*, indirect.*, "
                      "shadow.visibility, depth (default reference.exr).");
  command->add_option("--png", options->png,
                      "Also write the final image as a PNG with the scene's exposure and tonemap, as `ssgi render` "
                      "writes the frame's.");
  options->settings.Register(*command, {"size", "background", "exposure_ev", "tonemap"});
  command
      ->add_option("--transport", options->transport,
                   "full (default): path tracing of all light transport, the ground truth; paper: direct light and "
                   "one specular bounce of it, what the screen-space pipeline models (docs/user-guide.md).")
      ->check(CLI::IsMember({"full", "paper"}));
  command
      ->add_option("--spp", options->spp,
                   "Samples per pixel: paths (full), or light and bounce samples (paper). Default 64; the error "
                   "falls as 1/sqrt(spp).")
      ->check(CLI::Range(1, 65536));
  options->bouncesOption =
      command
          ->add_option("--bounces", options->bounces,
                       "Full transport: reflections after the first hit (default " +
                           std::to_string(kDefaultReferenceBounces) + "; 0 = direct and environment light only).")
          ->check(CLI::Range(0, 1024));
  command->add_flag("--pixel-centre", options->pixelCentre,
                    "Full transport: every path through the pixel centre (no antialiasing), for per-pixel metrics "
                    "against a --dump.");
  command->add_option("--seed", options->seed,
                      "Selects the sample streams (default 0): two seeds give independent noise, so the difference "
                      "of two references measures it.");
  AddThreadsOption(*command, options->threads, "Worker threads (0 = all). Output is identical for any count.");
  AddMaxMemoryOption(*command, options->maxMemory);
  return {command, [options] { return Reference(*options); }};
}

}  // namespace ssgi::cli
