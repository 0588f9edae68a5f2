// `ssgi passes`: passes of the pipeline run on buffers from outside (a dump of the oracle's, or a GPU
// port's in the dump's layer names).
#include <cstdio>
#include <cstring>
#include <memory>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "passes/frame/dump.h"
#include "passes/frame/memory.h"
#include "passes/sky_light.h"

namespace ssgi::cli {
namespace {

struct PassesOptions {
  std::string input;
  std::string scene;
  std::string from = "gbuffer";
  std::string to = "tonemap";
  std::string output;
  int threads = 0;
  bool stats = false;
  std::string maxMemory;
};

// The layers of a dump that passes before `from` write (the catalogue's), by part and channel name:
// the only ones LoadFrameDump reads when the frame runs from `from`, so the others are not read;
// and the sky visibility volume (TakeSkyVolume).
ExrChannelFilter LayersBefore(FramePass from) {
  return [from](const std::string& part, const std::string& name) {
    if (part == DumpPartName(DumpPart::kSkyVolume, 0)) return true;
    for (const DumpLayer& layer : DumpLayers()) {
      if (layer.pass >= from || layer.name != name) continue;
      switch (layer.part) {
        case DumpPart::kImage:
          if (part.empty() || part == DumpPartName(layer.part, 0)) return true;
          break;
        case DumpPart::kShadowMap:
        case DumpPart::kSkyVolume:
        case DumpPart::kBounceHalf:
          if (part == DumpPartName(layer.part, 0)) return true;
          break;
        case DumpPart::kHiZLevels:
        case DumpPart::kPyramidLevels: {
          // "hiz.0" without its level: "hiz.".
          const std::string levels = DumpPartName(layer.part, 0);
          if (part.compare(0, levels.size() - 1, levels, 0, levels.size() - 1) == 0) return true;
          break;
        }
      }
    }
    return false;
  };
}

// The volume is made once per scene and kept while its geometry is the same (docs/pipeline.md §Sky
// light): the dump's, where it holds one of the scene's grid, is the one kept, so that the passes
// light the frame as the dump's maker did (the oracle's own dump: the volume it would build; a
// port's: the port's maps).
void TakeSkyVolume(const ExrFile& dump, const Scene& scene, const FrameConfig& config, Frame& frame) {
  const std::string part = DumpPartName(DumpPart::kSkyVolume, 0);
  const ExrLayer* layer = dump.Find(part, "k");
  if (layer == nullptr || config.skyVisibility.directions == 0) return;
  SkyVisibilityVolume volume = SkyVisibilityGrid(scene, config.skyVisibility);
  if (layer->width != volume.cellsX * 4 || layer->height != volume.cellsY * volume.cellsZ || layer->isUint) return;
  // A layer of the volume's grid, as its coefficients.
  const auto read = [&](const ExrLayer& from, std::vector<float>& coefficients) {
    coefficients.resize(from.samples.size());
    std::memcpy(coefficients.data(), from.samples.data(), from.samples.size() * sizeof(float));
  };
  read(*layer, volume.coefficients);
  volume.meshHash = MeshGeometryHash(scene.mesh);
  // The interreflection volume on its grid, where the dump holds one.
  if (config.interreflection.directions > 0) {
    WorldBounceVolume interreflection = EmptyWorldBounce(scene, volume, config.environment, config.interreflection);
    bool complete = true;
    for (int c = 0; c < 3 && complete; ++c) {
      const ExrLayer* channel = dump.Find(part, std::string("interreflection.") + "RGB"[c]);
      complete =
          channel != nullptr && channel->width == layer->width && channel->height == layer->height && !channel->isUint;
      if (complete) read(*channel, interreflection.coefficients[size_t(c)]);
    }
    if (complete) frame.interreflection = std::move(interreflection);
  }
  frame.skyVolume = std::move(volume);
}

// Runs passes --from .. --to of the frame on the buffers of a dump and writes the frame's buffers as
// a dump.
int Passes(const PassesOptions& options) {
  const ThreadLimit threadLimit(options.threads);
  const FramePass from = ParseFramePass(options.from);
  const FramePass to = ParseFramePass(options.to);
  if (to < from)
    throw UsageError("--to " + options.to + " comes before --from " + options.from + " in the pipeline (" +
                     FramePassNames() + ")");
  CheckInputFile(options.input, "dump");
  if (!options.scene.empty()) CheckInputFile(options.scene, "scene");
  OutputFiles outputs;
  outputs.Add(options.output);
  if (outputs.Kind(options.output) != ImageFileKind::kExr)
    throw InputError(options.output, "the passes' buffers are written as a multi-part EXR: use a .exr name");
  const MemoryBudget budget = BudgetFor(options.maxMemory);
  const ExrChannelFilter read = LayersBefore(from);
  const size_t dumpBytes = ExrSampleBytes(options.input, read);
  CheckMemory("reading " + options.input, dumpBytes, budget, "");
  const ExrFile dump = ReadExrFile(options.input, read);
  const auto [scene, config] = LoadDumpScene(dump, options.input, options.scene);
  // The dump read, and a frame holding every buffer, written as a dump in turn.
  CheckMemory("passes on a " + std::to_string(config.width) + "x" + std::to_string(config.height) + " dump",
              dumpBytes + EstimateFrameMemory(scene, config, BufferLifetime::kKeepAll, true).bytes, budget, "");
  Frame frame;
  LoadFrameDump(dump, options.input, scene, config, from, to, frame);
  TakeSkyVolume(dump, scene, config, frame);
  RunFramePasses(scene, config, from, to, frame);
  const std::string sceneName =
      options.scene.empty() ? dump.metadata.at("ssgi:scene") : fs::absolute(options.scene).string();
  outputs.Write(options.output, [&](const fs::path& path) {
    WriteFrameDump(path, frame, DumpMetadata(sceneName, config));
  });
  outputs.Commit();
  if (options.stats) PrintStats(StageRows(frame.stats), config.width, config.height, ThreadCount(options.threads));
  std::printf("ran %s .. %s on %s\nwrote %s\n", options.from.c_str(), options.to.c_str(), options.input.c_str(),
              options.output.c_str());
  return 0;
}

}  // namespace

Command AddPassesCommand(CLI::App& app) {
  auto options = std::make_shared<PassesOptions>();
  CLI::App* command = app.add_subcommand(
      "passes", "Run passes of the pipeline on buffers from outside (a --dump of the oracle, or a GPU port's buffers "
                "in the dump's layer names) and write the frame's buffers as a dump.");
  command->add_option("input", options->input, "Dump (.exr) holding the buffers the passes read.")->required();
  command->add_option("-o,--output", options->output, "Dump (.exr) to write.")->required();
  command->add_option("--scene", options->scene,
                      "Scene file (camera, lights, materials, settings). Default: the scene the dump names.");
  command->add_option("--from", options->from, "First pass to run (default gbuffer): " + FramePassNames() + ".");
  command->add_option("--to", options->to, "Last pass to run (default tonemap).");
  AddThreadsOption(*command, options->threads, "Worker threads (0 = all).");
  command->add_flag("--stats", options->stats, "Print each pass's time.");
  AddMaxMemoryOption(*command, options->maxMemory);
  std::string passList = "\nThe passes, in pipeline order:\n";
  for (const PassDeclaration& pass : FramePasses())
    passList += "  " + std::string(pass.name) + std::string(16 - std::min<size_t>(pass.name.size(), 15), ' ') +
                std::string(pass.summary) + "\n";
  command->footer(passList);
  return {command, [options] { return Passes(*options); }};
}

}  // namespace ssgi::cli
