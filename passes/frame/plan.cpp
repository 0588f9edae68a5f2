// The frame plan: which effects the visible pixels need.
#include "passes/frame/plan.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>
#include <vector>

#include "core/brdf.h"
#include "core/lighting.h"
#include "core/parallel.h"
#include "passes/shadow_map.h"

namespace ssgi {
namespace {

// One visible pixel as the direct light sees it; the normal is decoded only when a light needs it.
class VisiblePixel {
 public:
  VisiblePixel(const ViewProjection& view, int x, int y, float depth, uint32_t word1, NormalEncoding encoding)
      : ray_(view.PixelRay(float(x) + 0.5f, float(y) + 0.5f)),
        position_(ray_.origin + ray_.direction * depth),
        word1_(word1),
        encoding_(encoding) {}

  // Whether the light's term at this pixel can be non-zero: the conditions under which the direct
  // light's BrdfCosine and Evaluate give anything but 0, computed as they compute them. (Lights
  // are never negative: the scene loader refuses that.)
  bool FacesLight(const PreparedLight& light) {
    if (light.isSpot && !MayBeInsideCone(light)) return false;
    const LightAtPoint l = Evaluate(light, position_);
    if (!(l.irradiance.x > 0.0f || l.irradiance.y > 0.0f || l.irradiance.z > 0.0f)) return false;
    if (!decoded_) {
      toViewer_ = glm::normalize(-ray_.direction);
      normal_ = UnpackNormal(word1_, encoding_);
      decoded_ = true;
    }
    return glm::dot(normal_, l.toLight) > 0.0f && glm::dot(normal_, toViewer_) > 0.0f;
  }

 private:
  // A cheap necessary condition for Evaluate's cone factor to be above 0: the angle test in double
  // with a margin far above float's rounding, so that a spot aimed away from everything visible
  // costs a few operations per pixel rather than an Evaluate and a normal decode.
  bool MayBeInsideCone(const PreparedLight& light) const {
    const glm::dvec3 offset = glm::dvec3(light.position) - glm::dvec3(position_);
    const double along = -glm::dot(offset, glm::dvec3(light.direction));
    return along >= (double(light.cosOuter) - 1e-4) * glm::length(offset);
  }

  ViewProjection::Ray ray_;
  glm::vec3 position_;
  uint32_t word1_;
  NormalEncoding encoding_;
  bool decoded_ = false;
  glm::vec3 toViewer_{0.0f}, normal_{0.0f};
};

std::string Share(size_t part, size_t whole) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f%%", whole > 0 ? 100.0 * double(part) / double(whole) : 0.0);
  return text;
}

}  // namespace

void CountPlanRowScalar(const uint32_t* word1, const uint32_t* word2, int width, uint32_t smoothCodes,
                        uint32_t* geometry, uint32_t* smooth) {
  for (int x = 0; x < width; ++x) {
    if (UnpackDepth(word2[x]) == kBackgroundDepth) continue;
    const int tile = x / TileMask::kTileSize;
    ++geometry[tile];
    if ((word1[x] >> 24) < smoothCodes) ++smooth[tile];
  }
}

FramePlan PlanFrame(const Scene& scene, const FrameConfig& config, const GBuffer& gbuffer,
                    const Plane<uint32_t>& edgeCoverage, const ViewProjection& view, bool countShadowPixels) {
  const int width = gbuffer.width(), height = gbuffer.height();
  FramePlan plan;
  plan.reflectionTiles = TileMask::None(width, height);
  const int tilesX = plan.reflectionTiles.tilesX, tilesY = plan.reflectionTiles.tilesY;
  plan.tiles = plan.reflectionTiles.needed.size();
  plan.pixels = size_t(width) * size_t(height);
  const std::vector<size_t> shadowLights = ShadowCastingLights(scene);
  if (config.shadows != EffectMode::kOff && !shadowLights.empty()) plan.shadowLight = shadowLights.front();
  const std::vector<PreparedLight> lights = PrepareLights(scene, view.view);
  // The roughness codes below the cut-off, decided as the trace and the composite decide them:
  // UnpackRoughness grows with the code, so they are the codes below the first one that is not.
  const float cutoff = config.ssrTrace.roughnessCutoff;
  uint32_t smoothCodes = 0;
  while (smoothCodes < 256 && UnpackRoughness(smoothCodes << 24) < cutoff) ++smoothCodes;
  const bool seekShadows = plan.shadowLight && config.shadows == EffectMode::kAuto;

  std::vector<uint32_t> geometryPerTile(plan.tiles, 0), smoothPerTile(plan.tiles, 0);
  std::vector<size_t> shadowsPerTile(plan.tiles, 0);  // pixels facing the shadowed light, when counted
  // Each light needs one facing pixel, anywhere: once a tile has found it, the others stop looking
  // (which tiles looked depends on scheduling, so only the counted plan reports shadow tiles).
  const std::unique_ptr<std::atomic<bool>[]> reached(new std::atomic<bool>[lights.size()]);
  for (size_t i = 0; i < lights.size(); ++i) reached[i] = false;
  // Whether some light still needs a facing pixel (or the shadowed one's are being counted).
  const bool countingShadows = countShadowPixels && seekShadows;
  const auto seeking = [&] {
    if (countingShadows) return true;
    for (size_t i = 0; i < lights.size(); ++i)
      if (!reached[i].load(std::memory_order_relaxed)) return true;
    return false;
  };
  // A row of tiles at a time, each image row whole: the rows of one tile are pages apart, a stride
  // the hardware prefetchers do not follow.
  ParallelFor("frame_plan", size_t(tilesY), [&](size_t tileRow) {
    const size_t firstTile = tileRow * size_t(tilesX);
    const int y0 = int(tileRow) * TileMask::kTileSize, y1 = std::min(y0 + TileMask::kTileSize, height);
    for (int y = y0; y < y1; ++y) {
      const uint32_t* word1 = gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(size_t(y));
      const uint32_t* word2 = gbuffer.word[GBufferWord::kDepth].ConstRow(size_t(y));
      CountPlanRowSimd(word1, word2, width, smoothCodes, &geometryPerTile[firstTile], &smoothPerTile[firstTile]);
      for (int x = 0; x < width && seeking(); ++x) {
        const float depth = UnpackDepth(word2[x]);
        if (depth == kBackgroundDepth) continue;
        VisiblePixel pixel(view, x, y, depth, word1[x], gbuffer.normalEncoding);
        for (size_t i = 0; i < lights.size(); ++i) {
          const bool counted = countingShadows && i == *plan.shadowLight;
          if (!counted && reached[i].load(std::memory_order_relaxed)) continue;
          if (!pixel.FacesLight(lights[i])) continue;
          reached[i].store(true, std::memory_order_relaxed);
          if (counted) ++shadowsPerTile[firstTile + size_t(x / TileMask::kTileSize)];
        }
      }
    }
  });
  for (size_t tile = 0; tile < plan.tiles; ++tile) {
    plan.geometryPixels += geometryPerTile[tile];
    plan.reflections.pixels += smoothPerTile[tile];
    plan.reflections.tiles += smoothPerTile[tile] > 0;
    plan.reflectionTiles.needed[tile] = smoothPerTile[tile] > 0;
    if (countShadowPixels) {
      plan.shadows.pixels += shadowsPerTile[tile];
      plan.shadows.tiles += shadowsPerTile[tile] > 0;
    }
  }
  plan.reflections.counted = true;
  plan.shadows.counted = seekShadows && countShadowPixels;
  for (size_t i = 0; i < lights.size(); ++i) plan.lightReaches.push_back(reached[i].load());
  plan.directionalLights = scene.directionalLights.size();

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
    plan.shadows.run = plan.lightReaches[*plan.shadowLight];
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
  const bool lightReachesPixels =
      std::find(plan.lightReaches.begin(), plan.lightReaches.end(), true) != plan.lightReaches.end();
  if (config.sky == EffectMode::kOff) {
    plan.sky.why = "switched off";
  } else if (config.sky == EffectMode::kOn) {
    plan.sky.run = true;
    plan.sky.why = "switched on";
  } else if (plan.geometryPixels == 0) {
    plan.sky.why = "no pixel has geometry";
  } else if (!config.environment.IsBlack()) {
    plan.sky.run = true;
    plan.sky.why = "the environment lights the visible surfaces";
  } else if (lightReachesPixels && SkyMakesInterreflection(config)) {
    // Under a black sky the pass adds no sky light, but its interreflection volume carries the
    // lights' light from surface to surface, on screen and off.
    plan.sky.run = true;
    plan.sky.why = "the environment is black, but lights reach visible surfaces: the interreflection volume "
                   "carries their light between surfaces";
  } else {
    plan.sky.why = "the environment is black";
  }
  if (config.bounce == EffectMode::kOff) {
    plan.bounce.why = "switched off";
  } else if (config.bounce == EffectMode::kOn) {
    plan.bounce.run = true;
    plan.bounce.why = "switched on";
  } else if (plan.geometryPixels == 0) {
    plan.bounce.why = "no pixel has geometry";
  } else if (plan.sky.run && SkyMakesInterreflection(config)) {
    plan.bounce.why = "the interreflection volume carries the bounced light";
  } else {
    // Without light on screen the lit image is black on every surface, and there is no sky light to occlude.
    plan.bounce.run = lightReachesPixels || plan.sky.run;
    plan.bounce.why = lightReachesPixels && plan.sky.run ? "lights and the sky light the visible surfaces"
                      : lightReachesPixels               ? "lights reach visible surfaces"
                      : plan.sky.run                     ? "the sky lights the visible surfaces"
                                                         : "nothing on screen is lit (no light reaches a visible "
                                                           "pixel and the sky light does not run)";
  }
  if (config.antialiasing == Antialiasing::kOff) {
    plan.antialias.why = "switched off";
  } else if (config.antialiasing == Antialiasing::kMlaa) {
    // The image's edges are found after the composite, in the image; one without geometry in front of
    // a constant environment is one colour.
    const bool constantBackground = config.environment.kind == EnvironmentKind::kConstant;
    plan.antialias.run = plan.geometryPixels > 0 || !constantBackground;
    plan.antialias.why = plan.geometryPixels > 0 ? "mlaa searches the image's luma edges (pixels have geometry)"
                         : plan.antialias.run
                             ? "mlaa searches the image's luma edges (the environment is not one colour)"
                             : "no pixel has geometry and the environment is one colour";
  } else {
    // Edge pixels are those with a non-zero edge coverage word (passes/gbuffer.h): the first row
    // holding one decides (an OR over the row, which the compiler vectorises, where a search for the
    // first word would not be), unless they are counted per tile (for --explain).
    bool found = false;
    if (countShadowPixels) {
      std::vector<uint32_t> edgesPerTile(plan.tiles, 0);
      for (size_t y = 0; y < edgeCoverage.ysize(); ++y) {
        const uint32_t* row = edgeCoverage.ConstRow(y);
        uint32_t* tileRow = &edgesPerTile[y / TileMask::kTileSize * size_t(tilesX)];
        for (size_t x = 0; x < edgeCoverage.xsize(); ++x) tileRow[x / TileMask::kTileSize] += row[x] != 0;
      }
      for (uint32_t edges : edgesPerTile) {
        plan.antialias.pixels += edges;
        plan.antialias.tiles += edges > 0;
      }
      found = plan.antialias.pixels > 0;
    } else {
      for (size_t y = 0; y < edgeCoverage.ysize() && !found; ++y) {
        const uint32_t* row = edgeCoverage.ConstRow(y);
        uint32_t any = 0;
        for (size_t x = 0; x < edgeCoverage.xsize(); ++x) any |= row[x];
        found = any != 0;
      }
    }
    plan.antialias.counted = countShadowPixels;
    plan.antialias.run = found;
    plan.antialias.why = plan.antialias.run ? "pixels lie on geometric edges" : "no pixel lies on a geometric edge";
  }
  return plan;
}

std::string ExplainPlan(const FramePlan& plan) {
  std::string text = "frame plan: " + std::to_string(plan.geometryPixels) + " of " + std::to_string(plan.pixels) +
                     " pixels have geometry (" + Share(plan.geometryPixels, plan.pixels) + ")\n";
  // `running`: what runs, and where, when the effect runs; `skipped`: what does not run when it does not.
  const auto line = [&](const char* name, const std::string& skipped, const std::string& running,
                        const EffectPlan& effect) {
    text += std::string("  ") + name + ": " + (effect.run ? "run" : "skipped") + ", " + effect.why;
    if (effect.counted)
      text += "; needed in " + std::to_string(effect.tiles) + " of " + std::to_string(plan.tiles) + " tiles (" +
              Share(effect.tiles, plan.tiles) + "), " + std::to_string(effect.pixels) + " pixels (" +
              Share(effect.pixels, plan.pixels) + ")";
    text += "\n    " + (effect.run ? running : skipped) + "\n";
  };
  const size_t lights = plan.lightReaches.size();
  const size_t shaded = size_t(std::count(plan.lightReaches.begin(), plan.lightReaches.end(), true));
  text += "  lights: " + std::to_string(shaded) + " of " + std::to_string(lights) +
          " face a visible pixel and are shaded";
  std::string unseen;
  for (size_t i = 0; i < lights; ++i) {
    if (plan.lightReaches[i]) continue;
    const bool spot = i >= plan.directionalLights;
    unseen += std::string(unseen.empty() ? "" : ", ") + (spot ? "spot light " : "directional light ") +
              std::to_string((spot ? i - plan.directionalLights : i) + 1);
  }
  text += (unseen.empty() ? std::string() : "; not shaded (no visible pixel faces it): " + unseen) + "\n";
  line("shadows", "shadow map, blocker search, shadow filter do not run",
       "shadow map, blocker search, shadow filter run", plan.shadows);
  // The sky light and the bounce light every pixel with geometry: the composite then runs on the whole image.
  const bool composesEverywhere = plan.sky.run || plan.bounce.run;
  const std::string tracePasses = composesEverywhere ? "ssr trace, cone trace" : "ssr trace, cone trace, composite";
  line("reflections", "hi-z, colour pyramid, " + tracePasses + " do not run",
       plan.reflections.tiles == plan.tiles ? "hi-z, colour pyramid, " + tracePasses + " run on the whole image"
                                            : "hi-z, colour pyramid run; " + tracePasses + " run on those " +
                                                  std::to_string(plan.reflections.tiles) + " tiles only",
       plan.reflections);
  line("sky", "sky light does not run",
       "sky light runs on every pixel with geometry; the composite adds its specular part", plan.sky);
  line("bounce", "bounce does not run",
       std::string("bounce runs at half resolution on every pixel with geometry; the composite adds its light on "
                   "the diffuse albedo") +
           (plan.sky.run ? " and darkens the sky's diffuse light by its visibility" : ""),
       plan.bounce);
  line("antialias", "antialias does not run", "antialias blends those pixels with their neighbours across the edge",
       plan.antialias);
  return text;
}

}  // namespace ssgi
