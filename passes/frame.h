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
#include "passes/frame_config.h"
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

// What each pass of a frame did, as the passes report it; a pass that did not run is absent.
struct FrameStats {
  GBufferStats gbuffer;
  std::optional<ShadowMapStats> shadowMap;
  std::optional<ShadowFilterStats> shadowFilter;
  DirectLightStats directLight;
  std::optional<HiZStats> hiz;
  std::optional<ColorPyramidStats> colorPyramid;
  std::optional<SsrTraceStats> ssrTrace;
  std::optional<SsrConeStats> ssrCone;
  std::optional<CompositeStats> composite;
  TonemapStats tonemap;
  double totalMs = 0.0;
  size_t triangles = 0;  // submitted to the G-buffer raster
  size_t pixels = 0;     // of the image
};

// One stage of FrameStats as a row of a table (`--stats`, the sweep's CSV columns): its wall time
// and what it processed.
struct StageStats {
  std::string name;
  double ms = 0.0;
  double items = 0.0;    // what it processed, in itemUnit
  std::string itemUnit;  // "triangles", "pixels", "texels", "rays"
};
// The stages that ran, in pipeline order, ending with "frame total".
std::vector<StageStats> StageRows(const FrameStats& stats);

struct Frame {
  ViewProjection view;
  GBufferOutputs gbuffer;
  // Present when the scene has a shadow-casting light and shadows are not switched off: the first
  // such light's shadow map (its term is G-buffer word 3) and its filtered visibility.
  std::optional<ShadowMapOutputs> shadowMap;
  ShadowFilterOutputs shadowVisibility;
  DirectLightOutputs direct;
  // Present when the scene has a surface smooth enough to reflect and reflections are not off.
  bool reflections = false;
  HiZ hiz;
  ColorPyramid colorPyramid;
  SsrTraceOutputs ssrTrace;
  SsrConeOutputs ssrCone;
  CompositeOutputs composite;
  TonemapOutputs display;  // 8-bit sRGB of the final image
  FrameStats stats;

  // The final linear HDR image: result = direct + indirect (direct alone without reflections).
  const Plane3<float>& Result() const { return reflections ? composite.result : direct.radiance; }
};

// Whether the scene calls for screen-space reflections: some material smooth enough to be traced
// (roughness below the trace's cut-off, or a roughness texture that may make it so).
bool SceneReflects(const Scene& scene, float roughnessCutoff);

// Renders the scene as the configuration says.
Frame RenderFrame(const Scene& scene, const FrameConfig& config);

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
void WriteFrameBuffers(const std::filesystem::path& path, const Frame& frame);

}  // namespace ssgi
