// The frame, as one straight script (DESIGN.md §1): it owns every buffer and runs the passes in
// order, each a free function with typed inputs and outputs. A pass the scene does not need is not
// run (DESIGN.md §9).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/plane.h"
#include "core/scene.h"
#include "passes/direct_light.h"
#include "passes/gbuffer.h"
#include "passes/tonemap.h"

namespace ssgi {

// One row of `--stats`: a stage's wall time and what it processed.
struct StageStats {
  std::string name;
  double ms = 0.0;
  double items = 0.0;      // triangles or pixels processed, 0 when not meaningful
  std::string itemUnit;    // "triangles", "pixels"
};

struct Frame {
  ViewProjection view;
  GBufferOutputs gbuffer;
  DirectLightOutputs direct;
  TonemapOutputs display;  // 8-bit sRGB of the final image
  std::vector<StageStats> stats;

  // The final linear HDR image: result = direct (+ indirect once a pass provides it).
  const Plane3<float>& Result() const { return direct.radiance; }
};

// Renders the scene at scene.settings' size and options.
Frame RenderFrame(const Scene& scene);

// Writes every intermediate buffer of the frame into one multi-channel EXR for oracle comparisons:
// the raw G-buffer words as uint32 ("gbuffer.word0".."gbuffer.word3"), their decoded values
// ("albedo.R/G/B", "metallic", "normal.X/Y/Z" view space, "roughness", "depth" in metres with the
// background +inf, "shadow.hard", "shadow.blocker"), the visibility buffer ("raster.depthKey",
// "raster.triangle" uint32, 0xFFFFFFFF = none) and the direct light ("direct.R/G/B").
void WriteFrameBuffers(const std::filesystem::path& path, const Frame& frame, NormalEncoding encoding);

}  // namespace ssgi
