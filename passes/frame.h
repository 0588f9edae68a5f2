// The frame, as one straight script (DESIGN.md §1): it owns every buffer and runs the passes in
// order, each a free function with typed inputs and outputs. A pass the scene does not need is not
// run (DESIGN.md §9).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/plane.h"
#include "core/scene.h"
#include "passes/color_pyramid.h"
#include "passes/composite.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "passes/hiz.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"
#include "passes/ssr_cone.h"
#include "passes/ssr_trace.h"
#include "passes/tonemap.h"

namespace ssgi {

// One row of `--stats`: a stage's wall time and what it processed.
struct StageStats {
  std::string name;
  double ms = 0.0;
  double items = 0.0;      // triangles or pixels processed, 0 when not meaningful
  std::string itemUnit;    // "triangles", "pixels"
};

// Pass parameters that are not part of a scene: quality knobs and comparison modes.
struct FrameOptions {
  ShadowMapParams shadowMap;
  ShadowFilterParams shadowFilter;
  SsrTraceParams ssrTrace;
  SsrConeParams ssrCone;
};

// Quality presets (README "Accuracy and time"), chosen from the sweep's measured Pareto fronts on
// the default scene and Sponza: each knob is cut where the time it saves costs least error. kHigh
// is FrameOptions' defaults (the paper's settings); kUltra adds what still lowered the error (the
// shadow map's resolution above all); knobs that bought nothing measurable stay at the defaults.
enum class Quality { kLow, kMedium, kHigh, kUltra };
FrameOptions QualityPreset(Quality quality);
// "low", "medium", "high", "ultra"; anything else throws InputError naming --quality.
Quality ParseQuality(const std::string& name);

struct Frame {
  ViewProjection view;
  GBufferOutputs gbuffer;
  // Present when the scene has a shadow-casting light and shadows are not switched off: the first
  // such light's shadow map (its term is G-buffer word 3) and its filtered visibility.
  std::optional<ShadowMapOutputs> shadowMap;
  ShadowFilterOutputs shadowVisibility;
  size_t shadowTiles = 0, shadowTilesBlurred = 0;  // blur-area control: tiles in the image, tiles blurred
  DirectLightOutputs direct;
  // Present when the scene has a surface smooth enough to reflect and reflections are not off.
  bool reflections = false;
  HiZ hiz;
  ColorPyramid colorPyramid;
  SsrTraceOutputs ssrTrace;
  SsrConeOutputs ssrCone;
  CompositeOutputs composite;
  size_t ssrTiles = 0, ssrTilesTraced = 0;  // 32x32 tiles in the image, tiles with a traced ray
  size_t ssrRays = 0;
  double ssrMeanIterations = 0.0;
  TonemapOutputs display;  // 8-bit sRGB of the final image
  std::vector<StageStats> stats;

  // The final linear HDR image: result = direct + indirect (direct alone without reflections).
  const Plane3<float>& Result() const { return reflections ? composite.result : direct.radiance; }
};

// Whether the scene calls for screen-space reflections: some material smooth enough to be traced
// (roughness below the trace's cut-off, or a roughness texture that may make it so).
bool SceneReflects(const Scene& scene, float roughnessCutoff);

// Renders the scene at scene.settings' size and options.
Frame RenderFrame(const Scene& scene, const FrameOptions& options);

// The G-buffer's albedo as 8-bit sRGB RGB rows (background black): the paper's "albedo" image.
std::vector<uint8_t> AlbedoImage(const GBuffer& gbuffer);

// Writes every intermediate buffer of the frame into one multi-channel EXR for oracle comparisons:
// the raw G-buffer words as uint32 ("gbuffer.word0".."gbuffer.word3"), their decoded values
// ("albedo.R/G/B", "metallic", "normal.X/Y/Z" view space, "roughness", "depth" in metres with the
// background +inf, "shadow.hard", "shadow.blocker"), the visibility buffer ("raster.depthKey",
// "raster.triangle" uint32, 0xFFFFFFFF = none), the filtered light visibility ("shadow.visibility",
// when shadows ran), the direct light ("direct.R/G/B") and, when reflections ran, the trace
// ("ssr.hitX", "ssr.hitY", "ssr.confidence"), the cone-traced radiance ("ssr.reflected.R/G/B"), the
// indirect light ("indirect.R/G/B") and the result ("result.R/G/B").
void WriteFrameBuffers(const std::filesystem::path& path, const Frame& frame, NormalEncoding encoding);

}  // namespace ssgi
