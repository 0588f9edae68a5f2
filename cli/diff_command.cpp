// `ssgi diff`: a port's dump against the oracle's, layer by layer in pipeline order, with one verdict.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/output_files.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "passes/frame/diff.h"
#include "passes/frame/dump.h"

namespace ssgi::cli {
namespace {

struct DiffOptions {
  std::string oracle;
  std::string port;
  std::string thresholds;
  std::string json;
  std::string heatmaps;
  std::string scene;
  std::string maxMemory;
  int threads = 0;
  int subpixelBits = 8;
  bool verbose = false;
};

std::string FormatDifference(double value) {
  if (!std::isfinite(value)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

std::string FormatPercent(double percent) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g%%", percent);
  return text;
}

// What makes a passing layer close to its tolerance (diff.h kCloseShare).
std::string CloseReason(const LayerDiff& layer, const LayerTolerance& tolerance) {
  std::string reason;
  if (layer.toleranceUsed > kCloseShare)
    reason = "a sample uses " + FormatPercent(100.0 * layer.toleranceUsed) + " of the tolerance";
  if (layer.overTolerance > 0 && layer.percentOver > kCloseShare * tolerance.percent)
    reason += (reason.empty() ? "" : ", ") + FormatPercent(layer.percentOver) + " of samples beyond it, " +
              FormatPercent(tolerance.percent) + " allowed";
  return reason;
}

void PrintLayer(const LayerDiff& layer, const DiffThresholds& thresholds) {
  std::printf("  %-20s %-14s", layer.id.c_str(), std::string(FramePassName(layer.pass)).c_str());
  if (!layer.compared) {
    std::printf(" %s%s\n", layer.ok ? "not compared: " : "FAIL: ", layer.problem.c_str());
    return;
  }
  const std::string worst =
      layer.worstX >= 0 ? "(" + std::to_string(layer.worstX) + ", " + std::to_string(layer.worstY) + ")" : "-";
  const std::string ulp = !layer.ulpMeasured ? "-" : layer.maxUlp == UINT64_MAX ? "nan" : std::to_string(layer.maxUlp);
  const std::string verdict = !layer.ok     ? "FAIL" + (layer.problem.empty() ? "" : ": " + layer.problem)
                              : layer.close ? "close: " + CloseReason(layer, thresholds.For(layer.id))
                                            : "ok";
  std::printf(" %10s %12s %10s %9zu %7zu  %-12s %s\n", FormatDifference(layer.maxAbsolute).c_str(), ulp.c_str(),
              FormatDifference(layer.rmse).c_str(), layer.overTolerance, layer.edgePixels, worst.c_str(),
              verdict.c_str());
}

// "a, b, c and 5 more": the first few of a list.
std::string FirstNames(const std::vector<std::string>& names, size_t shown = 8) {
  std::string text;
  for (size_t i = 0; i < std::min(shown, names.size()); ++i) text += (i == 0 ? "" : ", ") + names[i];
  if (names.size() > shown) text += " and " + std::to_string(names.size() - shown) + " more";
  return text;
}

// The counts under the table: compared layers by verdict, layers that could not be compared, and
// layers only one file holds, each on one line.
void PrintSummary(const DiffReport& report, bool verbose) {
  size_t ok = 0, close = 0, failed = 0, typeDiffers = 0, sizeDiffers = 0;
  std::vector<std::string> portOnly, oraclePasses;
  size_t oracleOnly = 0;
  for (const LayerDiff& layer : report.layers) {
    switch (layer.presence) {
      case LayerPresence::kOracleOnly: {
        ++oracleOnly;
        const std::string pass(FramePassName(layer.pass));
        if (std::find(oraclePasses.begin(), oraclePasses.end(), pass) == oraclePasses.end())
          oraclePasses.push_back(pass);
        continue;
      }
      case LayerPresence::kPortOnly:
        portOnly.push_back(layer.id);
        continue;
      case LayerPresence::kBoth:
        break;
    }
    if (layer.typeDiffers) {
      ++typeDiffers;
    } else if (!layer.compared) {
      ++sizeDiffers;
    } else {
      (!layer.ok ? failed : layer.close ? close : ok) += 1;
    }
  }
  std::printf("%s compared: %zu ok, %zu close, %zu FAIL%s\n", CountOf(ok + close + failed, "layer").c_str(), ok, close,
              failed, verbose || ok == 0 ? "" : " (--verbose lists the ok ones)");
  if (typeDiffers + sizeDiffers > 0) {
    std::string line = CountOf(typeDiffers + sizeDiffers, "layer") + " not comparable, failing: ";
    if (typeDiffers > 0) line += CountOf(typeDiffers, "type mismatch", "type mismatches") + " (uint32 against float)";
    if (sizeDiffers > 0)
      line += (typeDiffers > 0 ? ", " : "") + CountOf(sizeDiffers, "size mismatch", "size mismatches");
    std::printf("%s\n", line.c_str());
  }
  if (oracleOnly + portOnly.size() > 0) {
    std::string line = CountOf(oracleOnly, "layer") + " only in the oracle's file";
    if (oracleOnly > 0)
      line += " (" + std::string(oraclePasses.size() == 1 ? "pass " : "passes ") + FirstNames(oraclePasses) + ")";
    line += ", " + std::to_string(portOnly.size()) + " only in the port's";
    if (!portOnly.empty()) line += ": " + FirstNames(portOnly);
    std::printf("%s; not compared\n", line.c_str());
  }
}

// One verdict over all passes: each layer both dumps hold, against its tolerance (docs/pipeline.md
// 'Matching rules'). Exit 0 when every layer is within tolerance, 1 when one is not; 2 for a command
// line or a file that cannot be used.
int Diff(const DiffOptions& options) {
  const ThreadLimit threadLimit(options.threads);
  CheckInputFile(options.oracle, "oracle dump");
  CheckInputFile(options.port, "port dump");
  const fs::path thresholdsPath =
      options.thresholds.empty() ? DataFilePath("diff_thresholds.json") : fs::path(options.thresholds);
  CheckInputFile(thresholdsPath, "thresholds");
  OutputFiles outputs;
  if (!options.json.empty()) outputs.Add(options.json, true);
  std::optional<CreatedFolder> heatmapFolder;
  if (!options.heatmaps.empty()) heatmapFolder.emplace(options.heatmaps);
  const DiffThresholds thresholds = LoadDiffThresholds(thresholdsPath);
  CheckMemory("reading the two dumps", ExrSampleBytes(options.oracle) + ExrSampleBytes(options.port),
              BudgetFor(options.maxMemory));
  // The port's file whole; of the oracle's, the samples of the layers the port also holds.
  const ExrFile port = ReadExrFile(options.port);
  const ExrFile oracle = ReadExrFile(options.oracle, OracleLayersToRead(port));
  // The scene's geometry judges coverage differences; without a scene they are compared as values.
  std::optional<DumpScene> scene;
  std::optional<ViewProjection> view;
  if (!options.scene.empty() || oracle.metadata.count("ssgi:scene")) {
    scene = LoadDumpScene(oracle, options.oracle, options.scene);
    view = MakePerspective(scene->scene.camera, scene->config.width, scene->config.height);
  }
  const std::optional<ViewProjection> shadowView =
      scene ? DiffShadowView(oracle, port, scene->scene, scene->config) : std::nullopt;
  std::optional<CoverageGeometry> geometry;
  if (scene)
    geometry.emplace(CoverageGeometry{scene->scene.mesh, *view, CoverageRounding(options.subpixelBits),
                                      shadowView ? &*shadowView : nullptr});
  const DiffReport report = DiffDumps(oracle, port, thresholds, geometry);

  std::printf("%s (port) against %s (oracle), thresholds %s\n", options.port.c_str(), options.oracle.c_str(),
              thresholdsPath.string().c_str());
  // By default only the layers that need a look: those that fail and those close to failing.
  std::vector<const LayerDiff*> shown;
  for (const LayerDiff& layer : report.layers)
    if (options.verbose || (layer.presence == LayerPresence::kBoth && (!layer.ok || layer.close)))
      shown.push_back(&layer);
  if (!shown.empty()) {
    std::printf("  %-20s %-14s %10s %12s %10s %9s %7s  %-12s %s\n", "layer", "pass", "max abs", "max ulp", "rmse",
                "over", "edge", "worst", "");
    for (const LayerDiff* layer : shown) PrintLayer(*layer, thresholds);
  }
  PrintSummary(report, options.verbose);
  if (report.ok)
    std::printf("verdict: PASS, every compared layer within tolerance\n");
  else
    std::printf("verdict: FAIL, first failing pass: %s\n", std::string(FramePassName(*report.firstFailingPass)).c_str());

  if (!options.json.empty()) {
    outputs.Write(options.json, [&](const fs::path& path) {
      std::ofstream file(path, std::ios::binary | std::ios::trunc);
      file << DiffReportJson(report) << "\n";
      file.close();
      if (!file) throw InputError(path, "cannot write the JSON report");
    });
  }
  std::vector<fs::path> written;
  if (heatmapFolder) {
    for (const LayerDiff& layer : report.layers) {
      if (layer.ok || !layer.compared) continue;
      int width = 0, height = 0;
      const std::vector<uint8_t> heat = LayerDiffHeatmap(oracle, port, layer.id, width, height);
      std::string name = layer.id;
      std::replace(name.begin(), name.end(), ':', '_');
      const fs::path path = fs::path(options.heatmaps) / (name + ".png");
      outputs.Add(path);
      outputs.Write(path, [&](const fs::path& temporary) { WritePng(temporary, width, height, heat); });
      written.push_back(path);
    }
  }
  outputs.Commit();
  if (heatmapFolder) heatmapFolder->Keep();
  if (!options.json.empty()) std::printf("wrote %s\n", options.json.c_str());
  for (const fs::path& path : written) std::printf("wrote %s\n", path.string().c_str());
  return report.ok ? 0 : 1;
}

}  // namespace

Command AddDiffCommand(CLI::App& app) {
  auto options = std::make_shared<DiffOptions>();
  CLI::App* command = app.add_subcommand(
      "diff",
      "Compare a port's dump with the oracle's, layer by layer in pipeline order, against named tolerances: "
      "a line per layer that fails or is close to its tolerance, the counts, and a verdict naming the first failing "
      "pass. Exit 0 pass, 1 fail, 2 usage or "
      "unreadable input.");
  command->add_option("oracle", options->oracle, "The oracle's dump (ssgi render --dump).")->required();
  command->add_option("port", options->port, "The port's dump, in the same layer names.")->required();
  command->add_option("--thresholds", options->thresholds,
                      "Tolerances per layer (JSON). Default: data/diff_thresholds.json.");
  command->add_option("--json", options->json, "Also write the report as JSON, for CI.");
  command->add_option("--heatmaps", options->heatmaps, "Write a heat map PNG of each failing layer into this folder.");
  command->add_option("--scene", options->scene,
                      "Scene whose geometry judges coverage differences at triangle edges. Default: the scene the "
                      "oracle's dump names.");
  command
      ->add_option("--subpixel-bits", options->subpixelBits,
                   "The port's rasterizer's sub-pixel precision (GL_SUBPIXEL_BITS): a pixel whose centre lies "
                   "within two of its sub-pixel steps of a triangle edge may be covered differently. Default: 8.")
      ->check(CLI::Range(1, 16));
  command->add_flag("-v,--verbose", options->verbose,
                    "Print every layer; by default only those that fail or are close to their tolerance (over half "
                    "of it used).");
  AddThreadsOption(*command, options->threads, "Worker threads (0 = all); the report is the same at any count.");
  AddMaxMemoryOption(*command, options->maxMemory);
  return {command, [options] {
            try {
              return Diff(*options);
            } catch (const InputError& e) {
              // Exit 1 is the verdict "fail": input the diff cannot use is a usage error.
              throw UsageError(e.what());
            }
          }};
}

}  // namespace ssgi::cli
