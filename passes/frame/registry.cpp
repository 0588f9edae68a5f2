// The pass registry: the frame's passes in pipeline order, each with its buffers, stats rows and
// step. Read top to bottom, it is the frame: scene -> G-buffer -> shadow map and blocker search ->
// shadow filter -> direct light -> sky light -> diffuse bounce -> Hi-Z -> colour pyramid -> SSR
// trace -> cone trace -> composite -> morphological edges -> anti-aliasing -> tonemap (docs/design.md §1). A buffer
// handed on to another is left empty (std::exchange), never moved-from with its old size, which a later reader would
// take for a filled buffer.
#include "passes/frame/registry.h"

#include <algorithm>
#include <utility>

#include "core/check.h"
#include "core/closed_surfaces.h"
#include "core/lighting.h"
#include "core/pyramid.h"
#include "core/stopwatch.h"
#include "core/system_memory.h"
#include "passes/frame/dump.h"
#include "passes/frame/frame.h"

namespace ssgi {
namespace {

using B = FrameBuffer;
using P = FramePass;

// Beyond 1 / kPartialPyramidShare of the image needing reflections, the hits are not listed: so many
// cones read most of the pyramid.
constexpr size_t kPartialPyramidShare = 10;

// What the rasterizer keeps per submitted triangle: the set-up triangle and its tile-bin entries.
constexpr size_t kRasterBytesPerTriangle = 160;

// The bytes of a Plane<T> of that size: hwy::Image pads each row to its alignment and vector size.
template <class T = float>
size_t PlaneBytes(size_t width, size_t height) {
  return hwy::ImageBase::BytesPerRow(width, sizeof(T)) * height;
}
size_t ImagePlanes(const FrameShape& s, size_t planes) { return planes * PlaneBytes(s.width, s.height); }

template <class T>
size_t Held(const Plane<T>& plane) {
  return plane.bytes_per_row() * plane.ysize();
}
template <class T>
size_t Held(const Plane3<T>& planes) {
  return Held(planes.c[0]) + Held(planes.c[1]) + Held(planes.c[2]);
}
template <class Level>
size_t HeldLevels(const std::vector<Level>& levels) {
  size_t bytes = 0;
  for (const Level& level : levels) bytes += Held(level);
  return bytes;
}

// Whether the frame holds an image-sized plane (a buffer freed, or not loaded from a dump, has none).
template <class T>
bool ImageSized(const Frame& f, const Plane<T>& plane) {
  return plane.xsize() == size_t(f.gbuffer.gbuffer.width()) && plane.xsize() > 0;
}

std::optional<StageStats> Row(double ms, double items, std::string unit) {
  return StageStats{"", ms, items, std::move(unit)};
}

template <class Levels>
void DumpLevels(DumpPart part, const Levels& levels, DumpSink& sink) {
  for (size_t k = 0; k < levels.size(); ++k) {
    if constexpr (std::is_same_v<typename Levels::value_type, Plane<float>>)
      sink.Add(part, int(k), "Y", levels[k]);
    else
      sink.Add3(part, int(k), "", levels[k]);
  }
}

// ---- G-buffer (passes/gbuffer.h) ----

void GBufferStep(FrameStep& s) {
  Frame& f = s.frame;
  if (s.Runs(P::kGBuffer))
    f.stats.gbuffer = RunGBuffer(
        {s.scene, f.view},
        {s.config.normalEncoding, s.config.antialiasing == Antialiasing::kEdge, s.config.specularAaKappa}, f.gbuffer);
}

const char kWord0Meaning[] = "albedo R, G, B 8-bit sRGB codes (bits 0-23), metallic code (24-31)";
const char kWord1Meaning[] = "view-space normal, 24-bit encoding (bits 0-23), perceptual roughness code (24-31)";
const char kNormalMeaning[] = "view-space unit normal from word 1; 0 on background";
const char kAlbedoMeaning[] = "linear albedo from word 0, [0, 1]";

PassDeclaration GBufferPass() {
  PassDeclaration pass{P::kGBuffer, "gbuffer",
                       "rasterize the visibility buffer and resolve the packed 128-bit G-buffer"};
  pass.makes = {
      {.id = B::kGBufferWords,
       .name = "g-buffer words 0-2",
       .frameOutput = true,
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 3); },
       .layers = {{"gbuffer.word0", P::kGBuffer, true, DumpPart::kImage, false, kWord0Meaning},
                  {"gbuffer.word1", P::kGBuffer, true, DumpPart::kImage, false, kWord1Meaning},
                  {"gbuffer.word2", P::kGBuffer, true, DumpPart::kImage, false,
                   "view depth, float32 bits, metres; +inf background"},
                  {"albedo.R", P::kGBuffer, false, DumpPart::kImage, true, kAlbedoMeaning},
                  {"albedo.G", P::kGBuffer, false, DumpPart::kImage, true, kAlbedoMeaning},
                  {"albedo.B", P::kGBuffer, false, DumpPart::kImage, true, kAlbedoMeaning},
                  {"metallic", P::kGBuffer, false, DumpPart::kImage, true, "metallic from word 0, [0, 1]"},
                  {"normal.X", P::kGBuffer, false, DumpPart::kImage, true, kNormalMeaning},
                  {"normal.Y", P::kGBuffer, false, DumpPart::kImage, true, kNormalMeaning},
                  {"normal.Z", P::kGBuffer, false, DumpPart::kImage, true, kNormalMeaning},
                  {"roughness", P::kGBuffer, false, DumpPart::kImage, true, "perceptual roughness from word 1, [0, 1]"},
                  {"depth", P::kGBuffer, false, DumpPart::kImage, true,
                   "view depth from word 2, metres; +inf background"}},
       .heldBytes =
           [](const Frame& f) {
             const GBuffer& g = f.gbuffer.gbuffer;
             return Held(g.word[GBufferWord::kAlbedoMetallic]) + Held(g.word[GBufferWord::kNormalRoughness]) +
                    Held(g.word[GBufferWord::kDepth]);
           },
       .release = nullptr,  // a frame output
       .dump = [](const Frame& f, DumpSink& sink) { sink.AddGBufferWords(f.gbuffer.gbuffer); },
       .load = [](const DumpSource& source, Frame& f) { source.LoadGBufferWords(f.gbuffer.gbuffer); },
       .readByPlan = true},
      // Allocated with the G-buffer and set to "lit" by its resolve; its term is the shadow map's.
      {.id = B::kShadowTerm,
       .name = "g-buffer word 3",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 1); },
       .layers = {{"gbuffer.word3", P::kShadowMap, true, DumpPart::kImage, false,
                   "shadow term: hard-shadow flag (bit 31), average blocker distance float32 bits without sign "
                   "(0-30); 0 = lit"},
                  {"shadow.hard", P::kShadowMap, false, DumpPart::kImage, true,
                   "hard shadow from word 3: 1 occluded, 0 lit"},
                  {"shadow.blocker", P::kShadowMap, false, DumpPart::kImage, true,
                   "average blocker distance from word 3, metres, >= 0; 0 = no blocker"}},
       .heldBytes = [](const Frame& f) { return Held(f.gbuffer.gbuffer.word[GBufferWord::kShadowTerm]); },
       .release = [](Frame& f) { f.gbuffer.gbuffer.word[GBufferWord::kShadowTerm] = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.shadows) sink.AddShadowTerm(f.gbuffer.gbuffer.word[GBufferWord::kShadowTerm]);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             source.Load(DumpPart::kImage, 0, "gbuffer.word3", f.gbuffer.gbuffer.word[GBufferWord::kShadowTerm]);
           },
       .carriedThrough = true},
      {.id = B::kVisibility,
       .name = "visibility buffer",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 2); },
       .layers = {{"raster.depthKey", P::kGBuffer, false, DumpPart::kImage, false,
                   "visibility buffer: reversed-Z depth key z_ndc of the nearest surface, (0, 1]; 0 = nothing drawn"},
                  {"raster.triangle", P::kGBuffer, true, DumpPart::kImage, false,
                   "visibility buffer: triangle index of the nearest surface; 0xFFFFFFFF = nothing drawn"}},
       .heldBytes =
           [](const Frame& f) { return Held(f.gbuffer.visibility.depthKey) + Held(f.gbuffer.visibility.triangle); },
       .release = [](Frame& f) { f.gbuffer.visibility = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (!ImageSized(f, f.gbuffer.visibility.triangle)) return;
             sink.Add(DumpPart::kImage, 0, "raster.depthKey", f.gbuffer.visibility.depthKey);
             sink.Add(DumpPart::kImage, 0, "raster.triangle", f.gbuffer.visibility.triangle);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             source.Load(DumpPart::kImage, 0, "raster.depthKey", f.gbuffer.visibility.depthKey);
             source.Load(DumpPart::kImage, 0, "raster.triangle", f.gbuffer.visibility.triangle);
           },
       .carriedThrough = true},
  };
  pass.makes.push_back(
      {.id = B::kEdgeCoverage,
       .name = "edge coverage",
       .bytes = [](const FrameShape& s) { return s.edgeCoverage ? PlaneBytes<uint32_t>(s.width, s.height) : 0; },
       .layers = {{"aa.coverage", P::kGBuffer, true, DumpPart::kImage, false,
                   "edge coverage word: shares of the pixel, in 1/256, covered by the left (bits 0-7), right "
                   "(8-15), upper (16-23) and lower (24-31) neighbour's surface; 0 = no edge"}},
       .heldBytes = [](const Frame& f) { return Held(f.gbuffer.edgeCoverage); },
       .release = [](Frame& f) { f.gbuffer.edgeCoverage = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (ImageSized(f, f.gbuffer.edgeCoverage))
               sink.Add(DumpPart::kImage, 0, "aa.coverage", f.gbuffer.edgeCoverage);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             if (source.Has(DumpPart::kImage, 0, "aa.coverage"))
               source.Load(DumpPart::kImage, 0, "aa.coverage", f.gbuffer.edgeCoverage);
           },
       .readByPlan = true});
  pass.scratchName = "g-buffer raster set-up";
  pass.scratchBytes = [](const FrameShape& s) { return kRasterBytesPerTriangle * s.triangles; };
  pass.stats = {
      {"g-buffer raster",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.gbuffer) return std::nullopt;
         return Row(s.gbuffer->rasterMs, double(s.triangles), "triangles");
       }},
      {"g-buffer resolve",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.gbuffer) return std::nullopt;
         return Row(s.gbuffer->resolveMs, double(s.gbuffer->coveredPixels), "pixels");
       }},
      // The frame plan runs right after the G-buffer pass, on its buffer.
      {"frame plan", [](const FrameStats& s) { return Row(s.planMs, double(s.pixels), "pixels"); }},
  };
  pass.step = GBufferStep;
  return pass;
}

// ---- Shadow map and blocker search (passes/shadow_map.h): the first shadow-casting light's ----

void ShadowMapStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.Runs(P::kShadowMap)) return;
  if (!f.shadowMap) f.shadowMap.emplace();  // a kept frame's map is redrawn in place
  GBuffer& g = f.gbuffer.gbuffer;
  f.stats.shadowMap = RunShadowMap({s.scene, f.view, g, f.plan.shadowLight.value_or(0)}, s.config.shadowMap,
                                   *f.shadowMap, g.word[GBufferWord::kShadowTerm]);
}

PassDeclaration ShadowMapPass() {
  PassDeclaration pass{P::kShadowMap, "shadow_map",
                       "the shadowed light's shadow map and the PCSS blocker search into G-buffer word 3"};
  pass.effect = FrameEffect::kShadows;
  pass.makes = {
      {.id = B::kShadowMap,
       .name = "shadow map",
       // Depth keys only: the shadow map's raster writes no triangle indices. With them, the mesh's
       // closed surfaces, kept from frame to frame: a surface index per triangle (their boxes, 24
       // bytes a closed surface, are left out).
       .bytes =
           [](const FrameShape& s) {
             return PlaneBytes(s.shadowMapResolution, s.shadowMapResolution) + sizeof(uint32_t) * s.triangles;
           },
       .layers = {{"depthKey", P::kShadowMap, false, DumpPart::kShadowMap, false,
                   "shadow map: reversed-Z depth key seen from the light, [0, 1]; 0 = nothing drawn"}},
       .heldBytes =
           [](const Frame& f) {
             return f.shadowMap ? Held(f.shadowMap->shadowMap.depthKey) + Held(f.shadowMap->shadowMap.triangle) +
                                      sizeof(uint32_t) * f.shadowMap->closedSurfaces.surface.size()
                                : 0;
           },
       .release = [](Frame& f) { f.shadowMap.reset(); },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.shadowMap) sink.Add(DumpPart::kShadowMap, 0, "depthKey", f.shadowMap->shadowMap.depthKey);
           }},
  };
  pass.reads = {B::kGBufferWords};
  pass.writes = {B::kShadowTerm};
  pass.scratchName = "shadow-map raster set-up";
  // Finding the closed surfaces (the first frame) comes before the raster, and needs less.
  pass.scratchBytes = [](const FrameShape& s) {
    return std::max(kRasterBytesPerTriangle * s.triangles, ClosedSurfacesBuildBytes(s.triangles, s.vertices));
  };
  pass.stats = {
      {"shadow map",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.shadowMap) return std::nullopt;
         return Row(s.shadowMap->fitMs + s.shadowMap->rasterMs, double(s.shadowMap->triangles), "triangles");
       }},
      {"blocker search",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.shadowMap) return std::nullopt;
         return Row(s.shadowMap->searchMs, double(s.shadowMap->pixels), "pixels");
       }},
  };
  pass.step = ShadowMapStep;
  return pass;
}

// ---- Shadow filter (passes/shadow_filter.h): SSABSS, SSPCSS or the hard test ----

void ShadowFilterStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.Runs(P::kShadowFilter)) return;
  const std::vector<PreparedLight> viewLights = PrepareLights(s.scene, f.view.view);
  f.stats.shadowFilter = RunShadowFilter({f.gbuffer.gbuffer, f.view, viewLights[f.plan.shadowLight.value_or(0)]},
                                         s.config.shadowFilter, f.shadowVisibility);
}

PassDeclaration ShadowFilterPass() {
  PassDeclaration pass{P::kShadowFilter, "shadow_filter",
                       "the shadowed light's soft visibility from word 3 (SSABSS, SSPCSS or hard)"};
  pass.effect = FrameEffect::kShadows;
  pass.makes = {
      {.id = B::kShadowVisibility,
       .name = "shadow visibility",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 1); },
       .layers = {{"shadow.visibility", P::kShadowFilter, false, DumpPart::kImage, false,
                   "filtered light visibility of the shadowed light, [0, 1], 1 = lit; 1 on background"}},
       .heldBytes = [](const Frame& f) { return Held(f.shadowVisibility.visibility); },
       .release = [](Frame& f) { f.shadowVisibility = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.shadows && ImageSized(f, f.shadowVisibility.visibility))
               sink.Add(DumpPart::kImage, 0, "shadow.visibility", f.shadowVisibility.visibility);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load(DumpPart::kImage, 0, "shadow.visibility", f.shadowVisibility.visibility); }},
  };
  pass.reads = {B::kGBufferWords, B::kShadowTerm};
  pass.stats = {{"shadow filter", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.shadowFilter) return std::nullopt;
                   return Row(s.shadowFilter->ms, double(s.pixels), "pixels");
                 }}};
  pass.step = ShadowFilterStep;
  return pass;
}

// ---- Direct light (passes/direct_light.h) ----

void DirectLightStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.Runs(P::kDirectLight)) return;
  DirectLightInputs inputs{f.gbuffer.gbuffer, f.view, s.scene};
  inputs.shadeLights = &f.plan.lightReaches;
  if (f.shadows) {
    inputs.lightVisibility = &f.shadowVisibility.visibility;
    inputs.shadowedLight = f.plan.shadowLight.value_or(0);
  }
  // Pixels without geometry show the environment's mean radiance (the sky light, where it runs,
  // puts the environment's own there).
  DirectLightParams params = s.config.directLight;
  params.background = s.config.environment.MeanRadiance();
  f.stats.directLight = RunDirectLight(inputs, params, f.direct);
}

const char kDirectMeaning[] = "direct radiance, linear RGB, [0, 65504]; background colour";

PassDeclaration DirectLightPass() {
  PassDeclaration pass{P::kDirectLight, "direct_light", "each light's BRDF term times its visibility"};
  pass.makes = {
      {.id = B::kDirect,
       .name = "direct light",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 3); },
       .layers = {{"direct.R", P::kDirectLight, false, DumpPart::kImage, false, kDirectMeaning},
                  {"direct.G", P::kDirectLight, false, DumpPart::kImage, false, kDirectMeaning},
                  {"direct.B", P::kDirectLight, false, DumpPart::kImage, false, kDirectMeaning}},
       .heldBytes = [](const Frame& f) { return Held(f.direct.radiance); },
       .release = nullptr,  // its storage becomes the result's
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (ImageSized(f, f.direct.radiance.c[0])) sink.Add3(DumpPart::kImage, 0, "direct.", f.direct.radiance);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load3(DumpPart::kImage, 0, "direct.", f.direct.radiance); }},
  };
  pass.reads = {B::kGBufferWords, B::kShadowVisibility};
  pass.stats = {
      {"direct light", [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.directLight) return std::nullopt;
         return Row(s.directLight->ms, double(s.pixels), "pixels");
       }}};
  pass.step = DirectLightStep;
  return pass;
}

// ---- Sky light (passes/sky_light.h): the environment's diffuse light, under the sky's visibility ----

bool SameSkyVisibilityParams(const SkyVisibilityParams& a, const SkyVisibilityParams& b) {
  return a.directions == b.directions && a.mapSize == b.mapSize && a.cellsOnLongestAxis == b.cellsOnLongestAxis;
}

void SkyLightStep(FrameStep& s) {
  Frame& f = s.frame;
  // The environment's tables and the scene's visibility volume outlive the frame while they hold.
  if (!SameEnvironment(f.environment, s.config.environment))
    f.environment = PrepareEnvironmentLighting(s.config.environment);
  if (!s.Runs(P::kSkyLight)) return;
  if (s.config.skyVisibility.directions == 0) {
    f.skyVolume.reset();
  } else if (!f.skyVolume || f.skyVolume->meshHash != MeshGeometryHash(s.scene.mesh) ||
             !SameSkyVisibilityParams(f.skyVolume->params, s.config.skyVisibility)) {
    Stopwatch build;
    f.skyVolume = BuildSkyVisibility(s.scene, s.config.skyVisibility);
    f.stats.skyVisibilityMs = build.Lap();
  }
  if (!f.skyVolume || !SkyMakesInterreflection(s.config)) {
    f.interreflection.reset();
  } else if (!f.interreflection ||
             !WorldBounceHolds(*f.interreflection, s.scene, *f.skyVolume, f.environment, s.config.interreflection)) {
    Stopwatch build;
    f.interreflection = BuildWorldBounce(s.scene, *f.skyVolume, f.environment, s.config.interreflection);
    f.stats.interreflectionMs = build.Lap();
  }
  if (f.stats.skyVisibilityMs || f.stats.interreflectionMs) ReturnFreedMemory();
  // Freeing early, `lit` is written over the direct image: each pixel is read before it is written.
  if (s.Releases()) f.skyLight.lit = std::exchange(f.direct.radiance, {});
  const Plane3<float>& direct = s.Releases() ? f.skyLight.lit : f.direct.radiance;
  f.stats.skyLight = RunSkyLight({f.gbuffer.gbuffer, f.view, f.environment, f.skyVolume ? &*f.skyVolume : nullptr,
                                  direct, f.interreflection ? &*f.interreflection : nullptr},
                                 {}, f.skyLight);
}

const char kInterreflectionMeaning[] =
    "interreflection volume (passes/world_bounce.h), one channel: per cell k0, kx, ky, kz (E(n) / pi = k0 + k.n), "
    "laid out as the sky visibility volume";
const char kSkyDiffuseMeaning[] =
    "the sky's diffuse light: albedo (1 - metallic) E(n) / pi V, linear RGB, >= 0; 0 on background";
const char kSkyReflectedMeaning[] =
    "the interreflection volume towards the mirror direction: max(E_w(p, r) / pi, 0), linear RGB; 0 on background; "
    "only with the volume";
const char kLitMeaning[] = "direct + the sky's diffuse light, linear RGB, >= 0: what the pyramid and composite read";

PassDeclaration SkyLightPass() {
  PassDeclaration pass{
      P::kSkyLight, "sky_light",
      "the environment's diffuse light times a world-space sky visibility, and the scene's light interreflected off "
      "screen; lit = direct + both"};
  pass.effect = FrameEffect::kSky;
  pass.makes = {
      {.id = B::kSkyVolume,
       .name = "sky visibility volume",
       .frameOutput = true,  // kept for the next frame of the same scene
       .bytes = [](const FrameShape& s) { return s.skyVolumeBytes; },
       .layers = {{"k", P::kSkyLight, false, DumpPart::kSkyVolume, false,
                   "sky visibility volume: per cell k0, kx, ky, kz (V(n) = k0 + k.n), cells x fastest, 4 "
                   "floats a cell along a row of 4 * cellsX; rows y, then z"},
                  {"interreflection.R", P::kSkyLight, false, DumpPart::kSkyVolume, false, kInterreflectionMeaning},
                  {"interreflection.G", P::kSkyLight, false, DumpPart::kSkyVolume, false, kInterreflectionMeaning},
                  {"interreflection.B", P::kSkyLight, false, DumpPart::kSkyVolume, false, kInterreflectionMeaning}},
       .heldBytes =
           [](const Frame& f) {
             size_t bytes = f.skyVolume ? f.skyVolume->coefficients.capacity() * sizeof(float) : 0;
             if (f.interreflection)
               for (const std::vector<float>& channel : f.interreflection->coefficients)
                 bytes += channel.capacity() * sizeof(float);
             return bytes;
           },
       .release = nullptr,
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.sky && f.skyVolume)
               sink.AddSkyVolume(*f.skyVolume, f.interreflection ? &*f.interreflection : nullptr);
           }},
      {.id = B::kSkyDiffuse,
       .name = "sky light",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, s.interreflection ? 7 : 4); },
       .layers = {{"sky.diffuse.R", P::kSkyLight, false, DumpPart::kImage, false, kSkyDiffuseMeaning},
                  {"sky.diffuse.G", P::kSkyLight, false, DumpPart::kImage, false, kSkyDiffuseMeaning},
                  {"sky.diffuse.B", P::kSkyLight, false, DumpPart::kImage, false, kSkyDiffuseMeaning},
                  {"sky.visibility", P::kSkyLight, false, DumpPart::kImage, false,
                   "world-space sky visibility V(p, n), [0, 1]; 1 on background"},
                  {"sky.reflected.R", P::kSkyLight, false, DumpPart::kImage, false, kSkyReflectedMeaning},
                  {"sky.reflected.G", P::kSkyLight, false, DumpPart::kImage, false, kSkyReflectedMeaning},
                  {"sky.reflected.B", P::kSkyLight, false, DumpPart::kImage, false, kSkyReflectedMeaning}},
       .heldBytes =
           [](const Frame& f) {
             return Held(f.skyLight.diffuse) + Held(f.skyLight.visibility) + Held(f.skyLight.reflected);
           },
       .release =
           [](Frame& f) {
             f.skyLight.diffuse = {};
             f.skyLight.visibility = {};
             f.skyLight.reflected = {};
           },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (!f.sky || !ImageSized(f, f.skyLight.visibility)) return;
             sink.Add3(DumpPart::kImage, 0, "sky.diffuse.", f.skyLight.diffuse);
             sink.Add(DumpPart::kImage, 0, "sky.visibility", f.skyLight.visibility);
             if (ImageSized(f, f.skyLight.reflected.c[0]))
               sink.Add3(DumpPart::kImage, 0, "sky.reflected.", f.skyLight.reflected);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             source.Load3(DumpPart::kImage, 0, "sky.diffuse.", f.skyLight.diffuse);
             source.Load(DumpPart::kImage, 0, "sky.visibility", f.skyLight.visibility);
             // Only a frame with the interreflection volume has it.
             if (source.Has(DumpPart::kImage, 0, "sky.reflected.R"))
               source.Load3(DumpPart::kImage, 0, "sky.reflected.", f.skyLight.reflected);
             else
               f.skyLight.reflected = {};
           }},
      {.id = B::kLit,
       .name = "lit image",
       .storageOf = B::kDirect,  // freeing early, written over the direct image
       .bytes = [](const FrameShape& s) { return s.handOver ? 0 : ImagePlanes(s, 3); },
       .layers = {{"lit.R", P::kSkyLight, false, DumpPart::kImage, false, kLitMeaning},
                  {"lit.G", P::kSkyLight, false, DumpPart::kImage, false, kLitMeaning},
                  {"lit.B", P::kSkyLight, false, DumpPart::kImage, false, kLitMeaning}},
       .heldBytes = [](const Frame& f) { return Held(f.skyLight.lit); },
       .release = nullptr,  // its storage becomes the result's
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.sky && ImageSized(f, f.skyLight.lit.c[0])) sink.Add3(DumpPart::kImage, 0, "lit.", f.skyLight.lit);
           },
       .load = [](const DumpSource& source, Frame& f) { source.Load3(DumpPart::kImage, 0, "lit.", f.skyLight.lit); },
       // Without the sky light its readers read the direct image.
       .absentAs = B::kDirect},
  };
  pass.reads = {B::kGBufferWords, B::kDirect};
  pass.scratchName = "sky visibility volume build";
  pass.scratchBytes = [](const FrameShape& s) { return s.skyVolumeBuildBytes; };
  pass.stats = {
      {"sky visibility",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.skyVisibilityMs) return std::nullopt;
         return Row(*s.skyVisibilityMs, 0.0, "");
       }},
      {"interreflection volume",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.interreflectionMs) return std::nullopt;
         return Row(*s.interreflectionMs, 0.0, "");
       }},
      {"sky light",
       [](const FrameStats& s) -> std::optional<StageStats> {
         if (!s.skyLight) return std::nullopt;
         return Row(s.skyLight->ms, double(s.skyLight->pixels), "pixels");
       }},
  };
  pass.step = SkyLightStep;
  return pass;
}

// ---- Diffuse bounce and ambient occlusion (passes/bounce.h) ----

void BounceStep(FrameStep& s) {
  Frame& f = s.frame;
  if (s.Runs(P::kBounce))
    f.stats.bounce = RunBounce({f.gbuffer.gbuffer, f.view, f.Lit()}, s.config.diffuseBounce, f.diffuseBounce);
}

// The bounce's half-resolution size: pixel (i, j) stands for full-resolution pixel (2i, 2j).
size_t HalfSide(size_t side) { return (side + 1) / 2; }

const char kBounceMeaning[] =
    "the bounce: E / pi, the cosine-weighted mean radiance arriving from on-screen surfaces, linear RGB, [0, 65504]; "
    "0 on background";
const char kBounceHalfNormalMeaning[] = "decoded view-space unit normal of pixel (2i, 2j); 0 on background";
const char kBounceHalfLitMeaning[] = "the lit image at pixel (2i, 2j), sanitised: linear RGB, [0, 65504]";
const char kBounceMarchMeaning[] = "the march's bounce, E / pi, linear RGB, [0, 65504]; 0 on background";
const char kBounceRowsMeaning[] = "the filter's pass along rows over the march's bounce; 0 on background";
const char kBounceFilteredMeaning[] = "the filter's pass along columns over the rows' bounce; 0 on background";

// The half-resolution planes with their layer names, in the catalogue's order.
template <class Visit>
void ForEachBounceHalfPlane(const BounceHalfRes& h, Visit visit) {
  visit("depth", h.depth);
  visit("normal.X", h.normal.c[0]);
  visit("normal.Y", h.normal.c[1]);
  visit("normal.Z", h.normal.c[2]);
  visit("normalCode", h.normalCode);
  visit("lit.R", h.lit.c[0]);
  visit("lit.G", h.lit.c[1]);
  visit("lit.B", h.lit.c[2]);
  visit("march.visibility", h.visibility);
  visit("march.R", h.bounce.c[0]);
  visit("march.G", h.bounce.c[1]);
  visit("march.B", h.bounce.c[2]);
  visit("rows.visibility", h.horizontalVisibility);
  visit("rows.R", h.horizontalBounce.c[0]);
  visit("rows.G", h.horizontalBounce.c[1]);
  visit("rows.B", h.horizontalBounce.c[2]);
  visit("filtered.visibility", h.filteredVisibility);
  visit("filtered.R", h.filteredBounce.c[0]);
  visit("filtered.G", h.filteredBounce.c[1]);
  visit("filtered.B", h.filteredBounce.c[2]);
}

PassDeclaration BouncePass() {
  PassDeclaration pass{P::kBounce, "bounce",
                       "diffuse bounce and ambient occlusion by the visibility bitmask, at half resolution, "
                       "filtered and upsampled"};
  pass.effect = FrameEffect::kBounce;
  const auto half = [](std::string_view name, bool isUint, std::string_view meaning) {
    return DumpLayer{name, P::kBounce, isUint, DumpPart::kBounceHalf, false, meaning};
  };
  pass.makes = {
      {.id = B::kBounceHalf,
       .name = "bounce half-resolution steps",
       // 19 float planes and the normal codes' uint32 plane.
       .bytes =
           [](const FrameShape& s) {
             const size_t width = HalfSide(s.width), height = HalfSide(s.height);
             return 19 * PlaneBytes(width, height) + PlaneBytes<uint32_t>(width, height);
           },
       .layers = {half("depth", false, "view depth of pixel (2i, 2j), metres; +inf background"),
                  half("normal.X", false, kBounceHalfNormalMeaning),
                  half("normal.Y", false, kBounceHalfNormalMeaning),
                  half("normal.Z", false, kBounceHalfNormalMeaning),
                  half("normalCode", true,
                       "G-buffer word 1's normal code (bits 0-23) of pixel (2i, 2j); 0 on background"),
                  half("lit.R", false, kBounceHalfLitMeaning),
                  half("lit.G", false, kBounceHalfLitMeaning),
                  half("lit.B", false, kBounceHalfLitMeaning),
                  half("march.visibility", false, "the march's ambient visibility, [0, 1]; 1 on background"),
                  half("march.R", false, kBounceMarchMeaning),
                  half("march.G", false, kBounceMarchMeaning),
                  half("march.B", false, kBounceMarchMeaning),
                  half("rows.visibility", false, "the filter's pass along rows over the march's visibility"),
                  half("rows.R", false, kBounceRowsMeaning),
                  half("rows.G", false, kBounceRowsMeaning),
                  half("rows.B", false, kBounceRowsMeaning),
                  half("filtered.visibility", false, "the filter's pass along columns over the rows' visibility"),
                  half("filtered.R", false, kBounceFilteredMeaning),
                  half("filtered.G", false, kBounceFilteredMeaning),
                  half("filtered.B", false, kBounceFilteredMeaning)},
       .heldBytes =
           [](const Frame& f) {
             size_t bytes = 0;
             ForEachBounceHalfPlane(f.diffuseBounce.half,
                                    [&](std::string_view, const auto& plane) { bytes += Held(plane); });
             return bytes;
           },
       .release = [](Frame& f) { f.diffuseBounce.half = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             const BounceHalfRes& h = f.diffuseBounce.half;
             if (!f.bounce || h.depth.xsize() != HalfSide(size_t(f.gbuffer.gbuffer.width()))) return;
             ForEachBounceHalfPlane(
                 h, [&](std::string_view name, const auto& plane) { sink.Add(DumpPart::kBounceHalf, 0, name, plane); });
           }},
      {.id = B::kBounce,
       .name = "bounce",
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, 4); },
       .layers = {{"bounce.R", P::kBounce, false, DumpPart::kImage, false, kBounceMeaning},
                  {"bounce.G", P::kBounce, false, DumpPart::kImage, false, kBounceMeaning},
                  {"bounce.B", P::kBounce, false, DumpPart::kImage, false, kBounceMeaning},
                  {"bounce.visibility", P::kBounce, false, DumpPart::kImage, false,
                   "ambient visibility: the cosine-weighted share of the hemisphere no on-screen surface within "
                   "the radius covers, [0, 1]; 1 on background"}},
       .heldBytes = [](const Frame& f) { return Held(f.diffuseBounce.bounce) + Held(f.diffuseBounce.visibility); },
       .release =
           [](Frame& f) {
             f.diffuseBounce.bounce = {};
             f.diffuseBounce.visibility = {};
           },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (!f.bounce || !ImageSized(f, f.diffuseBounce.visibility)) return;
             sink.Add3(DumpPart::kImage, 0, "bounce.", f.diffuseBounce.bounce);
             sink.Add(DumpPart::kImage, 0, "bounce.visibility", f.diffuseBounce.visibility);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             source.Load3(DumpPart::kImage, 0, "bounce.", f.diffuseBounce.bounce);
             source.Load(DumpPart::kImage, 0, "bounce.visibility", f.diffuseBounce.visibility);
           }},
  };
  pass.reads = {B::kGBufferWords, B::kLit};
  pass.stats = {{"bounce", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.bounce) return std::nullopt;
                   return Row(s.bounce->ms, double(s.bounce->pixels), "pixels");
                 }}};
  pass.step = BounceStep;
  return pass;
}

// ---- Hi-Z (passes/hiz.h) ----

void HiZStep(FrameStep& s) {
  Frame& f = s.frame;
  if (s.Runs(P::kHiZ)) f.stats.hiz = RunHiZ(f.gbuffer.gbuffer.word[GBufferWord::kDepth], f.hiz);
}

PassDeclaration HiZPass() {
  PassDeclaration pass{P::kHiZ, "hiz", "the max-inverse-depth pyramid the trace marches"};
  pass.effect = FrameEffect::kReflections;
  pass.makes = {
      {.id = B::kHiZ,
       .name = "hi-z",
       .bytes =
           [](const FrameShape& s) {
             size_t bytes = 0;
             for (const PyramidSize& level : PyramidLevelSizes(s.width, s.height))
               bytes += PlaneBytes(level.width, level.height);
             return bytes;
           },
       .layers = {{"Y", P::kHiZ, false, DumpPart::kHiZLevels, false,
                   "Hi-Z level L: max inverse view depth 1/d over the texel's footprint, 1/metres, >= 0; 0 = "
                   "background only"}},
       .heldBytes = [](const Frame& f) { return HeldLevels(f.hiz.levels); },
       .release = [](Frame& f) { f.hiz = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.reflections) DumpLevels(DumpPart::kHiZLevels, f.hiz.levels, sink);
           },
       .load = [](const DumpSource& source, Frame& f) { source.LoadLevels(f.hiz.levels); }},
  };
  pass.reads = {B::kGBufferWords};
  pass.stats = {{"hi-z", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.hiz) return std::nullopt;
                   return Row(s.hiz->ms, double(s.hiz->texels), "texels");
                 }}};
  pass.step = HiZStep;
  return pass;
}

// ---- Colour pyramid (passes/color_pyramid.h) ----

// Made after the trace (FrameSteps): where few pixels reflect, only the texels their cones read.
void ColorPyramidStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.DirectInPyramid()) {
    if (s.Runs(P::kColorPyramid)) f.stats.colorPyramid = RunColorPyramid(f.Lit(), f.colorPyramid);
    return;
  }
  std::optional<ColorPyramidNeeds> needs;
  if (s.Runs(P::kSsrTrace) && s.Runs(P::kSsrCone) &&
      f.plan.reflections.pixels <= f.plan.pixels / kPartialPyramidShare) {
    needs = SsrConePyramidNeeds(f.gbuffer.gbuffer.word[GBufferWord::kNormalRoughness], f.ssrTrace.hitX, f.ssrTrace.hitY,
                                f.ssrTrace.confidence, &f.plan.reflectionTiles, f.plan.pixels / 2);
  }
  // The lit image is already sanitised: it is level 0 until the cone trace has read it.
  f.colorPyramid.levels.resize(std::max<size_t>(f.colorPyramid.levels.size(), 1));
  f.colorPyramid.levels[0] = std::exchange(f.sky ? f.skyLight.lit : f.direct.radiance, {});
  f.stats.colorPyramid = RunColorPyramidOnLevelZero(f.colorPyramid, KernelPath::kSimd, needs ? &*needs : nullptr);
}

PassDeclaration ColorPyramidPass() {
  PassDeclaration pass{P::kColorPyramid, "color_pyramid", "the direct image pre-convolved level by level"};
  pass.effect = FrameEffect::kReflections;
  pass.makes = {
      {.id = B::kColorPyramid,
       .name = "colour pyramid",
       .storageOf = B::kLit,  // level 0 is the lit image
       .bytes =
           [](const FrameShape& s) {
             size_t bytes = 0;
             const std::vector<PyramidSize> levels = PyramidLevelSizes(s.width, s.height);
             for (size_t k = s.handOver ? 1 : 0; k < levels.size(); ++k)
               bytes += 3 * PlaneBytes(levels[k].width, levels[k].height);
             return bytes;
           },
       .layers = {{"R", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
                   "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"},
                  {"G", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
                   "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"},
                  {"B", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
                   "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"}},
       .heldBytes = [](const Frame& f) { return HeldLevels(f.colorPyramid.levels); },
       .release = [](Frame& f) { f.colorPyramid = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.reflections) DumpLevels(DumpPart::kPyramidLevels, f.colorPyramid.levels, sink);
           },
       .load = [](const DumpSource& source, Frame& f) { source.LoadLevels(f.colorPyramid.levels); }},
  };
  // The trace's hits name the texels a partial pyramid makes.
  pass.reads = {B::kLit, B::kSsrTrace};
  pass.stats = {{"colour pyramid", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.colorPyramid) return std::nullopt;
                   return Row(s.colorPyramid->ms, double(s.colorPyramid->texels), "texels");
                 }}};
  pass.step = ColorPyramidStep;
  return pass;
}

// ---- SSR trace (passes/ssr_trace.h) ----

void SsrTraceStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.Runs(P::kSsrTrace)) return;
  // Only the plan's reflection tiles can trace.
  f.stats.ssrTrace = RunSsrTrace({f.gbuffer.gbuffer, f.view, f.hiz, &f.plan.reflectionTiles, s.LeavesSkippedTiles()},
                                 s.config.ssrTrace, f.ssrTrace, KernelPath::kSimd,
                                 s.Undumped() ? SsrTraceSteps::kSkip : SsrTraceSteps::kRecord);  // for dumps
}

const char kReflectedMeaning[] = "cone-traced radiance before the specular weight, linear, [0, 65504]; 0 without hit";

PassDeclaration SsrTracePass() {
  PassDeclaration pass{P::kSsrTrace, "ssr_trace", "each smooth pixel's reflected ray marched through the Hi-Z"};
  pass.effect = FrameEffect::kReflections;
  pass.makes = {
      {.id = B::kSsrTrace,
       .name = "ssr hits, confidence and steps",
       // The steps are recorded only for a dump.
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, s.handOver ? 3 : 4); },
       .layers = {{"ssr.hitX", P::kSsrTrace, false, DumpPart::kImage, false,
                   "trace hit, level-0 pixel coordinates (centres at +0.5), [0, width); -1 = no hit"},
                  {"ssr.hitY", P::kSsrTrace, false, DumpPart::kImage, false,
                   "trace hit, level-0 pixel coordinates (centres at +0.5), [0, height); -1 = no hit"},
                  {"ssr.confidence", P::kSsrTrace, false, DumpPart::kImage, false,
                   "trace confidence, [0, 1]; 0 exactly where there is no hit"},
                  {"ssr.iterations", P::kSsrTrace, false, DumpPart::kImage, false,
                   "Hi-Z steps the pixel's ray took, a whole number in [0, ssr_iterations]; 0 where no ray was "
                   "traced"}},
       .heldBytes =
           [](const Frame& f) {
             const SsrTraceOutputs& t = f.ssrTrace;
             return Held(t.hitX) + Held(t.hitY) + Held(t.confidence) + Held(t.iterations);
           },
       .release = [](Frame& f) { f.ssrTrace = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             const SsrTraceOutputs& t = f.ssrTrace;
             if (!f.reflections || !ImageSized(f, t.hitX)) return;
             sink.Add(DumpPart::kImage, 0, "ssr.hitX", t.hitX);
             sink.Add(DumpPart::kImage, 0, "ssr.hitY", t.hitY);
             sink.Add(DumpPart::kImage, 0, "ssr.confidence", t.confidence);
             if (ImageSized(f, t.iterations)) sink.Add(DumpPart::kImage, 0, "ssr.iterations", t.iterations);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             SsrTraceOutputs& t = f.ssrTrace;
             source.Load(DumpPart::kImage, 0, "ssr.hitX", t.hitX);
             source.Load(DumpPart::kImage, 0, "ssr.hitY", t.hitY);
             source.Load(DumpPart::kImage, 0, "ssr.confidence", t.confidence);
             if (source.Has(DumpPart::kImage, 0, "ssr.iterations"))
               source.Load(DumpPart::kImage, 0, "ssr.iterations", t.iterations);
           }},
  };
  pass.reads = {B::kGBufferWords, B::kHiZ};
  pass.stats = {{"ssr trace", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.ssrTrace) return std::nullopt;
                   return Row(s.ssrTrace->ms, double(s.ssrTrace->rays), "rays");
                 }}};
  pass.step = SsrTraceStep;
  return pass;
}

// ---- Cone trace (passes/ssr_cone.h) ----

void SsrConeStep(FrameStep& s) {
  Frame& f = s.frame;
  // Freeing early, the hits' planes become the reflection's red and green: the cone trace reads a
  // pixel's hit before it writes its reflection.
  if (s.Releases()) {
    f.ssrCone.reflected.c[0] = std::exchange(f.ssrTrace.hitX, {});
    f.ssrCone.reflected.c[1] = std::exchange(f.ssrTrace.hitY, {});
  }
  if (s.Runs(P::kSsrCone)) {
    const Plane3<float>& reflected = f.ssrCone.reflected;
    const Plane<float>& hitX = s.Releases() ? reflected.c[0] : f.ssrTrace.hitX;
    const Plane<float>& hitY = s.Releases() ? reflected.c[1] : f.ssrTrace.hitY;
    // The cone skips the tiles the trace skipped only after this run's trace: hits read from a
    // port's file are taken as they are.
    const TileMask* tracedTiles = s.Runs(P::kSsrTrace) ? &f.plan.reflectionTiles : nullptr;
    f.stats.ssrCone = RunSsrCone(
        {f.gbuffer.gbuffer, f.colorPyramid, hitX, hitY, f.ssrTrace.confidence, tracedTiles, s.LeavesSkippedTiles()},
        s.config.ssrCone, f.ssrCone);
  }
  if (s.DirectInPyramid()) (f.sky ? f.skyLight.lit : f.direct.radiance) = std::exchange(f.colorPyramid.levels[0], {});
}

PassDeclaration SsrConePass() {
  PassDeclaration pass{P::kSsrCone, "ssr_cone", "each hit's radiance gathered over the roughness cone"};
  pass.effect = FrameEffect::kReflections;
  pass.makes = {
      {.id = B::kReflected,
       .name = "cone trace",
       .storageOf = B::kSsrTrace,  // the hits' planes hold the reflection's red and green
       .bytes = [](const FrameShape& s) { return ImagePlanes(s, s.handOver ? 1 : 3); },
       .layers = {{"ssr.reflected.R", P::kSsrCone, false, DumpPart::kImage, false, kReflectedMeaning},
                  {"ssr.reflected.G", P::kSsrCone, false, DumpPart::kImage, false, kReflectedMeaning},
                  {"ssr.reflected.B", P::kSsrCone, false, DumpPart::kImage, false, kReflectedMeaning}},
       .heldBytes = [](const Frame& f) { return Held(f.ssrCone.reflected); },
       .release = [](Frame& f) { f.ssrCone = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.reflections && ImageSized(f, f.ssrCone.reflected.c[0]))
               sink.Add3(DumpPart::kImage, 0, "ssr.reflected.", f.ssrCone.reflected);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load3(DumpPart::kImage, 0, "ssr.reflected.", f.ssrCone.reflected); }},
  };
  pass.reads = {B::kGBufferWords, B::kColorPyramid, B::kSsrTrace};
  pass.stats = {{"cone trace", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.ssrCone) return std::nullopt;
                   return Row(s.ssrCone->ms, double(s.ssrCone->pixels), "pixels");
                 }}};
  pass.step = SsrConeStep;
  return pass;
}

// ---- Composite (passes/composite.h) ----

void CompositeStep(FrameStep& s) {
  Frame& f = s.frame;
  Plane3<float>& lit = f.sky ? f.skyLight.lit : f.direct.radiance;
  // In place where no later reader needs the lit image and the reflection apart: freed, they are
  // handed on; kept for reuse, their planes trade places with the result's and the indirect term's,
  // which the next frame writes again. The composite reads a pixel before it writes over it.
  if (s.Releases()) {
    f.composite.result = std::exchange(lit, {});
    if (f.reflections) f.composite.indirect = std::exchange(f.ssrCone.reflected, {});
  } else if (s.ComposesInPlace()) {
    std::swap(f.composite.result, lit);
    if (f.reflections) std::swap(f.composite.indirect, f.ssrCone.reflected);
  }
  if (!s.Runs(P::kComposite)) return;
  const Plane3<float>& base = s.ComposesInPlace() ? f.composite.result : lit;
  const Plane3<float>* reflected = !f.reflections        ? nullptr
                                   : s.ComposesInPlace() ? &f.composite.indirect
                                                         : &f.ssrCone.reflected;
  // Only the traced tiles have indirect light, unless the sky or the bounce lights every pixel.
  const TileMask* tracedTiles =
      f.reflections && !f.sky && !f.bounce && s.Runs(P::kSsrTrace) ? &f.plan.reflectionTiles : nullptr;
  CompositeInputs inputs{f.gbuffer.gbuffer,
                         f.view,
                         base,
                         reflected,
                         f.reflections ? &f.ssrTrace.confidence : nullptr,
                         s.config.ssrTrace.roughnessCutoff,
                         tracedTiles,
                         f.sky ? &f.environment : nullptr,
                         f.sky ? &f.skyLight.visibility : nullptr};
  if (f.sky && f.skyLight.reflected.c[0].xsize() != 0) inputs.skyReflected = &f.skyLight.reflected;
  if (f.bounce) {
    inputs.bounce = &f.diffuseBounce.bounce;
    // The bounce's visibility occludes the sky's diffuse light, which lit holds unoccluded.
    if (f.sky) {
      inputs.skyDiffuse = &f.skyLight.diffuse;
      inputs.ambientVisibility = &f.diffuseBounce.visibility;
    }
  }
  // Freeing early without reflections, nothing reads the indirect term alone.
  inputs.keepIndirect = !(s.Releases() && !f.reflections);
  f.stats.composite = RunComposite(inputs, f.composite);
}

const char kResultMeaning[] =
    "lit (its sky light darkened by the bounce's visibility) + indirect radiance, linear, >= 0";

PassDeclaration CompositePass() {
  PassDeclaration pass{P::kComposite, "composite",
                       "indirect = (reflection, or the sky where the trace did not see) x specular weight + "
                       "bounce x diffuse albedo; result = lit (its sky light darkened by the bounce's visibility) + "
                       "indirect"};
  pass.effect = FrameEffect::kIndirect;
  pass.makes = {
      {.id = B::kIndirect,
       .name = "indirect",
       .storageOf = B::kReflected,
       .bytes = [](const FrameShape& s) { return s.handOver ? 0 : ImagePlanes(s, 3); },
       .layers = {{"indirect.R", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"},
                  {"indirect.G", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"},
                  {"indirect.B", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"}},
       .heldBytes = [](const Frame& f) { return Held(f.composite.indirect); },
       .release = [](Frame& f) { f.composite.indirect = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.Has(FrameEffect::kIndirect) && ImageSized(f, f.composite.result.c[0]) &&
                 ImageSized(f, f.composite.indirect.c[0]))
               sink.Add3(DumpPart::kImage, 0, "indirect.", f.composite.indirect);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load3(DumpPart::kImage, 0, "indirect.", f.composite.indirect); },
       .carriedThrough = true},
      {.id = B::kResult,
       .name = "result",
       .frameOutput = true,
       .storageOf = B::kLit,
       .bytes = [](const FrameShape& s) { return s.handOver ? 0 : ImagePlanes(s, 3); },
       .layers = {{"result.R", P::kComposite, false, DumpPart::kImage, false, kResultMeaning},
                  {"result.G", P::kComposite, false, DumpPart::kImage, false, kResultMeaning},
                  {"result.B", P::kComposite, false, DumpPart::kImage, false, kResultMeaning}},
       .heldBytes = [](const Frame& f) { return Held(f.composite.result); },
       .release = nullptr,  // a frame output
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.Has(FrameEffect::kIndirect) && ImageSized(f, f.composite.result.c[0]))
               sink.Add3(DumpPart::kImage, 0, "result.", f.composite.result);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load3(DumpPart::kImage, 0, "result.", f.composite.result); },
       // Without the composite the final image is the lit (the direct) image.
       .absentAs = B::kLit},
  };
  pass.reads = {B::kGBufferWords, B::kLit, B::kReflected, B::kSsrTrace, B::kSkyDiffuse, B::kBounce};
  pass.stats = {{"composite", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.composite) return std::nullopt;
                   return Row(s.composite->ms, double(s.composite->pixels), "pixels");
                 }}};
  pass.step = CompositeStep;
  return pass;
}

// ---- Morphological anti-aliasing (passes/mlaa.h) ----

void MlaaStep(FrameStep& s) {
  Frame& f = s.frame;
  if (s.config.antialiasing != Antialiasing::kMlaa || !s.Runs(P::kMlaa)) return;
  f.stats.mlaa = RunMlaa({f.Composed()}, {.exposureEv = s.config.tonemap.exposureEv}, f.mlaa);
}

const char kMlaaLumaMeaning[] = "the perceptual luma the edges are found in: sqrt(t / (1 + t)), t the luminance x 2^EV";
const char kMlaaEdgesMeaning[] = "bit 0: a luma edge with the left neighbour, bit 1: with the upper neighbour";
const char kMlaaWeightsMeaning[] =
    "the left and top edges' blend weights in 1/256: byte 0 this pixel's colour over the left neighbour, byte 1 "
    "the left neighbour's over this pixel, bytes 2-3 the same with the upper neighbour";
const char kMlaaCoverageMeaning[] =
    "the edge coverage word the weights give: bytes 0-3 the left, right, upper, lower neighbour's share, in 1/256";

PassDeclaration MlaaPass() {
  PassDeclaration pass{P::kMlaa, "mlaa",
                       "morphological anti-aliasing: the final image's luma edges and the coverage their runs outline"};
  pass.effect = FrameEffect::kAntialias;
  pass.makes = {
      {.id = B::kMlaa,
       .name = "morphological edges and coverage",
       .bytes =
           [](const FrameShape& s) {
             return s.mlaa ? PlaneBytes<float>(s.width, s.height) + 3 * PlaneBytes<uint32_t>(s.width, s.height) : 0;
           },
       .layers = {{"mlaa.luma", P::kMlaa, false, DumpPart::kImage, false, kMlaaLumaMeaning},
                  {"mlaa.edges", P::kMlaa, true, DumpPart::kImage, false, kMlaaEdgesMeaning},
                  {"mlaa.weights", P::kMlaa, true, DumpPart::kImage, false, kMlaaWeightsMeaning},
                  {"mlaa.coverage", P::kMlaa, true, DumpPart::kImage, false, kMlaaCoverageMeaning}},
       .heldBytes =
           [](const Frame& f) {
             return Held(f.mlaa.luma) + Held(f.mlaa.edges) + Held(f.mlaa.weights) + Held(f.mlaa.coverage);
           },
       .release = [](Frame& f) { f.mlaa = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (!ImageSized(f, f.mlaa.coverage)) return;
             sink.Add(DumpPart::kImage, 0, "mlaa.luma", f.mlaa.luma);
             sink.Add(DumpPart::kImage, 0, "mlaa.edges", f.mlaa.edges);
             sink.Add(DumpPart::kImage, 0, "mlaa.weights", f.mlaa.weights);
             sink.Add(DumpPart::kImage, 0, "mlaa.coverage", f.mlaa.coverage);
           },
       .load =
           [](const DumpSource& source, Frame& f) {
             if (!source.Has(DumpPart::kImage, 0, "mlaa.coverage")) return;
             source.Load(DumpPart::kImage, 0, "mlaa.luma", f.mlaa.luma);
             source.Load(DumpPart::kImage, 0, "mlaa.edges", f.mlaa.edges);
             source.Load(DumpPart::kImage, 0, "mlaa.weights", f.mlaa.weights);
             source.Load(DumpPart::kImage, 0, "mlaa.coverage", f.mlaa.coverage);
           }},
  };
  pass.reads = {B::kResult};
  pass.stats = {{"mlaa", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.mlaa) return std::nullopt;
                   return Row(s.mlaa->ms, double(s.mlaa->edgePixels), "pixels");
                 }}};
  pass.step = MlaaStep;
  return pass;
}

// ---- Anti-aliasing (passes/antialias.h) ----

void AntialiasStep(FrameStep& s) {
  Frame& f = s.frame;
  if (!s.Runs(P::kAntialias)) return;
  // Where no dump reads the image before the anti-aliasing, in place: nothing else reads it.
  if (s.Undumped()) f.antialiased = {};
  Plane3<float>& out = s.Undumped() ? f.MutableComposed() : f.antialiased;
  const Plane<uint32_t>& coverage =
      s.config.antialiasing == Antialiasing::kMlaa ? f.mlaa.coverage : f.gbuffer.edgeCoverage;
  f.stats.antialias = RunAntialias({coverage, f.Composed()}, out);
}

const char kAntialiasedMeaning[] =
    "the final image anti-aliased across geometric edges (--aa edge) or luma edges (--aa mlaa), linear, >= 0 "
    "(result where no pixel is on an edge)";

PassDeclaration AntialiasPass() {
  PassDeclaration pass{P::kAntialias, "antialias",
                       "the final image blended across its edges (geometric or morphological) by their coverage of "
                       "each pixel"};
  pass.effect = FrameEffect::kAntialias;
  pass.makes = {
      {.id = B::kAntialiased,
       .name = "anti-aliased result",
       .storageOf = B::kResult,
       .bytes = [](const FrameShape& s) { return s.handOver ? 0 : ImagePlanes(s, 3); },
       .layers = {{"aa.result.R", P::kAntialias, false, DumpPart::kImage, false, kAntialiasedMeaning},
                  {"aa.result.G", P::kAntialias, false, DumpPart::kImage, false, kAntialiasedMeaning},
                  {"aa.result.B", P::kAntialias, false, DumpPart::kImage, false, kAntialiasedMeaning}},
       .heldBytes = [](const Frame& f) { return Held(f.antialiased); },
       .release = [](Frame& f) { f.antialiased = {}; },
       .dump =
           [](const Frame& f, DumpSink& sink) {
             if (f.antialias && ImageSized(f, f.antialiased.c[0]))
               sink.Add3(DumpPart::kImage, 0, "aa.result.", f.antialiased);
           },
       .load = [](const DumpSource& source,
                  Frame& f) { source.Load3(DumpPart::kImage, 0, "aa.result.", f.antialiased); }},
  };
  pass.reads = {B::kEdgeCoverage, B::kMlaa, B::kResult};
  pass.stats = {{"antialias", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.antialias) return std::nullopt;
                   return Row(s.antialias->ms, double(s.antialias->edgePixels), "pixels");
                 }}};
  pass.step = AntialiasStep;
  return pass;
}

// ---- Tonemap (passes/tonemap.h) ----

void TonemapStep(FrameStep& s) {
  Frame& f = s.frame;
  if (s.Runs(P::kTonemap)) f.stats.tonemap = RunTonemap(f.Result(), s.config.tonemap, f.display);
}

const char kDisplayMeaning[] = "the 8-bit image: sRGB code 0-255";

PassDeclaration TonemapPass() {
  PassDeclaration pass{P::kTonemap, "tonemap", "exposure, display curve and 8-bit sRGB encoding"};
  pass.makes = {
      {.id = B::kDisplay,
       .name = "display image",
       .frameOutput = true,
       .bytes = [](const FrameShape& s) { return s.width * s.height * 3; },
       // The image's bytes, converted to a uint32 plane per channel for the dump.
       .layers = {{"display.R", P::kTonemap, true, DumpPart::kImage, true, kDisplayMeaning},
                  {"display.G", P::kTonemap, true, DumpPart::kImage, true, kDisplayMeaning},
                  {"display.B", P::kTonemap, true, DumpPart::kImage, true, kDisplayMeaning}},
       .heldBytes = [](const Frame& f) { return f.display.rgb.capacity(); },
       .release = nullptr,  // a frame output
       .dump = [](const Frame& f, DumpSink& sink) { sink.AddDisplay(f.display); }},
  };
  pass.reads = {B::kResult, B::kAntialiased};
  pass.stats = {{"tonemap", [](const FrameStats& s) -> std::optional<StageStats> {
                   if (!s.tonemap) return std::nullopt;
                   return Row(s.tonemap->ms, double(s.tonemap->pixels), "pixels");
                 }}};
  pass.step = TonemapStep;
  return pass;
}

std::vector<PassDeclaration> MakeRegistry() {
  std::vector<PassDeclaration> passes = {GBufferPass(),   ShadowMapPass(), ShadowFilterPass(), DirectLightPass(),
                                         SkyLightPass(),  BouncePass(),    HiZPass(),          ColorPyramidPass(),
                                         SsrTracePass(),  SsrConePass(),   CompositePass(),    MlaaPass(),
                                         AntialiasPass(), TonemapPass()};
  for (size_t i = 0; i < passes.size(); ++i) SSGI_CHECK(size_t(passes[i].pass) == i);
  return passes;
}

}  // namespace

const std::vector<PassDeclaration>& FramePasses() {
  static const std::vector<PassDeclaration> passes = MakeRegistry();
  return passes;
}

const PassDeclaration& FramePassDeclaration(FramePass pass) { return FramePasses()[size_t(pass)]; }

const std::vector<MadeBuffer>& FrameBuffers() {
  static const std::vector<MadeBuffer> buffers = [] {
    std::vector<MadeBuffer> all;
    for (const PassDeclaration& pass : FramePasses())
      for (const BufferDeclaration& buffer : pass.makes) all.push_back({&buffer, &pass});
    std::sort(all.begin(), all.end(),
              [](const MadeBuffer& a, const MadeBuffer& b) { return a.buffer->id < b.buffer->id; });
    for (size_t i = 0; i < all.size(); ++i) SSGI_CHECK(size_t(all[i].buffer->id) == i);
    return all;
  }();
  return buffers;
}

const MadeBuffer& FrameBufferDeclaration(FrameBuffer buffer) { return FrameBuffers()[size_t(buffer)]; }

const std::vector<FramePass>& FrameSteps() {
  static const std::vector<FramePass> steps = {
      P::kGBuffer,  P::kShadowMap,    P::kShadowFilter, P::kDirectLight, P::kSkyLight, P::kBounce,    P::kHiZ,
      P::kSsrTrace, P::kColorPyramid, P::kSsrCone,      P::kComposite,   P::kMlaa,     P::kAntialias, P::kTonemap};
  return steps;
}

size_t StepOf(FramePass pass) {
  const std::vector<FramePass>& steps = FrameSteps();
  return size_t(std::find(steps.begin(), steps.end(), pass) - steps.begin());
}

std::optional<size_t> LastStepOf(FrameBuffer id) {
  const MadeBuffer& made = FrameBufferDeclaration(id);
  if (made.buffer->frameOutput) return std::nullopt;
  size_t last = StepOf(made.maker->pass);
  for (const PassDeclaration& pass : FramePasses())
    if (std::find(pass.reads.begin(), pass.reads.end(), id) != pass.reads.end())
      last = std::max(last, StepOf(pass.pass));
  for (const MadeBuffer& other : FrameBuffers()) {
    if (other.buffer->storageOf != id) continue;
    const std::optional<size_t> end = LastStepOf(other.buffer->id);
    if (!end) return std::nullopt;
    last = std::max(last, *end);
  }
  return last;
}

}  // namespace ssgi
