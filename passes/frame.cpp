#include "passes/frame.h"

#include "core/error.h"
#include "core/image_io.h"
#include "core/lighting.h"
#include "core/stopwatch.h"

namespace ssgi {

Frame RenderFrame(const Scene& scene, const FrameConfig& config) {
  Frame frame;
  FrameStats& stats = frame.stats;
  Stopwatch total;
  frame.view = MakePerspective(scene.camera, config.width, config.height);
  stats.triangles = scene.mesh.TriangleCount();
  stats.pixels = size_t(config.width) * size_t(config.height);

  stats.gbuffer = RunGBuffer({scene, frame.view}, {config.normalEncoding}, frame.gbuffer);
  GBuffer& gbuffer = frame.gbuffer.gbuffer;

  // Shadows only where the scene calls for them (DESIGN.md §9): a light that casts them, and not
  // switched off. G-buffer word 3 has room for one light's term: the first shadow-casting light.
  const std::vector<size_t> shadowLights = ShadowCastingLights(scene);
  const bool shadows = config.shadows != EffectMode::kOff && !shadowLights.empty();
  if (shadows) {
    const size_t light = shadowLights.front();
    frame.shadowMap.emplace();
    stats.shadowMap =
        RunShadowMap({scene, frame.view, gbuffer, light}, config.shadowMap, *frame.shadowMap, gbuffer.word[3]);
    const std::vector<PreparedLight> viewLights = PrepareLights(scene, frame.view.view);
    stats.shadowFilter = RunShadowFilter({gbuffer, frame.view, viewLights[light]}, config.shadowFilter,
                                         frame.shadowVisibility);
  }

  DirectLightInputs directInputs{gbuffer, frame.view, scene};
  if (shadows) {
    directInputs.lightVisibility = &frame.shadowVisibility.visibility;
    directInputs.shadowedLight = shadowLights.front();
  }
  stats.directLight = RunDirectLight(directInputs, config.directLight, frame.direct);

  frame.reflections = config.reflections == EffectMode::kOn ||
                      (config.reflections == EffectMode::kAuto && SceneReflects(scene, config.ssrTrace.roughnessCutoff));
  if (frame.reflections) {
    stats.hiz = RunHiZ(gbuffer.word[2], frame.hiz);
    stats.colorPyramid = RunColorPyramid(frame.direct.radiance, frame.colorPyramid);
    stats.ssrTrace = RunSsrTrace({gbuffer, frame.view, frame.hiz}, config.ssrTrace, frame.ssrTrace);
    stats.ssrCone = RunSsrCone({gbuffer, frame.colorPyramid, frame.ssrTrace}, config.ssrCone, frame.ssrCone);
    stats.composite = RunComposite({gbuffer, frame.view, frame.direct.radiance, frame.ssrCone.reflected,
                                    frame.ssrTrace.confidence, config.ssrTrace.roughnessCutoff},
                                   frame.composite);
  }

  stats.tonemap = RunTonemap(frame.Result(), config.tonemap, frame.display);
  stats.totalMs = total.Lap();
  return frame;
}

std::vector<StageStats> StageRows(const FrameStats& s) {
  const double pixels = double(s.pixels);
  std::vector<StageStats> rows;
  rows.push_back({"g-buffer raster", s.gbuffer.rasterMs, double(s.triangles), "triangles"});
  rows.push_back({"g-buffer resolve", s.gbuffer.resolveMs, double(s.gbuffer.coveredPixels), "pixels"});
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
    const uint32_t* w0 = gbuffer.word[0].ConstRow(y);
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) rgb[(size_t(y) * width + x) * 3 + c] = uint8_t(w0[x] >> (8 * c));
  }
  return rgb;
}

bool SceneReflects(const Scene& scene, float roughnessCutoff) {
  for (const Material& m : scene.materials)
    if (m.roughness < roughnessCutoff || m.roughnessTexture != kNoTexture) return true;
  return false;
}

void WriteFrameBuffers(const std::filesystem::path& path, const Frame& frame) {
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
      const glm::vec3 normal = background ? glm::vec3(0.0f) : UnpackNormal(w1, g.normalEncoding);
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
