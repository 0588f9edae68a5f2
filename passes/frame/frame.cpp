#include "passes/frame/frame.h"

#include <algorithm>
#include <optional>
#include <type_traits>
#include <utility>

#include "core/error.h"
#include "core/lighting.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

// Beyond 1 / kPartialPyramidShare of the image needing reflections, the hits are not listed: so many
// cones read most of the pyramid.
constexpr size_t kPartialPyramidShare = 10;

}  // namespace

std::string_view FramePassName(FramePass pass) {
  switch (pass) {
    case FramePass::kGBuffer: return "gbuffer";
    case FramePass::kShadowMap: return "shadow_map";
    case FramePass::kShadowFilter: return "shadow_filter";
    case FramePass::kDirectLight: return "direct_light";
    case FramePass::kHiZ: return "hiz";
    case FramePass::kColorPyramid: return "color_pyramid";
    case FramePass::kSsrTrace: return "ssr_trace";
    case FramePass::kSsrCone: return "ssr_cone";
    case FramePass::kComposite: return "composite";
    case FramePass::kTonemap: return "tonemap";
  }
  return "";
}

FramePass ParseFramePass(std::string_view name) {
  std::string names;
  for (FramePass pass : kFramePasses) {
    if (FramePassName(pass) == name) return pass;
    names += (names.empty() ? "" : ", ") + std::string(FramePassName(pass));
  }
  throw InputError("'" + std::string(name) + "' is not a pass; the passes: " + names);
}

Frame RenderFrame(const Scene& scene, const FrameConfig& config, BufferLifetime lifetime) {
  Frame frame;
  RunFramePasses(scene, config, FramePass::kGBuffer, FramePass::kTonemap, frame, lifetime);
  return frame;
}

void RunFramePasses(const Scene& scene, const FrameConfig& config, FramePass from, FramePass to, Frame& frame,
                    BufferLifetime lifetime) {
  // Frees a buffer whose last reader has run (BufferLifetime::kUntilLastReader).
  const bool release = lifetime == BufferLifetime::kUntilLastReader;
  const auto drop = [release](auto& buffer) {
    if (release) buffer = std::remove_reference_t<decltype(buffer)>();
  };
  FrameStats& stats = frame.stats;
  stats = FrameStats{};
  Stopwatch total;
  frame.view = MakePerspective(scene.camera, config.width, config.height);
  stats.triangles = scene.mesh.TriangleCount();
  stats.pixels = size_t(config.width) * size_t(config.height);
  const auto runs = [&](FramePass pass) { return from <= pass && pass <= to; };

  if (runs(FramePass::kGBuffer))
    stats.gbuffer = RunGBuffer({scene, frame.view}, {config.normalEncoding}, frame.gbuffer);
  drop(frame.gbuffer.visibility);
  GBuffer& gbuffer = frame.gbuffer.gbuffer;

  // Only the effects the visible pixels need (docs/design.md §9). G-buffer word 3 has room for one
  // light's term: the first shadow-casting light's.
  Stopwatch planning;
  frame.plan = PlanFrame(scene, config, gbuffer, frame.view);
  stats.planMs = planning.Lap();
  frame.shadows = frame.plan.shadows.run && (from > FramePass::kShadowMap || to >= FramePass::kShadowMap);
  const size_t shadowLight = frame.plan.shadowLight.value_or(0);  // meaningful where frame.shadows
  if (frame.shadows && runs(FramePass::kShadowMap)) {
    if (!frame.shadowMap) frame.shadowMap.emplace();  // a kept frame's map is redrawn in place
    stats.shadowMap = RunShadowMap({scene, frame.view, gbuffer, shadowLight}, config.shadowMap, *frame.shadowMap,
                                   gbuffer.word[GBufferWord::kShadowTerm]);
  }
  drop(frame.shadowMap);
  if (frame.shadows && runs(FramePass::kShadowFilter)) {
    const std::vector<PreparedLight> viewLights = PrepareLights(scene, frame.view.view);
    stats.shadowFilter = RunShadowFilter({gbuffer, frame.view, viewLights[shadowLight]}, config.shadowFilter,
                                         frame.shadowVisibility);
  }

  if (runs(FramePass::kDirectLight)) {
    DirectLightInputs directInputs{gbuffer, frame.view, scene};
    directInputs.shadeLights = &frame.plan.lightReaches;
    if (frame.shadows) {
      directInputs.lightVisibility = &frame.shadowVisibility.visibility;
      directInputs.shadowedLight = shadowLight;
    }
    stats.directLight = RunDirectLight(directInputs, config.directLight, frame.direct);
  }
  drop(frame.shadowVisibility);
  drop(frame.gbuffer.gbuffer.word[GBufferWord::kShadowTerm]);  // the shadow term: read by the filter only

  frame.reflections = frame.plan.reflections.run;
  if (frame.reflections) {
    // Freeing early, buffers are also handed on instead of copied (docs/pipeline.md §Memory): the
    // direct image becomes the pyramid's level 0 (it is already sanitised), the hits' planes the
    // reflection's red and green, and the composite writes over the direct image and the
    // reflection. Each pass reads a pixel before it writes over it: the same bytes.
    if (runs(FramePass::kHiZ)) stats.hiz = RunHiZ(gbuffer.word[GBufferWord::kDepth], frame.hiz);
    // No dump reads the frame's reflection buffers: it frees them, or keeps them for reuse.
    const bool undumped = lifetime != BufferLifetime::kKeepAll;
    // Then the direct image is the pyramid's level 0 while the pyramid is made and read.
    const bool directInPyramid = undumped && runs(FramePass::kColorPyramid);
    const auto makePyramid = [&](const ColorPyramidNeeds* needs) {
      if (directInPyramid) {
        frame.colorPyramid.levels.resize(std::max<size_t>(frame.colorPyramid.levels.size(), 1));
        frame.colorPyramid.levels[0] = std::move(frame.direct.radiance);
        stats.colorPyramid = RunColorPyramidOnLevelZero(frame.colorPyramid, KernelPath::kSimd, needs);
      } else if (runs(FramePass::kColorPyramid)) {
        stats.colorPyramid = RunColorPyramid(frame.direct.radiance, frame.colorPyramid);
      }
    };
    // And the frame traces first and makes only the texels the cone trace of those hits reads
    // (docs/pipeline.md §Frame plan), where the hits are few enough for listing them to pay.
    const bool pyramidAfterTrace = directInPyramid && runs(FramePass::kSsrTrace) && runs(FramePass::kSsrCone);
    if (!pyramidAfterTrace) makePyramid(nullptr);
    // Only the plan's reflection tiles can trace. The cone and the composite skip the other tiles
    // only after this run's trace: hits read from a port's file are taken as they are.
    const TileMask* reflectionTiles = &frame.plan.reflectionTiles;
    const TileMask* tracedTiles = runs(FramePass::kSsrTrace) ? reflectionTiles : nullptr;
    // And the skipped tiles' hits and reflection are left as they are: the cone trace and the
    // composite in place read neither there.
    const bool leaveSkippedTiles = undumped && runs(FramePass::kComposite);
    if (runs(FramePass::kSsrTrace)) {
      stats.ssrTrace =
          RunSsrTrace({gbuffer, frame.view, frame.hiz, reflectionTiles, leaveSkippedTiles}, config.ssrTrace,
                      frame.ssrTrace, KernelPath::kSimd,
                      undumped ? SsrTraceSteps::kSkip : SsrTraceSteps::kRecord);  // steps: for dumps
    }
    drop(frame.hiz);
    if (pyramidAfterTrace) {
      std::optional<ColorPyramidNeeds> needs;
      if (frame.plan.reflections.pixels <= frame.plan.pixels / kPartialPyramidShare) {
        needs =
            SsrConePyramidNeeds(gbuffer.word[GBufferWord::kNormalRoughness], frame.ssrTrace.hitX, frame.ssrTrace.hitY,
                                frame.ssrTrace.confidence, reflectionTiles, frame.plan.pixels / 2);
      }
      makePyramid(needs ? &*needs : nullptr);
    }
    if (release) {
      frame.ssrCone.reflected.c[0] = std::move(frame.ssrTrace.hitX);
      frame.ssrCone.reflected.c[1] = std::move(frame.ssrTrace.hitY);
    }
    if (runs(FramePass::kSsrCone)) {
      const Plane3<float>& reflected = frame.ssrCone.reflected;
      const Plane<float>& hitX = release ? reflected.c[0] : frame.ssrTrace.hitX;
      const Plane<float>& hitY = release ? reflected.c[1] : frame.ssrTrace.hitY;
      stats.ssrCone =
          RunSsrCone({gbuffer, frame.colorPyramid, hitX, hitY, frame.ssrTrace.confidence, tracedTiles,
                      leaveSkippedTiles},
                     config.ssrCone, frame.ssrCone);
    }
    if (directInPyramid) frame.direct.radiance = std::move(frame.colorPyramid.levels[0]);
    drop(frame.colorPyramid);
    drop(frame.ssrTrace.hitX);
    drop(frame.ssrTrace.hitY);
    // The composite works in place where no later reader needs the direct image and the reflection
    // apart: freed, they are handed on; kept for reuse, their planes trade places with the result's
    // and the indirect term's, which the next frame writes again.
    const bool composeInPlace =
        release || (lifetime == BufferLifetime::kKeepForReuse && runs(FramePass::kComposite));
    if (release) {
      frame.composite.result = std::move(frame.direct.radiance);
      frame.composite.indirect = std::move(frame.ssrCone.reflected);
    } else if (composeInPlace) {
      std::swap(frame.composite.result, frame.direct.radiance);
      std::swap(frame.composite.indirect, frame.ssrCone.reflected);
    }
    if (runs(FramePass::kComposite)) {
      const Plane3<float>& direct = composeInPlace ? frame.composite.result : frame.direct.radiance;
      const Plane3<float>& reflected = composeInPlace ? frame.composite.indirect : frame.ssrCone.reflected;
      stats.composite = RunComposite(
          {gbuffer, frame.view, direct, reflected, frame.ssrTrace.confidence, config.ssrTrace.roughnessCutoff,
           tracedTiles},
          frame.composite);
    }
    drop(frame.ssrCone);
    drop(frame.ssrTrace.confidence);
    drop(frame.composite.indirect);
    drop(frame.direct);
  }

  if (runs(FramePass::kTonemap)) stats.tonemap = RunTonemap(frame.Result(), config.tonemap, frame.display);
  stats.totalMs = total.Lap();
}

std::vector<StageStats> StageRows(const FrameStats& s) {
  const double pixels = double(s.pixels);
  std::vector<StageStats> rows;
  rows.push_back({"g-buffer raster", s.gbuffer.rasterMs, double(s.triangles), "triangles"});
  rows.push_back({"g-buffer resolve", s.gbuffer.resolveMs, double(s.gbuffer.coveredPixels), "pixels"});
  rows.push_back({"frame plan", s.planMs, pixels, "pixels"});
  if (s.shadowMap) {
    rows.push_back({"shadow map", s.shadowMap->fitMs + s.shadowMap->rasterMs, double(s.shadowMap->triangles),
                    "triangles"});
    rows.push_back({"blocker search", s.shadowMap->searchMs, double(s.shadowMap->pixels), "pixels"});
  }
  if (s.shadowFilter) rows.push_back({"shadow filter", s.shadowFilter->ms, pixels, "pixels"});
  rows.push_back({"direct light", s.directLight.ms, pixels, "pixels"});
  if (s.hiz) rows.push_back({"hi-z", s.hiz->ms, double(s.hiz->texels), "texels"});
  if (s.colorPyramid) rows.push_back({"colour pyramid", s.colorPyramid->ms, double(s.colorPyramid->texels), "texels"});
  if (s.ssrTrace) rows.push_back({"ssr trace", s.ssrTrace->ms, double(s.ssrTrace->rays), "rays"});
  if (s.ssrCone) rows.push_back({"cone trace", s.ssrCone->ms, double(s.ssrCone->pixels), "pixels"});
  if (s.composite) rows.push_back({"composite", s.composite->ms, double(s.composite->pixels), "pixels"});
  rows.push_back({"tonemap", s.tonemap.ms, double(s.tonemap.pixels), "pixels"});
  rows.push_back({"frame total", s.totalMs, pixels, "pixels"});
  return rows;
}

std::vector<uint8_t> AlbedoImage(const GBuffer& gbuffer) {
  const int width = gbuffer.width(), height = gbuffer.height();
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y) {
    const uint32_t* w0 = gbuffer.word[GBufferWord::kAlbedoMetallic].ConstRow(y);
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) rgb[(size_t(y) * width + x) * 3 + c] = uint8_t(w0[x] >> (8 * c));
  }
  return rgb;
}


}  // namespace ssgi
