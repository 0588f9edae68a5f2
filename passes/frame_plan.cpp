// The frame plan: which effects the visible pixels need.
#include "passes/frame_plan.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <vector>

#include "core/brdf.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

struct TileNeeds {
  size_t geometry = 0;
  size_t reflections = 0;  // pixels smoother than the cut-off
  size_t shadows = 0;      // pixels facing the shadowed light (1 at most unless counted)
};

// Whether the light's term at this pixel can be non-zero: the conditions under which the direct
// light's BrdfCosine and Evaluate give anything but 0, computed as they compute them.
bool FacesLight(const PreparedLight& light, const ViewProjection& view, int x, int y, float depth, uint32_t word1,
                NormalEncoding encoding) {
  const ViewProjection::Ray ray = view.PixelRay(float(x) + 0.5f, float(y) + 0.5f);
  const glm::vec3 position = ray.origin + ray.direction * depth;
  const glm::vec3 toViewer = glm::normalize(-ray.direction);
  const glm::vec3 normal = UnpackNormal(word1, encoding);
  const LightAtPoint l = Evaluate(light, position);
  if (!(l.irradiance.x > 0.0f || l.irradiance.y > 0.0f || l.irradiance.z > 0.0f)) return false;
  return glm::dot(normal, l.toLight) > 0.0f && glm::dot(normal, toViewer) > 0.0f;
}

std::string Share(size_t part, size_t whole) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f%%", whole > 0 ? 100.0 * double(part) / double(whole) : 0.0);
  return text;
}

}  // namespace

FramePlan PlanFrame(const Scene& scene, const FrameConfig& config, const GBuffer& gbuffer, const ViewProjection& view,
                    bool countShadowPixels) {
  const int width = gbuffer.width(), height = gbuffer.height();
  const int tilesX = (width + kPlanTileSize - 1) / kPlanTileSize;
  const int tilesY = (height + kPlanTileSize - 1) / kPlanTileSize;
  FramePlan plan;
  plan.tiles = size_t(tilesX) * size_t(tilesY);
  plan.pixels = size_t(width) * size_t(height);
  const std::vector<size_t> shadowLights = ShadowCastingLights(scene);
  if (config.shadows != EffectMode::kOff && !shadowLights.empty()) plan.shadowLight = shadowLights.front();
  const std::vector<PreparedLight> lights = PrepareLights(scene, view.view);
  // The roughness codes below the cut-off, decided as the trace and the composite decide them.
  const float cutoff = config.ssrTrace.roughnessCutoff;
  bool smooth[256];
  for (uint32_t code = 0; code < 256; ++code) smooth[code] = UnpackRoughness(code << 24) < cutoff;
  const bool seekShadows = plan.shadowLight && config.shadows == EffectMode::kAuto;

  std::vector<TileNeeds> needs(plan.tiles);
  // The decision needs one facing pixel, anywhere: once a tile has found it, the others stop looking
  // (which tiles looked depends on scheduling, so only the counted plan reports shadow tiles).
  std::atomic<bool> facingFound{false};
  // A row of tiles at a time, each image row whole: the rows of one tile are pages apart, a stride
  // the hardware prefetchers do not follow.
  ParallelFor("frame_plan", size_t(tilesY), [&](size_t tileRow) {
    const int y0 = int(tileRow) * kPlanTileSize, y1 = std::min(y0 + kPlanTileSize, height);
    for (int y = y0; y < y1; ++y) {
      const uint32_t* word1 = gbuffer.word[1].ConstRow(size_t(y));
      const uint32_t* word2 = gbuffer.word[2].ConstRow(size_t(y));
      for (int x = 0; x < width; ++x) {
        TileNeeds& n = needs[tileRow * size_t(tilesX) + size_t(x / kPlanTileSize)];
        const float depth = UnpackDepth(word2[x]);
        if (depth == kBackgroundDepth) continue;
        ++n.geometry;
        if (smooth[word1[x] >> 24]) ++n.reflections;
        if (seekShadows && (countShadowPixels || !facingFound.load(std::memory_order_relaxed)) &&
            FacesLight(lights[*plan.shadowLight], view, x, y, depth, word1[x], gbuffer.normalEncoding)) {
          ++n.shadows;
          facingFound.store(true, std::memory_order_relaxed);
        }
      }
    }
  });
  for (const TileNeeds& n : needs) {
    plan.geometryPixels += n.geometry;
    plan.reflections.pixels += n.reflections;
    plan.reflections.tiles += n.reflections > 0;
    if (countShadowPixels) {
      plan.shadows.pixels += n.shadows;
      plan.shadows.tiles += n.shadows > 0;
    }
  }
  plan.reflections.counted = true;
  plan.shadows.counted = seekShadows && countShadowPixels;

  char cutoffText[32];
  std::snprintf(cutoffText, sizeof(cutoffText), "%g", double(cutoff));
  if (config.shadows == EffectMode::kOff) {
    plan.shadows.why = "switched off";
  } else if (!plan.shadowLight) {
    plan.shadows.why = "no light casts shadows";
  } else if (config.shadows == EffectMode::kOn) {
    plan.shadows.run = true;
    plan.shadows.why = "switched on";
  } else {
    plan.shadows.run = facingFound.load();
    plan.shadows.why = plan.shadows.run ? "visible pixels face the shadow-casting light"
                                        : "no visible pixel faces the shadow-casting light";
  }
  if (config.reflections == EffectMode::kOff) {
    plan.reflections.why = "switched off";
  } else if (config.reflections == EffectMode::kOn) {
    plan.reflections.run = true;
    plan.reflections.why = "switched on";
  } else {
    plan.reflections.run = plan.reflections.pixels > 0;
    plan.reflections.why = std::string(plan.reflections.run ? "visible surfaces are smoother than"
                                                            : "no visible surface is smoother than") +
                           " the cut-off (roughness " + cutoffText + ")";
  }
  return plan;
}

std::string ExplainPlan(const FramePlan& plan) {
  std::string text = "frame plan: " + std::to_string(plan.geometryPixels) + " of " + std::to_string(plan.pixels) +
                     " pixels have geometry (" + Share(plan.geometryPixels, plan.pixels) + ")\n";
  const auto line = [&](const char* name, const char* passes, const EffectPlan& effect) {
    text += std::string("  ") + name + ": " + (effect.run ? "run" : "skipped") + ", " + effect.why;
    if (effect.counted)
      text += "; needed in " + std::to_string(effect.tiles) + " of " + std::to_string(plan.tiles) + " tiles (" +
              Share(effect.tiles, plan.tiles) + "), " + std::to_string(effect.pixels) + " pixels (" +
              Share(effect.pixels, plan.pixels) + ")";
    text += std::string("\n    ") + passes + (effect.run ? " run" : " do not run") + "\n";
  };
  line("shadows", "shadow map, blocker search, shadow filter", plan.shadows);
  line("reflections", "hi-z, colour pyramid, ssr trace, cone trace, composite", plan.reflections);
  return text;
}

}  // namespace ssgi
