// The frame, as one straight script (docs/design.md §1): it owns every buffer and runs the passes in
// order, each a free function with typed inputs and outputs. A pass the scene does not need is not
// run (docs/design.md §9).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/camera.h"
#include "core/plane.h"
#include "core/scene.h"
#include "passes/antialias.h"
#include "passes/bounce.h"
#include "passes/color_pyramid.h"
#include "passes/composite.h"
#include "passes/direct_light.h"
#include "passes/frame/config.h"
#include "passes/frame/plan.h"
#include "passes/frame/registry.h"
#include "passes/gbuffer.h"
#include "passes/hiz.h"
#include "passes/mlaa.h"
#include "passes/shadow_filter.h"
#include "passes/shadow_map.h"
#include "passes/sky_light.h"
#include "passes/ssr_cone.h"
#include "passes/ssr_trace.h"
#include "passes/tonemap.h"

namespace ssgi {

// What each pass of a frame did, as the passes report it; a pass that did not run is absent.
struct FrameStats {
  std::optional<GBufferStats> gbuffer;
  std::optional<ShadowMapStats> shadowMap;
  std::optional<ShadowFilterStats> shadowFilter;
  std::optional<DirectLightStats> directLight;
  std::optional<SkyLightStats> skyLight;
  std::optional<double> skyVisibilityMs;  // made this frame (a kept frame keeps it for its scene)
  std::optional<double> interreflectionMs;  // likewise
  std::optional<BounceStats> bounce;
  std::optional<HiZStats> hiz;
  std::optional<ColorPyramidStats> colorPyramid;
  std::optional<SsrTraceStats> ssrTrace;
  std::optional<SsrConeStats> ssrCone;
  std::optional<CompositeStats> composite;
  std::optional<MlaaStats> mlaa;
  std::optional<AntialiasStats> antialias;
  std::optional<TonemapStats> tonemap;
  double planMs = 0.0;  // PlanFrame: it runs in every frame, after the G-buffer pass or its dump
  double totalMs = 0.0;
  size_t triangles = 0;  // submitted to the G-buffer raster
  size_t pixels = 0;     // of the image
};

// The stages that ran, in pipeline order (each pass's rows in the registry), ending with "frame total".
std::vector<StageStats> StageRows(const FrameStats& stats);

// Every pass, in pipeline order.
inline constexpr FramePass kFramePasses[] = {
    FramePass::kGBuffer,   FramePass::kShadowMap, FramePass::kShadowFilter, FramePass::kDirectLight,
    FramePass::kSkyLight,  FramePass::kBounce,    FramePass::kHiZ,          FramePass::kColorPyramid,
    FramePass::kSsrTrace,  FramePass::kSsrCone,   FramePass::kComposite,    FramePass::kMlaa,
    FramePass::kAntialias, FramePass::kTonemap};
// The pass's registry name: "gbuffer", "shadow_map", ..., "tonemap".
std::string_view FramePassName(FramePass pass);
// The pass of that name; throws InputError listing the names for any other.
FramePass ParseFramePass(std::string_view name);
// The pass names in pipeline order, comma separated: for help texts and messages.
std::string FramePassNames();

// Whether `effect`'s passes belong to a frame with these effects on (kIndirect: any of the three
// that feed the composite).
bool EffectBelongs(FrameEffect effect, bool shadows, bool reflections, bool sky, bool bounce, bool antialias);

struct Frame {
  ViewProjection view;
  GBufferOutputs gbuffer;
  FramePlan plan;  // which effects the G-buffer's pixels need
  // Present when the scene has a shadow-casting light and shadows are not switched off: the first
  // such light's shadow map (its term is G-buffer word 3) and its filtered visibility.
  std::optional<ShadowMapOutputs> shadowMap;
  // Whether the shadow passes belong to this frame and G-buffer word 3 holds their term: the shadow
  // map ran, or the frame started after it from a dump.
  bool shadows = false;
  ShadowFilterOutputs shadowVisibility;
  DirectLightOutputs direct;
  // Whether the sky light belongs to this frame (the environment is not black).
  bool sky = false;
  EnvironmentLighting environment;               // the frame's environment, as the passes read it
  std::optional<SkyVisibilityVolume> skyVolume;  // the scene's, kept while its geometry is the same
  // The scene's interreflection on the volume's grid, kept while the scene, its lights and the
  // environment are the same.
  std::optional<WorldBounceVolume> interreflection;
  SkyLightOutputs skyLight;
  // Whether the diffuse bounce belongs to this frame (something on screen is lit), and its outputs.
  bool bounce = false;
  BounceOutputs diffuseBounce;
  // Present when the scene has a surface smooth enough to reflect and reflections are not off.
  bool reflections = false;
  HiZ hiz;
  ColorPyramid colorPyramid;
  SsrTraceOutputs ssrTrace;
  SsrConeOutputs ssrCone;
  CompositeOutputs composite;
  // Whether the anti-aliasing belongs to this frame (it is on and some pixel lies on an edge, or
  // with --aa mlaa some pixel has geometry), the morphological pass's buffers (--aa mlaa), and the
  // anti-aliased image: empty when it works in place on the result (BufferLifetime::kUntilLastReader).
  bool antialias = false;
  MlaaOutputs mlaa;
  Plane3<float> antialiased;
  TonemapOutputs display;  // 8-bit sRGB of the final image
  FrameStats stats;

  // Whether the effect's passes belong to this frame.
  bool Has(FrameEffect effect) const { return EffectBelongs(effect, shadows, reflections, sky, bounce, antialias); }
  // The image the colour pyramid and the composite read: lit = direct + the sky's diffuse light, or
  // the direct light without the sky light.
  const Plane3<float>& Lit() const { return sky ? skyLight.lit : direct.radiance; }
  // The final linear HDR image: result = lit + indirect (the direct light alone without reflections,
  // sky light and bounce), anti-aliased when the anti-aliasing ran into its own buffer.
  const Plane3<float>& Result() const {
    if (antialias && antialiased.c[0].xsize() > 0) return antialiased;
    return Composed();
  }
  // The image before the anti-aliasing (after it where it works in place).
  const Plane3<float>& Composed() const { return Has(FrameEffect::kIndirect) ? composite.result : direct.radiance; }
  Plane3<float>& MutableComposed() { return Has(FrameEffect::kIndirect) ? composite.result : direct.radiance; }
};

// How long a frame keeps its buffers.
enum class BufferLifetime {
  kKeepAll,          // to the frame's end: for dumps, tests and the benchmarks of single passes
  // To the frame's end, for the next frame to render into, as a running renderer keeps them.
  // Buffers are handed on as kUntilLastReader hands them (the direct image is the colour pyramid's
  // level 0, the composite works in place), the pyramid holds only what the cone trace reads, and
  // the trace and the cone trace leave the tiles without a smooth pixel as they were: after the
  // frame only Result() and the display image are defined among the reflection passes' buffers (a
  // dump needs kKeepAll).
  kKeepForReuse,
  // Each buffer freed once its last reader has run (passes/frame/memory.h gives the schedule): only
  // G-buffer words 0-2, the final image (Result) and the display image outlive the frame's passes.
  kUntilLastReader,
};

// What a pass's step (PassDeclaration::step) works with: the frame being rendered and how.
struct FrameStep {
  const Scene& scene;
  const FrameConfig& config;
  Frame& frame;
  BufferLifetime lifetime;
  FramePass from, to;

  // Whether the pass is in the run's range (a step may still hand buffers on around a pass it does
  // not run).
  bool Runs(FramePass pass) const { return from <= pass && pass <= to; }
  // No dump reads the frame's buffers: they are freed, or kept for the next frame to render into.
  bool Undumped() const { return lifetime != BufferLifetime::kKeepAll; }
  bool Releases() const { return lifetime == BufferLifetime::kUntilLastReader; }
  // Whether the direct image is the colour pyramid's level 0 while the pyramid is made and read.
  bool DirectInPyramid() const { return Undumped() && Runs(FramePass::kColorPyramid); }
  // Whether the trace and the cone trace leave the tiles without a smooth pixel as they were: the
  // cone trace and the composite in place read neither there.
  bool LeavesSkippedTiles() const { return Undumped() && Runs(FramePass::kComposite); }
  // Whether the composite writes over the direct image and the reflection.
  bool ComposesInPlace() const {
    return Releases() || (lifetime == BufferLifetime::kKeepForReuse && Runs(FramePass::kComposite));
  }
};

// Renders the scene as the configuration says.
Frame RenderFrame(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime = BufferLifetime::kKeepAll);

// Runs the passes from `from` to `to` (inclusive, pipeline order) of the frame RenderFrame would
// render, on a frame whose buffers that those passes read from earlier passes are filled already
// (LoadFrameDump in passes/frame/dump.h). Which passes belong to the frame (shadows, reflections) is
// the frame plan's decision on the G-buffer (passes/frame/plan.h); a pass that does not belong is
// skipped. frame.stats holds the passes that ran.
// observer, when given, sees the frame after each step (FrameSteps) and before the buffers whose last
// reader that step was are freed: the lifetime test weighs what the frame holds there.
using FrameStepObserver = std::function<void(FramePass step, const Frame& frame)>;
void RunFramePasses(const Scene& scene, const FrameConfig& config, FramePass from, FramePass to, Frame& frame,
                    BufferLifetime lifetime = BufferLifetime::kKeepAll, const FrameStepObserver& observer = {});

// The G-buffer's albedo as 8-bit sRGB RGB rows (background black): the paper's "albedo" image.
std::vector<uint8_t> AlbedoImage(const GBuffer& gbuffer);

}  // namespace ssgi
