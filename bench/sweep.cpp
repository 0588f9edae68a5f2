// "What accuracy costs in time" (docs/design.md §10): renders a scene under a list of quality settings,
// measures each pass's median time over repeated frames and the final image's error against a
// reference image (normally `ssgi reference`'s), and writes one CSV row per setting. Plot it with
// bench/plot_sweep.py; bench/README.md says how.
//
//   ssgi_sweep --reference ref.exr [--scene scene.json] [--size 512x512] [--repeats 5] -o sweep.csv
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/gbuffer.h"
#include "core/image_compare.h"
#include "core/parallel.h"
#include "core/plane.h"
#include "passes/frame/frame.h"

namespace {

namespace fs = std::filesystem;

struct Setting {
  std::string knob;   // which knob this row varies ("baseline" for the defaults)
  std::string value;  // its value, as text
  // Render at this fraction of the reference's size, then resample to it (bilinear) for the error.
  double scale = 1.0;
};

// The quality presets, then one knob at a time around the defaults (the axes the presets are
// chosen from), all from the frame settings table, then the resolution rows.
std::vector<Setting> Settings() {
  std::vector<Setting> settings{{"baseline", "defaults"}};
  for (const ssgi::QualityPreset& preset : ssgi::QualityPresets())
    settings.push_back({"preset", std::string(preset.name)});
  for (const ssgi::FrameSetting& knob : ssgi::FrameSettings())
    for (std::string_view value : knob.sweep) settings.push_back({std::string(knob.name), std::string(value)});
  for (double scale : {0.5, 0.75}) settings.push_back({"resolution", std::to_string(int(scale * 100)) + "%", scale});
  return settings;
}

// The setting's frame configuration on top of the scene file's.
ssgi::FrameConfig Configure(const Setting& setting, ssgi::FrameConfig config, int width, int height) {
  if (setting.knob == "preset") ssgi::ApplySetting(config, "quality", setting.value);
  if (ssgi::FindFrameSetting(setting.knob)) ssgi::ApplySetting(config, setting.knob, setting.value);
  config.width = std::max(1, int(std::lround(width * setting.scale)));
  config.height = std::max(1, int(std::lround(height * setting.scale)));
  return config;
}

// One channel per plane: a single one is "Y", three are "R", "G", "B".
ssgi::FloatImage ToFloatImage(const std::vector<const ssgi::Plane<float>*>& planes) {
  ssgi::FloatImage image;
  image.width = int(planes[0]->xsize());
  image.height = int(planes[0]->ysize());
  image.channelNames = planes.size() == 1 ? std::vector<std::string>{"Y"} : std::vector<std::string>{"R", "G", "B"};
  const size_t n = planes.size();
  image.pixels.resize(size_t(image.width) * size_t(image.height) * n);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (size_t c = 0; c < n; ++c) image.pixels[(size_t(y) * image.width + x) * n + c] = planes[c]->ConstRow(y)[x];
  return image;
}

ssgi::FloatImage ToFloatImage(const ssgi::Plane3<float>& rgb) { return ToFloatImage({&rgb.c[0], &rgb.c[1], &rgb.c[2]}); }

// The error of `image` against `reference`, resampled to the reference's size first when the
// setting rendered smaller.
ssgi::ImageDifference ErrorAgainst(ssgi::FloatImage image, const ssgi::FloatImage& reference) {
  if (image.width != reference.width || image.height != reference.height)
    image = ssgi::ResizeImage(image, reference.width, reference.height);
  return ssgi::CompareImages(image, reference);
}

// The frame's own depth, roughness and (with shadows) visibility, as ClassifyRegions reads a dump.
ssgi::FloatImage RegionLayers(const ssgi::Frame& frame) {
  const ssgi::GBuffer& g = frame.gbuffer.gbuffer;
  ssgi::FloatImage image;
  image.width = g.width();
  image.height = g.height();
  image.channelNames = {"depth", "roughness"};
  const bool shadows = frame.shadows && frame.shadowVisibility.visibility.xsize() == size_t(g.width());
  if (shadows) image.channelNames.push_back("shadow.visibility");
  const size_t n = image.channelNames.size();
  image.pixels.resize(size_t(image.width) * size_t(image.height) * n);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float* p = &image.pixels[(size_t(y) * image.width + x) * n];
      p[0] = ssgi::UnpackDepth(g.word[ssgi::GBufferWord::kDepth].ConstRow(y)[x]);
      p[1] = ssgi::UnpackRoughness(g.word[ssgi::GBufferWord::kNormalRoughness].ConstRow(y)[x]);
      if (shadows) p[2] = frame.shadowVisibility.visibility.ConstRow(y)[x];
    }
  return image;
}

// Edges of the roughness bins of the reflective region's error.
constexpr double kRoughnessBins[] = {0.0, 0.1, 0.2, 0.35, 0.5, 0.7};

// The display RMSE of `image` against `reference` over the reflective pixels of `classes` in each
// roughness bin (layers' channel 1, RegionLayers); NaN-free: 0 for an empty bin.
std::vector<double> ReflectiveErrorByRoughness(const ssgi::FloatImage& image, const ssgi::FloatImage& reference,
                                               const std::vector<uint8_t>& classes, const ssgi::FloatImage& layers) {
  std::vector<double> errors;
  const size_t channels = layers.Channels();
  for (size_t b = 0; b + 1 < std::size(kRoughnessBins); ++b) {
    std::vector<uint8_t> bin(classes.size(), 0);
    for (size_t i = 0; i < classes.size(); ++i) {
      const double roughness = layers.pixels[i * channels + 1];
      if ((classes[i] & ssgi::kRegionReflective) && roughness >= kRoughnessBins[b] && roughness < kRoughnessBins[b + 1])
        bin[i] = ssgi::kRegionReflective;
    }
    for (const ssgi::RegionDifference& d : ssgi::CompareRegions(image, reference, bin))
      if (d.region == ssgi::kRegionReflective) errors.push_back(d.rmseDisplay);
  }
  return errors;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

int Run(const std::string& scenePath, const std::string& referencePath, int width, int height, int repeats, int threads,
        const std::vector<std::string>& knobs, const std::vector<std::string>& sets, const std::string& output) {
  ssgi::RetainFreedMemory();
  const ssgi::ThreadLimit limit(threads);
  const ssgi::FloatImage referenceFile = ssgi::ReadFloatImage(referencePath);
  const ssgi::FloatImage reference = ssgi::SelectLayer(referenceFile, "", referencePath);
  // Per-pass ground truth, present in `ssgi reference` output: the shadow filter's visibility and
  // the SSR's indirect light.
  const std::optional<ssgi::FloatImage> referenceVisibility = ssgi::FindLayer(referenceFile, "shadow.visibility");
  const std::optional<ssgi::FloatImage> referenceIndirect = ssgi::FindLayer(referenceFile, "indirect");
  if (reference.width != width || reference.height != height)
    throw ssgi::InputError(referencePath, "is " + std::to_string(reference.width) + "x" +
                                              std::to_string(reference.height) + ", the sweep renders " +
                                              std::to_string(width) + "x" + std::to_string(height));
  const std::vector<Setting> settings = Settings();
  for (const std::string& knob : knobs)
    if (std::none_of(settings.begin(), settings.end(), [&](const Setting& s) { return s.knob == knob; }))
      throw ssgi::InputError("--knobs", "no knob '" + knob + "' (the CSV's knob column names them)");
  const ssgi::SceneFile loaded = ssgi::LoadSceneFile(scenePath);
  ssgi::FrameConfig sceneConfig = ssgi::FrameConfigFromSceneFile(loaded);
  // --set: on every row, before its own knob.
  for (const std::string& set : sets) {
    const size_t equals = set.find('=');
    if (equals == std::string::npos) throw ssgi::InputError("--set: '" + set + "' is not NAME=VALUE");
    ssgi::ApplySetting(sceneConfig, std::string_view(set).substr(0, equals), std::string_view(set).substr(equals + 1));
  }
  std::ofstream csv(output);
  if (!csv) throw ssgi::InputError(output, "cannot write");
  // rmse_visibility: linear RMSE of the filtered light visibility against the traced one (blank when
  // no shadows ran); rmse_display_indirect: display RMSE of the indirect light against the traced
  // bounce (blank when no reflections ran).
  // Per region of the frame's pixels (lit, in shadow, reflective, background; blank for the
  // resolution rows): the display RMSE and the mean test / reference ratio.
  csv << "knob,value,frame_ms,rmse,rmse_display,psnr_db,ssim,max_error,rmse_visibility,rmse_display_indirect";
  const char* regionColumns[] = {"lit", "shadow", "reflective", "background"};
  for (const char* region : regionColumns) csv << ",rmse_display_" << region << ",ratio_" << region;
  // The reflective region by the pixels' roughness: where sharing rays or fewer steps cost accuracy.
  for (size_t b = 0; b + 1 < std::size(kRoughnessBins); ++b)
    csv << ",rmse_display_reflective_r" << kRoughnessBins[b] << "-" << kRoughnessBins[b + 1];
  std::vector<std::string> stages;
  // Every frame is rendered into this one's buffers, as a running renderer renders: what a scene
  // makes once (the sky visibility volume, the environment's tables) is kept while it holds, and
  // one discarded frame first keeps the process's first touch of every buffer out of the times.
  ssgi::Frame frame;
  const auto render = [&](const ssgi::FrameConfig& config) {
    ssgi::RunFramePasses(loaded.scene, config, ssgi::FramePass::kGBuffer, ssgi::FramePass::kTonemap, frame);
  };
  render(Configure(settings.front(), sceneConfig, width, height));
  for (const Setting& setting : settings) {
    if (!knobs.empty() && std::find(knobs.begin(), knobs.end(), setting.knob) == knobs.end()) continue;
    const ssgi::FrameConfig config = Configure(setting, sceneConfig, width, height);
    std::map<std::string, std::vector<double>> times;
    ssgi::ImageDifference difference;
    std::string visibilityError, indirectError;
    std::vector<ssgi::RegionDifference> regions;
    std::vector<double> reflectiveByRoughness;
    for (int r = 0; r < repeats; ++r) {
      render(config);
      const std::vector<ssgi::StageStats> rows = ssgi::StageRows(frame.stats);
      for (const ssgi::StageStats& s : rows) times[s.name].push_back(s.ms);
      if (r == 0) {
        difference = ErrorAgainst(ToFloatImage(frame.Result()), reference);
        if (frame.shadowMap && referenceVisibility)
          visibilityError =
              std::to_string(ErrorAgainst(ToFloatImage({&frame.shadowVisibility.visibility}), *referenceVisibility).rmse);
        if (frame.reflections && referenceIndirect)
          indirectError =
              std::to_string(ErrorAgainst(ToFloatImage(frame.composite.indirect), *referenceIndirect).rmseDisplay);
        if (setting.scale == 1.0) {
          const ssgi::FloatImage layers = RegionLayers(frame);
          const std::vector<uint8_t> classes =
              ssgi::ClassifyRegions(layers, config.ssrTrace.roughnessCutoff, scenePath);
          const ssgi::FloatImage result = ToFloatImage(frame.Result());
          regions = ssgi::CompareRegions(result, reference, classes);
          reflectiveByRoughness = ReflectiveErrorByRoughness(result, reference, classes, layers);
        }
      }
      if (stages.empty()) {
        for (const ssgi::StageStats& s : rows) stages.push_back(s.name);
        for (const std::string& name : stages) csv << ",ms " << name;
        csv << "\n";
      }
    }
    csv << setting.knob << "," << setting.value << "," << Median(times["frame total"]) << "," << difference.rmse << ","
        << difference.rmseDisplay << "," << difference.psnr << "," << difference.ssim << "," << difference.maxError
        << "," << visibilityError << "," << indirectError;
    for (size_t r = 0; r < std::size(regionColumns); ++r) {
      if (regions.empty())
        csv << ",,";
      else
        csv << "," << regions[r].rmseDisplay << "," << regions[r].meanRatio;
    }
    for (size_t b = 0; b + 1 < std::size(kRoughnessBins); ++b) {
      csv << ",";
      if (!reflectiveByRoughness.empty()) csv << reflectiveByRoughness[b];
    }
    for (const std::string& name : stages) csv << "," << (times.count(name) ? Median(times[name]) : 0.0);
    csv << "\n";
    std::printf("%-16s %-8s %8.1f ms  RMSE %.5f  display RMSE %.5f  SSIM %.4f  visibility RMSE %-8s  indirect "
                "display RMSE %s\n",
                setting.knob.c_str(), setting.value.c_str(), Median(times["frame total"]), difference.rmse,
                difference.rmseDisplay, difference.ssim, visibilityError.c_str(), indirectError.c_str());
  }
  std::printf("wrote %s\n", output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ssgi_sweep: time and error against a reference for each quality setting, as CSV."};
  std::string scene = SSGI_SOURCE_DATA_DIR "/default.json", reference, output = "sweep.csv", size = "512x512";
  int repeats = 5, threads = 2;
  app.add_option("--scene", scene, "Scene file (default: the built-in default scene).");
  app.add_option("--reference", reference, "Reference image (RGB linear EXR of the same size).")->required();
  app.add_option("--size", size, "Image size WIDTHxHEIGHT (default 512x512); must match the reference.");
  app.add_option("--repeats", repeats, "Frames per setting; times are medians (default 5).")->check(CLI::Range(1, 100));
  app.add_option("--threads", threads, "Worker threads (default 2).")->check(CLI::Range(0, 1024));
  std::vector<std::string> knobs;
  app.add_option("--knobs", knobs, "Only these rows, by knob name (baseline, preset, ssr_iterations, ...); "
                                   "default: all.")
      ->delimiter(',');
  std::vector<std::string> sets;
  app.add_option("--set", sets, "NAME=VALUE: a frame setting for every row (e.g. effects.sky=off), repeatable.");
  app.add_option("-o,--output", output, "CSV file to write (default sweep.csv).");
  CLI11_PARSE(app, argc, argv);
  try {
    ssgi::FrameConfig sized;
    ssgi::ApplySetting(sized, "size", size);  // the table's check and its "--size: ..." message
    return Run(scene, reference, sized.width, sized.height, repeats, threads, knobs, sets, output);
  } catch (const ssgi::InputError& e) {
    std::fprintf(stderr, "ssgi_sweep: error: %s\n", e.what());
    return 1;
  }
}
