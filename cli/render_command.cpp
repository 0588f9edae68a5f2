// `ssgi render`: a scene to an image, and optionally every buffer of its frame as a dump.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/stopwatch.h"
#include "passes/frame/dump.h"
#include "passes/frame/memory.h"

namespace ssgi::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string output;
  CLI::Option* outputOption = nullptr;
  int threads = 0;
  bool stats = false;
  bool explain = false;
  std::string maxMemory;
  std::string dumpBuffers;
  SettingOptions settings;
};

void PrintMemory(size_t before, size_t estimate, size_t framePeak, size_t fileBacked, int width, int height) {
  // The process before the frame (most of it the shared libraries OpenImageIO loads) is a fixed
  // cost; what grows with the image is the frame's own share.
  const size_t peak = PeakResidentBytes();
  const size_t frameBytes = peak > before ? peak - before : 0;
  const double pixels = double(width) * double(height);
  std::printf("memory: peak %s resident (%.1f bytes per pixel), the frame's %s (%.1f bytes per pixel); "
              "estimate %s (%s before the frame + %s of buffers)\n",
              FormatBytes(peak).c_str(), double(peak) / pixels, FormatBytes(frameBytes).c_str(),
              double(frameBytes) / pixels, FormatBytes(before + estimate).c_str(), FormatBytes(before).c_str(),
              FormatBytes(estimate).c_str());
  std::printf("  of the peak, %s anonymous (%.1f bytes per pixel) and %s file-backed: library code, which the "
              "kernel can drop and read again\n",
              FormatBytes(framePeak - fileBacked).c_str(), double(framePeak - fileBacked) / pixels,
              FormatBytes(fileBacked).c_str());
}

int Render(const RenderOptions& options) {
  const ThreadLimit threadLimit(options.threads);
  const int threads = ThreadCount(options.threads);
  const fs::path scenePath = options.scene.empty() ? DefaultScenePath() : fs::path(options.scene);
  if (options.outputOption->count() > 0 && options.output.empty()) throw InputError("-o: the output file name is empty");
  const bool defaultOutput = options.output.empty();
  const fs::path output = defaultOutput ? fs::path(scenePath.stem().string() + ".png") : fs::path(options.output);
  // Every check that can fail before the (possibly long) render: the outputs' names and folders.
  CheckInputFile(scenePath, "scene");
  OutputFiles outputs;
  outputs.Add(output);
  if (!options.dumpBuffers.empty()) {
    outputs.Add(options.dumpBuffers);
    if (outputs.Kind(options.dumpBuffers) != ImageFileKind::kExr)
      throw InputError(options.dumpBuffers, "--dump writes a multi-part EXR: use a .exr name");
  }

  Stopwatch load;
  const auto [scene, config] = LoadSceneAndConfig(scenePath, options.settings);
  const double loadMs = load.Lap();

  // Refused before anything is allocated, rather than ending in bad_alloc or the OOM killer.
  const size_t before = ResidentBytes();
  // Without a dump, each buffer lives only until its last reader.
  const BufferLifetime lifetime =
      options.dumpBuffers.empty() ? BufferLifetime::kUntilLastReader : BufferLifetime::kKeepAll;
  const FrameMemoryEstimate memory = EstimateFrameMemory(scene, config, lifetime, !options.dumpBuffers.empty());
  const std::string size = std::to_string(config.width) + "x" + std::to_string(config.height);
  CheckMemory("a " + size + " frame", memory.bytes, BudgetFor(options.maxMemory),
              "render smaller or set a smaller --shadow-map-size");

  Frame frame;
  {
    Progress progress("render " + size);
    const size_t steps = FrameSteps().size();
    size_t done = 0;
    RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime,
                   [&](FramePass pass, const Frame&) {
                     progress.Update(double(++done) / double(steps), std::string(FramePassName(pass)));
                   });
  }
  // What of the frame's peak the kernel could not have reclaimed: the file-backed pages (library
  // code) change little after start-up, so the peak less them is the anonymous peak.
  const size_t framePeak = PeakResidentBytes();
  const size_t fileBacked = std::min(ResidentFileBytes(), framePeak);
  if (frame.plan.geometryPixels == 0)
    std::fprintf(stderr, "ssgi: warning: %s: no triangle covers a pixel (zero-area, behind the camera or out of "
                         "view): the image is the background\n",
                 scenePath.string().c_str());

  Stopwatch write;
  const int w = config.width, h = config.height;
  outputs.Write(output, [&](const fs::path& path) {
    if (outputs.Kind(output) == ImageFileKind::kPng) {
      WritePng(path, w, h, frame.display.rgb);
    } else {
      const Plane3<float>& result = frame.Result();
      WriteExr(path, w, h,
               {{"R", false, result.c[0].ConstRow(0), size_t(result.c[0].PixelsPerRow())},
                {"G", false, result.c[1].ConstRow(0), size_t(result.c[1].PixelsPerRow())},
                {"B", false, result.c[2].ConstRow(0), size_t(result.c[2].PixelsPerRow())}});
    }
  });
  if (!options.dumpBuffers.empty()) {
    outputs.Write(options.dumpBuffers, [&](const fs::path& path) {
      WriteFrameDump(path, frame, DumpMetadata(fs::absolute(scenePath).string(), config));
    });
  }
  outputs.Commit();
  const double writeMs = write.Lap();

  if (options.explain) {
    // Freeing early, the frame has let its edge coverage go after the anti-aliasing: the plan counts
    // the edge pixels of a G-buffer pass of the same view again, which writes the same words.
    const Plane<uint32_t>* edgeCoverage = &frame.gbuffer.edgeCoverage;
    GBufferOutputs again;
    if (config.antialiasing == Antialiasing::kEdge && edgeCoverage->xsize() == 0) {
      RunGBuffer({scene, frame.view}, {config.normalEncoding, true, config.specularAaKappa}, again);
      edgeCoverage = &again.edgeCoverage;
    }
    std::printf("%s",
                ExplainPlan(PlanFrame(scene, config, frame.gbuffer.gbuffer, *edgeCoverage, frame.view, true)).c_str());
  }
  if (options.stats) {
    std::printf("%s, load %.1f ms\n", DescribeScene(scenePath, scene).c_str(), loadMs);
    if (scene.reorientedTriangles > 0)
      std::printf("  %s wound against their neighbours turned to match\n",
                  CountOf(scene.reorientedTriangles, "triangle").c_str());
    PrintStats(StageRows(frame.stats), w, h, threads);
    if (const auto& f = frame.stats.shadowFilter; f && f->tiles > 0)
      std::printf("  shadow blur ran on %zu of %zu tiles (%.1f%%)\n", f->tilesBlurred, f->tiles,
                  100.0 * double(f->tilesBlurred) / double(f->tiles));
    if (const auto& t = frame.stats.ssrTrace)
      std::printf("  ssr traced %zu rays (%.1f Hi-Z steps each) in %zu of %zu tiles (%.1f%%)\n", t->rays,
                  t->meanIterations, t->tilesTraced, t->tiles, 100.0 * double(t->tilesTraced) / double(t->tiles));
    std::printf("  %-20s %10.3f\n", "write image", writeMs);
    PrintMemory(before, memory.bytes, framePeak, fileBacked, w, h);
  }
  if (!options.dumpBuffers.empty()) std::printf("wrote %s\n", options.dumpBuffers.c_str());
  if (defaultOutput && outputs.Existed(output))
    std::printf("wrote %s, over the file of that name that was there\n", output.string().c_str());
  else
    std::printf("wrote %s\n", output.string().c_str());
  return 0;
}

}  // namespace

Command AddRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* command = app.add_subcommand("render", "Render a scene (.json) or a bare model (.obj) to an image.");
  command->add_option("scene", options->scene,
                      "Scene file (.json, see docs/user-guide.md 'Scene files') or OBJ model (framed automatically, "
                      "default light). Default: the built-in default scene.");
  options->outputOption =
      command->add_option("-o,--output", options->output,
                          "Output image: .png (8-bit sRGB after exposure and tonemap) or .exr (linear float RGB "
                          "radiance). Default: <scene name>.png in the current folder.");
  AddThreadsOption(*command, options->threads,
                   "Worker threads (0 = all hardware threads). The image is byte-identical for any count.");
  command->add_flag("--stats", options->stats, "Print each stage's time in ms and its throughput.");
  AddMaxMemoryOption(*command, options->maxMemory);
  command->add_flag("--explain", options->explain,
                    "Print the frame plan: each effect run or skipped and why, and the share of tiles and pixels "
                    "that need it.");
  command->add_option("--dump,--dump-gbuffer", options->dumpBuffers,
                      "Also write every buffer of the frame to this multi-part .exr, as named layers in pipeline "
                      "order (docs/pipeline.md 'Dumps'): the oracle's buffers for `ssgi passes` and `ssgi diff`.");
  options->settings.Register(*command);
  return {command, [options] { return Render(*options); }};
}

}  // namespace ssgi::cli
