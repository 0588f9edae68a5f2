// `ssgi compare`: error metrics of a test image against a reference.
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "core/error.h"
#include "core/image_compare.h"
#include "core/image_io.h"
#include "passes/ssr_trace.h"

namespace ssgi::cli {
namespace {

struct CompareOptions {
  std::string test;
  std::string reference;
  std::string layer;
  std::string heatmap;
  double heatmapScale = 0.0;
  std::string regions;
};

// Error of a test image against a reference (docs/design.md §10): RMSE and PSNR on linear values, the
// largest error and where, and mean SSIM of the tonemapped luminance as the perceptual score.
int Compare(const CompareOptions& options) {
  CheckInputFile(options.test, "test image");
  CheckInputFile(options.reference, "reference image");
  if (!options.regions.empty()) CheckInputFile(options.regions, "regions dump");
  OutputFiles outputs;
  if (!options.heatmap.empty()) {
    outputs.Add(options.heatmap);
    if (outputs.Kind(options.heatmap) != ImageFileKind::kPng)
      throw InputError(options.heatmap, "--heatmap writes a PNG: use a .png name");
  }
  const FloatImage testFile = ReadFloatImage(options.test);
  const FloatImage referenceFile = ReadFloatImage(options.reference);
  const FloatImage test = SelectLayer(testFile, options.layer, options.test);
  const FloatImage reference = SelectLayer(referenceFile, options.layer, options.reference);
  if (test.width != reference.width || test.height != reference.height || test.Channels() != reference.Channels())
    throw InputError(options.test, "is " + std::to_string(test.width) + "x" + std::to_string(test.height) + " with " +
                                       CountOf(test.Channels(), "channel") + ", the reference " +
                                       std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                                       " with " + std::to_string(reference.Channels()));
  if (testFile.integerCodes != referenceFile.integerCodes) {
    const std::string& coded = testFile.integerCodes ? options.test : options.reference;
    std::fprintf(stderr,
                 "ssgi: warning: %s holds integer codes (8-bit sRGB, as a PNG) and the other image linear values: "
                 "the metrics compare unlike quantities; compare an .exr render, or a dump's layer\n",
                 coded.c_str());
  }
  const ImageDifference d = CompareImages(test, reference);
  std::printf("%s vs %s (layer %s: %dx%d, %s)\n", options.test.c_str(), options.reference.c_str(),
              options.layer.empty() ? "RGB" : options.layer.c_str(), test.width, test.height,
              CountOf(test.Channels(), "channel").c_str());
  std::printf("  RMSE       %.6g (linear), %.6g (of x/(1+x))\n", d.rmse, d.rmseDisplay);
  std::printf("  PSNR       %.2f dB (peak %.6g, the reference's largest value)\n", d.psnr, d.peak);
  std::printf("  max error  %.6g at (%d, %d)\n", d.maxError, d.maxX, d.maxY);
  std::printf("  SSIM       %.5f (mean SSIM of x/(1+x) tonemapped luminance; FLIP has no Debian 12 package)\n", d.ssim);
  if (d.nonFinite > 0) std::printf("  non-finite %s (excluded)\n", CountOf(d.nonFinite, "sample").c_str());
  // By region, where a frame's dump says which pixel is which: the test's own, or --regions.
  std::optional<FloatImage> regionsFile;
  if (!options.regions.empty()) regionsFile = ReadFloatImage(options.regions);
  const FloatImage& regionSource = regionsFile ? *regionsFile : testFile;
  if (regionsFile || (FindLayer(testFile, "depth") && FindLayer(testFile, "roughness"))) {
    if (regionSource.width != test.width || regionSource.height != test.height)
      throw InputError(options.regions, "is not the images' size");
    const std::vector<uint8_t> regions =
        ClassifyRegions(regionSource, SsrTraceParams().roughnessCutoff, regionsFile ? options.regions : options.test);
    std::printf("  by region (%s):\n  %-12s %8s %12s %14s %14s\n",
                FindLayer(regionSource, "shadow.visibility") ? "shadow.visibility, roughness, depth"
                                                             : "no shadows: every covered pixel lit",
                "region", "pixels", "RMSE", "display RMSE", "mean test/ref");
    for (const RegionDifference& r : CompareRegions(test, reference, regions))
      std::printf("  %-12s %8zu %12.6g %14.6g %14.4g\n", ImageRegionName(r.region), r.pixels, r.rmse, r.rmseDisplay,
                  r.meanRatio);
  }
  if (!options.heatmap.empty()) {
    const Heatmap map = ErrorHeatmap(test, reference, options.heatmapScale);
    outputs.Write(options.heatmap, [&](const fs::path& path) { WritePng(path, map.width, map.height, map.rgb); });
    outputs.Commit();
    std::printf("wrote %s: per-pixel error, black 0 to white %.4g (%s; %.2f%% of the pixels above it); the "
                "legend below the map\n",
                options.heatmap.c_str(), map.scale,
                options.heatmapScale > 0.0 ? "--heatmap-scale" : "the 99th percentile of the error",
                100.0 * map.shareAboveScale);
  }
  return 0;
}

}  // namespace

Command AddCompareCommand(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* command = app.add_subcommand(
      "compare", "Compare a test image with a reference: RMSE, PSNR (linear HDR), max error and where, SSIM.");
  command->add_option("test", options->test, "Test image (.exr, .png, ...).")->required();
  command->add_option("reference", options->reference, "Reference image, same size.")->required();
  command->add_option("--layer", options->layer,
                      "Channels to compare in both files: LAYER.R/G/B, or the single channel LAYER (e.g. result, "
                      "direct, indirect, shadow.visibility of a --dump EXR). Default: R, G, B.");
  command->add_option("--heatmap", options->heatmap,
                      "Write the per-pixel error as a heat map PNG, with a legend of its scale below it.");
  command->add_option("--heatmap-scale", options->heatmapScale,
                      "Error shown as white in the heat map (default: the 99th percentile of the error).")
      ->check(CLI::PositiveNumber);
  command->add_option("--regions", options->regions,
                      "A --dump of the test's frame whose depth, roughness and shadow.visibility say which pixels are "
                      "lit, in shadow, reflective or background; the error is then also given per region. Default: "
                      "the test file itself when it is a dump.");
  return {command, [options] { return Compare(*options); }};
}

}  // namespace ssgi::cli
