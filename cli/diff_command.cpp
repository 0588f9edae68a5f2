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
  CheckInputFile(options.oracle, "oracle dump");
  CheckInputFile(options.port, "port dump");
  const fs::path thresholdsPath =
      options.thresholds.empty() ? DataFilePath("diff_thresholds.json") : fs::path(options.thresholds);
  CheckInputFile(thresholdsPath, "thresholds");
  OutputFiles outputs;
  if (!options.json.empty()) outputs.Add(options.json, true);
  std::optional<CreatedFolder> heatmapFolder;
  if (!options.heatmaps.empty()) heatmapFolder.emplace(options.heatmaps);
  CheckMemory("reading the two dumps", ExrSampleBytes(options.oracle) + ExrSampleBytes(options.port),
              BudgetFor(options.maxMemory));
  const ExrFile oracle = ReadExrFile(options.oracle);
  const ExrFile port = ReadExrFile(options.port);
  const DiffThresholds thresholds = LoadDiffThresholds(thresholdsPath);
  // The scene's geometry judges coverage differences; without a scene they are compared as values.
  std::optional<DumpScene> scene;
  std::optional<ViewProjection> view;
  if (!options.scene.empty() || oracle.metadata.count("ssgi:scene")) {
    scene = LoadDumpScene(oracle, options.oracle, options.scene);
    view = MakePerspective(scene->scene.camera, scene->config.width, scene->config.height);
  }
  std::optional<CoverageGeometry> geometry;
  if (scene) geometry.emplace(CoverageGeometry{scene->scene.mesh, *view});
  const DiffReport report = DiffDumps(oracle, port, thresholds, geometry);

  std::printf("%s (port) against %s (oracle), thresholds %s\n", options.port.c_str(), options.oracle.c_str(),
              thresholdsPath.string().c_str());
  std::printf("  %-20s %-14s %10s %12s %10s %9s %7s  %-12s %s\n", "layer", "pass", "max abs", "max ulp", "rmse", "over",
              "edge", "worst", "");
  for (const LayerDiff& layer : report.layers) {
    std::printf("  %-20s %-14s", layer.id.c_str(), std::string(FramePassName(layer.pass)).c_str());
    if (!layer.compared) {
      std::printf(" %s%s\n", layer.ok ? "not compared: " : "FAIL: ", layer.problem.c_str());
      continue;
    }
    const std::string worst =
        layer.worstX >= 0 ? "(" + std::to_string(layer.worstX) + ", " + std::to_string(layer.worstY) + ")" : "-";
    std::printf(" %10s %12llu %10s %9zu %7zu  %-12s %s%s\n", FormatDifference(layer.maxAbsolute).c_str(),
                static_cast<unsigned long long>(layer.maxUlp), FormatDifference(layer.rmse).c_str(),
                layer.overTolerance, layer.edgePixels, worst.c_str(), layer.ok ? "ok" : "FAIL",
                layer.problem.empty() ? "" : (": " + layer.problem).c_str());
  }
  size_t compared = 0, absent = 0;
  for (const LayerDiff& layer : report.layers) (layer.compared ? compared : absent) += 1;
  std::printf("%zu layers compared, %zu in one file only\n", compared, absent);
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
      "diff", "Compare a port's dump with the oracle's, layer by layer in pipeline order, against named tolerances: "
              "one line per layer and a verdict naming the first failing pass. Exit 0 pass, 1 fail, 2 usage or "
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
