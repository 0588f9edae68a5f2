// The frame plan (docs/design.md §9: simulate only the effects a scene calls for): after the G-buffer,
// which effects the pixels on screen need. Shadows run only if some visible pixel faces the
// shadow-casting light (elsewhere its term is 0 whatever the visibility); reflections only if some
// visible pixel is smoother than the trace's cut-off (elsewhere the composite adds nothing); the
// sky light only if the environment is not black and some pixel has geometry; the diffuse bounce
// only if something on screen is lit (a light reaches a visible pixel, or the sky light runs):
// otherwise the lit image is black on every surface, so there is nothing to bounce, and no sky
// light to occlude. A skipped effect therefore leaves the image's bytes as they would be with it. `ssgi render
// --explain` prints the plan.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/scene.h"
#include "core/tile_mask.h"
#include "passes/frame/config.h"

namespace ssgi {

struct EffectPlan {
  bool run = false;
  std::string why;      // one line: what decided it
  bool counted = false;  // whether tiles and pixels were counted (shadows: only when asked)
  size_t tiles = 0;     // 32x32 tiles with a pixel that needs the effect
  size_t pixels = 0;    // pixels that need it
};

struct FramePlan {
  size_t tiles = 0;            // 32x32 tiles of the image
  size_t pixels = 0;           // of the image
  size_t geometryPixels = 0;   // pixels with geometry
  std::optional<size_t> shadowLight;  // the light whose term word 3 holds (PrepareLights order)
  EffectPlan shadows;
  EffectPlan reflections;
  EffectPlan sky;
  EffectPlan bounce;
  EffectPlan antialias;  // pixels: those on a geometric edge (when counted)
  // Per light, in PrepareLights order: whether some visible pixel faces it (the direct light's
  // conditions for a non-zero term). The direct light shades only these; the others add exactly 0.
  std::vector<bool> lightReaches;
  size_t directionalLights = 0;  // the first lights of lightReaches; spots follow
  // The tiles with a pixel smoother than the cut-off: the only tiles the trace, the cone and the
  // composite work on (every other pixel of the image has no hit and no indirect light).
  TileMask reflectionTiles;
};

// The plan for the frame of this G-buffer, rendered with `view`. countShadowPixels: count the
// pixels and tiles facing the shadowed light and those on an edge (for --explain) instead of
// stopping at the first.
// edgeCoverage: the G-buffer's edge coverage (empty unless --aa edge).
FramePlan PlanFrame(const Scene& scene, const FrameConfig& config, const GBuffer& gbuffer,
                    const Plane<uint32_t>& edgeCoverage, const ViewProjection& view, bool countShadowPixels = false);

// Per 32x32 tile of row y (tile t holds x in [32t, 32t + 32)): adds the row's pixels with geometry
// (word 2 not the background) to geometry[t] and those of them whose roughness code (word 1's top
// byte) is below smoothCodes to smooth[t].
void CountPlanRowScalar(const uint32_t* word1, const uint32_t* word2, int width, uint32_t smoothCodes,
                        uint32_t* geometry, uint32_t* smooth);
// Its Highway twin (passes/frame/plan_simd.cpp), dispatched to the machine's best target.
void CountPlanRowSimd(const uint32_t* word1, const uint32_t* word2, int width, uint32_t smoothCodes,
                      uint32_t* geometry, uint32_t* smooth);

// The plan as `--explain` prints it: a line per effect, run or skipped and why, with its share of
// tiles and pixels.
std::string ExplainPlan(const FramePlan& plan);

}  // namespace ssgi
