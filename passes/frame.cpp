#include "passes/frame.h"

#include "core/error.h"
#include "core/image_io.h"
#include "core/lighting.h"
#include "core/stopwatch.h"

namespace ssgi {

Frame RenderFrame(const Scene& scene, const FrameOptions& options) {
  Frame frame;
  Stopwatch total;
  const RenderSettings& settings = scene.settings;
  frame.view = MakePerspective(scene.camera, settings.width, settings.height);
  const double pixels = double(settings.width) * double(settings.height);

  const GBufferStats g = RunGBuffer({scene, frame.view}, {settings.normalEncoding}, frame.gbuffer);
  frame.stats.push_back({"g-buffer raster", g.rasterMs, double(scene.mesh.TriangleCount()), "triangles"});
  frame.stats.push_back({"g-buffer resolve", g.resolveMs, double(g.coveredPixels), "pixels"});

  // Shadows only where the scene calls for them (DESIGN.md §9): a light that casts them, and not
  // switched off. G-buffer word 3 has room for one light's term: the first shadow-casting light.
  const std::vector<size_t> shadowLights = ShadowCastingLights(scene);
  const bool shadows = settings.shadows != EffectMode::kOff && !shadowLights.empty();
  std::vector<PreparedLight> viewLights;
  if (shadows) {
    const size_t light = shadowLights.front();
    frame.shadowMap.emplace(ShadowMapOutputs{frame.gbuffer.gbuffer.word[3], {}, {}});
    const ShadowMapStats s =
        RunShadowMap({scene, frame.view, frame.gbuffer.gbuffer, light}, options.shadowMap, *frame.shadowMap);
    frame.stats.push_back({"shadow map", s.fitMs + s.rasterMs, double(s.triangles), "triangles"});
    frame.stats.push_back({"blocker search", s.searchMs, double(s.pixels), "pixels"});
    viewLights = PrepareLights(scene, frame.view.view);
    const ShadowFilterStats f = RunShadowFilter(
        {frame.gbuffer.gbuffer, frame.view, viewLights[light], settings.normalEncoding}, options.shadowFilter,
        frame.shadowVisibility);
    frame.stats.push_back({"shadow filter", f.ms, pixels, "pixels"});
    frame.shadowTilesBlurred = f.tilesBlurred;
    frame.shadowTiles = f.tiles;
  }

  DirectLightInputs directInputs{frame.gbuffer.gbuffer, frame.view, scene};
  if (shadows) {
    directInputs.lightVisibility = &frame.shadowVisibility.visibility;
    directInputs.shadowedLight = shadowLights.front();
  }
  const DirectLightStats d = RunDirectLight(directInputs, frame.direct);
  frame.stats.push_back({"direct light", d.ms, pixels, "pixels"});

  frame.reflections = settings.reflections == EffectMode::kOn ||
                      (settings.reflections == EffectMode::kAuto && SceneReflects(scene, options.ssrTrace.roughnessCutoff));
  if (frame.reflections) {
    const HiZStats h = RunHiZ(frame.gbuffer.gbuffer.word[2], frame.hiz);
    frame.stats.push_back({"hi-z", h.ms, double(h.texels), "texels"});
    const ColorPyramidStats c = RunColorPyramid(frame.direct.radiance, frame.colorPyramid);
    frame.stats.push_back({"colour pyramid", c.ms, double(c.texels), "texels"});
    const SsrTraceStats t = RunSsrTrace({frame.gbuffer.gbuffer, frame.view, frame.hiz, settings.normalEncoding},
                                        options.ssrTrace, frame.ssrTrace);
    frame.stats.push_back({"ssr trace", t.ms, double(t.rays), "rays"});
    frame.ssrRays = t.rays;
    frame.ssrMeanIterations = t.meanIterations;
    frame.ssrTilesTraced = t.tilesTraced;
    frame.ssrTiles = t.tiles;
    const SsrConeStats k =
        RunSsrCone({frame.gbuffer.gbuffer, frame.colorPyramid, frame.ssrTrace}, options.ssrCone, frame.ssrCone);
    frame.stats.push_back({"cone trace", k.ms, double(k.pixels), "pixels"});
    const CompositeStats m = RunComposite({frame.gbuffer.gbuffer, frame.view, settings.normalEncoding,
                                           frame.direct.radiance, frame.ssrCone.reflected, frame.ssrTrace.confidence,
                                           options.ssrTrace.roughnessCutoff},
                                          frame.composite);
    frame.stats.push_back({"composite", m.ms, double(m.pixels), "pixels"});
  }

  Stopwatch tonemap;
  RunTonemap(frame.Result(), {settings.exposureEv, settings.tonemap}, frame.display);
  frame.stats.push_back({"tonemap", tonemap.Lap(), pixels, "pixels"});
  frame.stats.push_back({"frame total", total.Lap(), pixels, "pixels"});
  return frame;
}

std::vector<uint8_t> AlbedoImage(const GBuffer& gbuffer) {
  const int width = gbuffer.width(), height = gbuffer.height();
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (int y = 0; y < height; ++y) {
    const uint32_t* w0 = gbuffer.word[0].ConstRow(y);
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) rgb[(size_t(y) * width + x) * 3 + c] = uint8_t(w0[x] >> (8 * c));
  }
  return rgb;
}

FrameOptions QualityPreset(Quality quality) {
  FrameOptions o;
  switch (quality) {
    case Quality::kLow:
      o.shadowMap.resolution = 1024;
      o.shadowMap.blockerSearchTaps = 4;
      o.shadowFilter.maxRadiusPixels = 16;
      o.shadowFilter.taps = 2;
      o.ssrTrace.maxIterations = 16;
      o.ssrCone.maxSamples = 1;
      break;
    case Quality::kMedium:
      o.shadowMap.blockerSearchTaps = 8;
      o.shadowFilter.taps = 4;
      o.ssrTrace.maxIterations = 32;
      o.ssrCone.maxSamples = 1;
      break;
    case Quality::kHigh:
      break;
    case Quality::kUltra:
      o.shadowMap.resolution = 4096;
      o.ssrTrace.maxIterations = 128;
      break;
  }
  return o;
}

Quality ParseQuality(const std::string& name) {
  if (name == "low") return Quality::kLow;
  if (name == "medium") return Quality::kMedium;
  if (name == "high") return Quality::kHigh;
  if (name == "ultra") return Quality::kUltra;
  throw InputError("--quality: expected low, medium, high or ultra, got '" + name + "'");
}

bool SceneReflects(const Scene& scene, float roughnessCutoff) {
  for (const Material& m : scene.materials)
    if (m.roughness < roughnessCutoff || m.roughnessTexture != kNoTexture) return true;
  return false;
}

void WriteFrameBuffers(const std::filesystem::path& path, const Frame& frame, NormalEncoding encoding) {
  const GBuffer& g = frame.gbuffer.gbuffer;
  const int width = g.width(), height = g.height();
  // Decoded G-buffer planes, so a port can compare values as well as bits.
  const char* names[] = {"albedo.R", "albedo.G", "albedo.B", "metallic", "normal.X", "normal.Y", "normal.Z",
                         "roughness", "depth", "shadow.hard", "shadow.blocker"};
  constexpr int kDecoded = 11;
  std::vector<Plane<float>> decoded;
  for (int i = 0; i < kDecoded; ++i) decoded.push_back(MakePlane<float>(width, height, 0.0f));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint32_t w0 = g.word[0].ConstRow(y)[x], w1 = g.word[1].ConstRow(y)[x];
      const uint32_t w2 = g.word[2].ConstRow(y)[x], w3 = g.word[3].ConstRow(y)[x];
      const float depth = UnpackDepth(w2);
      const bool background = depth == kBackgroundDepth;
      const glm::vec3 albedo = UnpackAlbedo(w0);
      const glm::vec3 normal = background ? glm::vec3(0.0f) : DecodeNormal(w1 & 0xFFFFFFu, encoding);
      const float values[kDecoded] = {albedo.x, albedo.y, albedo.z, UnpackMetallic(w0), normal.x, normal.y, normal.z,
                                      UnpackRoughness(w1), depth, UnpackHardShadow(w3) ? 1.0f : 0.0f,
                                      UnpackBlockerDistance(w3)};
      for (int i = 0; i < kDecoded; ++i) decoded[i].MutableRow(y)[x] = values[i];
    }
  }
  std::vector<ExrChannel> channels;
  auto add = [&](const std::string& name, bool isUint, const auto& plane) {
    channels.push_back({name, isUint, plane.ConstRow(0), size_t(plane.PixelsPerRow())});
  };
  for (int w = 0; w < 4; ++w) add("gbuffer.word" + std::to_string(w), true, g.word[w]);
  for (int i = 0; i < kDecoded; ++i) add(names[i], false, decoded[i]);
  add("raster.depthKey", false, frame.gbuffer.visibility.depthKey);
  add("raster.triangle", true, frame.gbuffer.visibility.triangle);
  if (frame.shadowMap) add("shadow.visibility", false, frame.shadowVisibility.visibility);
  const char* rgb[] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) add(std::string("direct.") + rgb[c], false, frame.direct.radiance.c[c]);
  if (frame.reflections) {
    add("ssr.hitX", false, frame.ssrTrace.hitX);
    add("ssr.hitY", false, frame.ssrTrace.hitY);
    add("ssr.confidence", false, frame.ssrTrace.confidence);
    for (int c = 0; c < 3; ++c) {
      add(std::string("ssr.reflected.") + rgb[c], false, frame.ssrCone.reflected.c[c]);
      add(std::string("indirect.") + rgb[c], false, frame.composite.indirect.c[c]);
      add(std::string("result.") + rgb[c], false, frame.composite.result.c[c]);
    }
  }
  WriteExr(path, width, height, channels);
}

}  // namespace ssgi
