// `ssgi reference`: the Embree ground truth of a scene, with the buffers `ssgi compare` pairs with a
// render's dump.
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

namespace ssgi::cli {
namespace {

struct ReferenceOptions {
  std::string scene;
  std::string output = "reference.exr";
  SettingOptions settings;
  int spp = 64;
  int threads = 0;
  std::string maxMemory;
};

// The Embree ground truth (docs/design.md §10): one EXR holding the final image as R, G, B and the
// matching buffers under the names --dump uses, so `ssgi compare --layer` pairs them.
int Reference(const ReferenceOptions& options) {
  const ThreadLimit threadLimit(options.threads);
  const fs::path scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  CheckInputFile(scenePath, "scene");
  OutputFiles outputs;
  outputs.Add(options.output);
  if (outputs.Kind(options.output) != ImageFileKind::kExr)
    throw InputError(options.output, "the reference is written as a multi-channel EXR: use a .exr name");
  const auto [scene, config] = LoadSceneAndConfig(scenePath, options.settings);
  ReferenceParams params = ReferenceParamsForSpp(options.spp);
  params.width = config.width;
  params.height = config.height;
  params.environment = {EnvironmentKind::kConstant, config.directLight.background};
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
  outputs.Commit();
  std::printf("reference %dx%d, %d spp: %.1f ms (%zu rays, BVH %.1f ms, %s)\nwrote %s\n", config.width,
              config.height, options.spp, ms, size_t(ref.stats.rays), ref.stats.buildMs,
              FormatBytes(ref.stats.bvhBytes).c_str(), options.output.c_str());
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
  options->settings.Register(*command, {"size", "background"});
  command->add_option("--spp", options->spp, "Light and bounce samples per pixel (default 64; error falls as 1/sqrt(spp)).")
      ->check(CLI::Range(1, 65536));
  AddThreadsOption(*command, options->threads, "Worker threads (0 = all). Output is identical for any count.");
  AddMaxMemoryOption(*command, options->maxMemory);
  return {command, [options] { return Reference(*options); }};
}

}  // namespace ssgi::cli
