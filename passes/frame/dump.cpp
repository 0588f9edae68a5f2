// The frame's buffers as named EXR layers: the catalogue, the writer and the reader.
#include "passes/frame/dump.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <type_traits>
#include <sstream>

#include "core/error.h"
#include "core/gbuffer.h"
#include "core/pyramid.h"

namespace ssgi {
namespace {

constexpr const char* kRgb[] = {"R", "G", "B"};

template <class T>
ExrChannel Channel(std::string name, const Plane<T>& plane) {
  static_assert(sizeof(T) == 4);
  return {std::move(name), std::is_same_v<T, uint32_t>, plane.ConstRow(0), size_t(plane.PixelsPerRow())};
}

// The G-buffer's fields decoded per pixel, in the catalogue's order of the decoded layers.
struct DecodedGBuffer {
  static constexpr const char* kNames[] = {"albedo.R", "albedo.G", "albedo.B", "metallic", "normal.X", "normal.Y",
                                           "normal.Z", "roughness", "depth"};
  static constexpr int kCount = 9;
  std::vector<Plane<float>> planes;

  explicit DecodedGBuffer(const GBuffer& g) {
    const int width = g.width(), height = g.height();
    for (int i = 0; i < kCount; ++i) planes.push_back(MakePlane<float>(width, height, 0.0f));
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const uint32_t w0 = g.word[GBufferWord::kAlbedoMetallic].ConstRow(y)[x],
                       w1 = g.word[GBufferWord::kNormalRoughness].ConstRow(y)[x],
                       w2 = g.word[GBufferWord::kDepth].ConstRow(y)[x];
        const float depth = UnpackDepth(w2);
        const glm::vec3 albedo = UnpackAlbedo(w0);
        const glm::vec3 normal = depth == kBackgroundDepth ? glm::vec3(0.0f) : UnpackNormal(w1, g.normalEncoding);
        const float values[kCount] = {albedo.x, albedo.y, albedo.z, UnpackMetallic(w0), normal.x,
                                      normal.y, normal.z, UnpackRoughness(w1), depth};
        for (int i = 0; i < kCount; ++i) planes[size_t(i)].MutableRow(y)[x] = values[i];
      }
    }
  }
};

// Word 3's two fields, decoded.
struct DecodedShadowTerm {
  Plane<float> hard, blocker;
  explicit DecodedShadowTerm(const Plane<uint32_t>& word3)
      : hard(MakePlane<float>(word3.xsize(), word3.ysize(), 0.0f)),
        blocker(MakePlane<float>(word3.xsize(), word3.ysize(), 0.0f)) {
    for (size_t y = 0; y < word3.ysize(); ++y) {
      for (size_t x = 0; x < word3.xsize(); ++x) {
        const uint32_t w3 = word3.ConstRow(y)[x];
        hard.MutableRow(y)[x] = UnpackHardShadow(w3) ? 1.0f : 0.0f;
        blocker.MutableRow(y)[x] = UnpackBlockerDistance(w3);
      }
    }
  }
};

// The display image's 8-bit codes, one uint32 plane per channel.
Plane3<uint32_t> DisplayCodes(const TonemapOutputs& display, size_t width, size_t height) {
  Plane3<uint32_t> codes = MakePlane3<uint32_t>(width, height, 0u);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) codes.c[c].MutableRow(y)[x] = display.rgb[(y * width + x) * 3 + size_t(c)];
  return codes;
}

[[noreturn]] void LayerError(const std::filesystem::path& file, const std::string& part, const std::string& layer,
                             const std::string& problem) {
  throw InputError(file, "layer '" + layer + "'" + (part.empty() || part == "frame" ? "" : " of part '" + part + "'") +
                             ": " + problem);
}

// Reads the dump's layer (part, name) into `plane` (made width x height), checking it as LoadFrameDump
// documents.
template <class T>
void LoadPlane(const ExrFile& dump, const std::filesystem::path& file, const std::string& part, const std::string& name,
               size_t width, size_t height, Plane<T>& plane) {
  const ExrLayer* layer = dump.Find(part, name);
  if (layer == nullptr) LayerError(file, part, name, "missing, and a pass to run reads it");
  constexpr bool kUint = std::is_same_v<T, uint32_t>;
  if (layer->isUint != kUint)
    LayerError(file, part, name, std::string("is ") + (layer->isUint ? "uint32" : "float") + ", must be " +
                                     (kUint ? "uint32" : "float (or half)"));
  if (size_t(layer->width) != width || size_t(layer->height) != height)
    LayerError(file, part, name, "is " + std::to_string(layer->width) + "x" + std::to_string(layer->height) +
                                     ", must be " + std::to_string(width) + "x" + std::to_string(height));
  plane = MakePlane<T>(width, height, T(0));
  for (size_t y = 0; y < height; ++y) {
    T* row = plane.MutableRow(y);
    std::memcpy(row, layer->samples.data() + y * width, width * sizeof(T));
    if constexpr (!kUint) {
      for (size_t x = 0; x < width; ++x)
        if (!std::isfinite(row[x]))
          LayerError(file, part, name,
                     "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " + (std::isnan(row[x]) ? "NaN" : "infinite"));
    }
  }
}

void LoadPlane3(const ExrFile& dump, const std::filesystem::path& file, const std::string& part,
                const std::string& prefix, size_t width, size_t height, Plane3<float>& planes) {
  for (int c = 0; c < 3; ++c) LoadPlane(dump, file, part, prefix + kRgb[c], width, height, planes.c[c]);
}

bool HasLayer(const ExrFile& dump, const std::string& part, const std::string& name) {
  return dump.Find(part, name) != nullptr;
}

}  // namespace

const std::vector<DumpLayer>& DumpLayers() {
  using P = FramePass;
  static const std::vector<DumpLayer> layers = {
      {"gbuffer.word0", P::kGBuffer, true, DumpPart::kImage, false,
       "albedo R, G, B 8-bit sRGB codes (bits 0-23), metallic code (24-31)"},
      {"gbuffer.word1", P::kGBuffer, true, DumpPart::kImage, false,
       "view-space normal, 24-bit encoding (bits 0-23), perceptual roughness code (24-31)"},
      {"gbuffer.word2", P::kGBuffer, true, DumpPart::kImage, false, "view depth, float32 bits, metres; +inf background"},
      {"albedo.R", P::kGBuffer, false, DumpPart::kImage, true, "linear albedo from word 0, [0, 1]"},
      {"albedo.G", P::kGBuffer, false, DumpPart::kImage, true, "linear albedo from word 0, [0, 1]"},
      {"albedo.B", P::kGBuffer, false, DumpPart::kImage, true, "linear albedo from word 0, [0, 1]"},
      {"metallic", P::kGBuffer, false, DumpPart::kImage, true, "metallic from word 0, [0, 1]"},
      {"normal.X", P::kGBuffer, false, DumpPart::kImage, true, "view-space unit normal from word 1; 0 on background"},
      {"normal.Y", P::kGBuffer, false, DumpPart::kImage, true, "view-space unit normal from word 1; 0 on background"},
      {"normal.Z", P::kGBuffer, false, DumpPart::kImage, true, "view-space unit normal from word 1; 0 on background"},
      {"roughness", P::kGBuffer, false, DumpPart::kImage, true, "perceptual roughness from word 1, [0, 1]"},
      {"depth", P::kGBuffer, false, DumpPart::kImage, true, "view depth from word 2, metres; +inf background"},
      {"raster.depthKey", P::kGBuffer, false, DumpPart::kImage, false,
       "visibility buffer: reversed-Z depth key z_ndc of the nearest surface, (0, 1]; 0 = nothing drawn"},
      {"raster.triangle", P::kGBuffer, true, DumpPart::kImage, false,
       "visibility buffer: triangle index of the nearest surface; 0xFFFFFFFF = nothing drawn"},
      {"depthKey", P::kShadowMap, false, DumpPart::kShadowMap, false,
       "shadow map: reversed-Z depth key seen from the light, [0, 1]; 0 = nothing drawn"},
      {"gbuffer.word3", P::kShadowMap, true, DumpPart::kImage, false,
       "shadow term: hard-shadow flag (bit 31), average blocker distance float32 bits without sign (0-30); 0 = lit"},
      {"shadow.hard", P::kShadowMap, false, DumpPart::kImage, true, "hard shadow from word 3: 1 occluded, 0 lit"},
      {"shadow.blocker", P::kShadowMap, false, DumpPart::kImage, true,
       "average blocker distance from word 3, metres, >= 0; 0 = no blocker"},
      {"shadow.visibility", P::kShadowFilter, false, DumpPart::kImage, false,
       "filtered light visibility of the shadowed light, [0, 1], 1 = lit; 1 on background"},
      {"direct.R", P::kDirectLight, false, DumpPart::kImage, false, "direct radiance, linear RGB, [0, 65504]; background colour"},
      {"direct.G", P::kDirectLight, false, DumpPart::kImage, false, "direct radiance, linear RGB, [0, 65504]; background colour"},
      {"direct.B", P::kDirectLight, false, DumpPart::kImage, false, "direct radiance, linear RGB, [0, 65504]; background colour"},
      {"Y", P::kHiZ, false, DumpPart::kHiZLevels, false,
       "Hi-Z level L: max inverse view depth 1/d over the texel's footprint, 1/metres, >= 0; 0 = background only"},
      {"R", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
       "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"},
      {"G", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
       "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"},
      {"B", P::kColorPyramid, false, DumpPart::kPyramidLevels, false,
       "colour pyramid level L: blurred direct radiance, linear, [0, 65504]"},
      {"ssr.hitX", P::kSsrTrace, false, DumpPart::kImage, false,
       "trace hit, level-0 pixel coordinates (centres at +0.5), [0, width); -1 = no hit"},
      {"ssr.hitY", P::kSsrTrace, false, DumpPart::kImage, false,
       "trace hit, level-0 pixel coordinates (centres at +0.5), [0, height); -1 = no hit"},
      {"ssr.confidence", P::kSsrTrace, false, DumpPart::kImage, false,
       "trace confidence, [0, 1]; 0 exactly where there is no hit"},
      {"ssr.iterations", P::kSsrTrace, false, DumpPart::kImage, false,
       "Hi-Z steps the pixel's ray took, a whole number in [0, ssr_iterations]; 0 where no ray was traced"},
      {"ssr.reflected.R", P::kSsrCone, false, DumpPart::kImage, false,
       "cone-traced radiance before the specular weight, linear, [0, 65504]; 0 without hit"},
      {"ssr.reflected.G", P::kSsrCone, false, DumpPart::kImage, false,
       "cone-traced radiance before the specular weight, linear, [0, 65504]; 0 without hit"},
      {"ssr.reflected.B", P::kSsrCone, false, DumpPart::kImage, false,
       "cone-traced radiance before the specular weight, linear, [0, 65504]; 0 without hit"},
      {"indirect.R", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"},
      {"indirect.G", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"},
      {"indirect.B", P::kComposite, false, DumpPart::kImage, false, "indirect radiance, linear, >= 0"},
      {"result.R", P::kComposite, false, DumpPart::kImage, false, "direct + indirect radiance, linear, >= 0"},
      {"result.G", P::kComposite, false, DumpPart::kImage, false, "direct + indirect radiance, linear, >= 0"},
      {"result.B", P::kComposite, false, DumpPart::kImage, false, "direct + indirect radiance, linear, >= 0"},
      {"display.R", P::kTonemap, true, DumpPart::kImage, false, "the 8-bit image: sRGB code 0-255"},
      {"display.G", P::kTonemap, true, DumpPart::kImage, false, "the 8-bit image: sRGB code 0-255"},
      {"display.B", P::kTonemap, true, DumpPart::kImage, false, "the 8-bit image: sRGB code 0-255"},
  };
  return layers;
}

std::string DumpPartName(DumpPart part, int level) {
  switch (part) {
    case DumpPart::kImage: return "frame";
    case DumpPart::kShadowMap: return "shadowmap";
    case DumpPart::kHiZLevels: return "hiz." + std::to_string(level);
    case DumpPart::kPyramidLevels: return "pyramid." + std::to_string(level);
  }
  return "";
}

std::map<std::string, std::string> DumpMetadata(const std::string& scene, const FrameConfig& config) {
  std::string settings;
  for (const FrameSetting& setting : FrameSettings()) {
    if (!setting.get) continue;
    settings += std::string(setting.name) + "=" + FormatSettingValue(setting.get(config)) + "\n";
  }
  return {{"ssgi:scene", scene}, {"ssgi:settings", settings}};
}

void ApplyDumpSettings(const ExrFile& dump, const std::filesystem::path& file, FrameConfig& config) {
  const auto found = dump.metadata.find("ssgi:settings");
  if (found == dump.metadata.end()) return;
  std::istringstream lines(found->second);
  std::string line;
  while (std::getline(lines, line)) {
    const size_t equals = line.find('=');
    if (equals == std::string::npos) throw InputError(file, "ssgi:settings: '" + line + "' is not name=value");
    try {
      ApplySetting(config, std::string_view(line).substr(0, equals), std::string_view(line).substr(equals + 1));
    } catch (const InputError& e) {
      throw InputError(file, std::string("ssgi:settings: ") + e.what());
    }
  }
}

const ExrLayer* FindDumpLayer(const ExrFile& dump, const std::string& part, const std::string& name) {
  if (const ExrLayer* layer = dump.Find(part, name)) return layer;
  if (part == DumpPartName(DumpPart::kImage, 0)) return dump.Find("", name);
  return nullptr;
}

DumpScene LoadDumpScene(const ExrFile& dump, const std::filesystem::path& file,
                        const std::filesystem::path& sceneFile) {
  std::filesystem::path scenePath = sceneFile;
  if (scenePath.empty()) {
    const auto named = dump.metadata.find("ssgi:scene");
    if (named == dump.metadata.end()) throw InputError(file, "names no scene (no ssgi:scene metadata): give --scene");
    scenePath = named->second;
  }
  SceneFile loaded = LoadSceneFile(scenePath);
  FrameConfig config = FrameConfigFromSceneFile(loaded);
  ApplyDumpSettings(dump, file, config);
  if (const ExrLayer* words = FindDumpLayer(dump, DumpPartName(DumpPart::kImage, 0), "gbuffer.word2")) {
    config.width = words->width;
    config.height = words->height;
  }
  return {std::move(loaded.scene), config};
}

void WriteFrameDump(const std::filesystem::path& path, const Frame& frame,
                    const std::map<std::string, std::string>& metadata) {
  const GBuffer& g = frame.gbuffer.gbuffer;
  const int width = g.width(), height = g.height();
  const DecodedGBuffer decoded(g);
  const DecodedShadowTerm shadowTerm(g.word[GBufferWord::kShadowTerm]);
  std::optional<Plane3<uint32_t>> display;
  if (frame.display.rgb.size() == size_t(width) * size_t(height) * 3)
    display = DisplayCodes(frame.display, size_t(width), size_t(height));

  ExrPart image{DumpPartName(DumpPart::kImage, 0), width, height, {}};
  std::vector<ExrPart> parts;
  for (int w = 0; w < 3; ++w) image.channels.push_back(Channel("gbuffer.word" + std::to_string(w), g.word[w]));
  for (int i = 0; i < DecodedGBuffer::kCount; ++i)
    image.channels.push_back(Channel(DecodedGBuffer::kNames[i], decoded.planes[size_t(i)]));
  image.channels.push_back(Channel("raster.depthKey", frame.gbuffer.visibility.depthKey));
  image.channels.push_back(Channel("raster.triangle", frame.gbuffer.visibility.triangle));
  if (frame.shadows) {
    image.channels.push_back(Channel("gbuffer.word3", g.word[GBufferWord::kShadowTerm]));
    image.channels.push_back(Channel("shadow.hard", shadowTerm.hard));
    image.channels.push_back(Channel("shadow.blocker", shadowTerm.blocker));
    if (frame.shadowVisibility.visibility.xsize() == size_t(width))
      image.channels.push_back(Channel("shadow.visibility", frame.shadowVisibility.visibility));
  }
  if (frame.direct.radiance.c[0].xsize() == size_t(width))
    for (int c = 0; c < 3; ++c) image.channels.push_back(Channel(std::string("direct.") + kRgb[c], frame.direct.radiance.c[c]));
  if (frame.reflections) {
    if (frame.ssrTrace.hitX.xsize() == size_t(width)) {
      image.channels.push_back(Channel("ssr.hitX", frame.ssrTrace.hitX));
      image.channels.push_back(Channel("ssr.hitY", frame.ssrTrace.hitY));
      image.channels.push_back(Channel("ssr.confidence", frame.ssrTrace.confidence));
      if (frame.ssrTrace.iterations.xsize() == size_t(width))
        image.channels.push_back(Channel("ssr.iterations", frame.ssrTrace.iterations));
    }
    if (frame.ssrCone.reflected.c[0].xsize() == size_t(width))
      for (int c = 0; c < 3; ++c)
        image.channels.push_back(Channel(std::string("ssr.reflected.") + kRgb[c], frame.ssrCone.reflected.c[c]));
    if (frame.composite.result.c[0].xsize() == size_t(width)) {
      for (int c = 0; c < 3; ++c)
        image.channels.push_back(Channel(std::string("indirect.") + kRgb[c], frame.composite.indirect.c[c]));
      for (int c = 0; c < 3; ++c)
        image.channels.push_back(Channel(std::string("result.") + kRgb[c], frame.composite.result.c[c]));
    }
  }
  if (display)
    for (int c = 0; c < 3; ++c) image.channels.push_back(Channel(std::string("display.") + kRgb[c], display->c[c]));
  parts.push_back(std::move(image));

  if (frame.shadowMap) {
    const Plane<float>& depthKey = frame.shadowMap->shadowMap.depthKey;
    parts.push_back({DumpPartName(DumpPart::kShadowMap, 0), int(depthKey.xsize()), int(depthKey.ysize()),
                     {Channel("depthKey", depthKey)}});
  }
  if (frame.reflections) {
    for (size_t k = 0; k < frame.hiz.levels.size(); ++k) {
      const Plane<float>& level = frame.hiz.levels[k];
      parts.push_back({DumpPartName(DumpPart::kHiZLevels, int(k)), int(level.xsize()), int(level.ysize()),
                       {Channel("Y", level)}});
    }
    for (size_t k = 0; k < frame.colorPyramid.levels.size(); ++k) {
      const Plane3<float>& level = frame.colorPyramid.levels[k];
      ExrPart part{DumpPartName(DumpPart::kPyramidLevels, int(k)), int(level.c[0].xsize()), int(level.c[0].ysize()), {}};
      for (int c = 0; c < 3; ++c) part.channels.push_back(Channel(kRgb[c], level.c[c]));
      parts.push_back(std::move(part));
    }
  }
  WriteExrParts(path, parts, metadata);
}

void LoadFrameDump(const ExrFile& dump, const std::filesystem::path& file, const Scene& scene,
                   const FrameConfig& config, FramePass from, FramePass to, Frame& frame) {
  const size_t width = size_t(config.width), height = size_t(config.height);
  const std::string image = DumpPartName(DumpPart::kImage, 0);
  const auto before = [&](FramePass pass) { return pass < from; };
  const auto runs = [&](FramePass pass) { return from <= pass && pass <= to; };
  // A layer is loaded when an earlier pass writes it and a pass that runs reads it, or, for the
  // G-buffer words, whenever the G-buffer pass does not run: every later pass reads them.
  GBuffer& g = frame.gbuffer.gbuffer;
  g.normalEncoding = config.normalEncoding;
  if (from > FramePass::kGBuffer) {
    for (int w = 0; w < 3; ++w) LoadPlane(dump, file, image, "gbuffer.word" + std::to_string(w), width, height, g.word[w]);
    // Word 3 as the G-buffer pass leaves it, unless the shadow term is loaded below.
    g.word[GBufferWord::kShadowTerm] = MakePlane<uint32_t>(width, height, kShadowLit);
    if (HasLayer(dump, image, "raster.triangle")) {
      LoadPlane(dump, file, image, "raster.depthKey", width, height, frame.gbuffer.visibility.depthKey);
      LoadPlane(dump, file, image, "raster.triangle", width, height, frame.gbuffer.visibility.triangle);
    }
  }
  if (from == FramePass::kGBuffer) return;
  // Which effects belong to the frame: the plan on the G-buffer, as RunFramePasses will make it.
  const FramePlan plan = PlanFrame(scene, config, g, MakePerspective(scene.camera, config.width, config.height));
  const bool shadows = plan.shadows.run, reflections = plan.reflections.run;
  if (shadows && before(FramePass::kShadowMap) && (runs(FramePass::kShadowFilter) || HasLayer(dump, image, "gbuffer.word3")))
    LoadPlane(dump, file, image, "gbuffer.word3", width, height, g.word[GBufferWord::kShadowTerm]);
  if (shadows && before(FramePass::kShadowFilter) && runs(FramePass::kDirectLight))
    LoadPlane(dump, file, image, "shadow.visibility", width, height, frame.shadowVisibility.visibility);
  const bool directRead = (reflections && (runs(FramePass::kColorPyramid) || runs(FramePass::kComposite))) ||
                          (!reflections && runs(FramePass::kTonemap));
  if (before(FramePass::kDirectLight) && directRead)
    LoadPlane3(dump, file, image, "direct.", width, height, frame.direct.radiance);
  if (!reflections) return;
  const std::vector<PyramidSize> sizes = PyramidLevelSizes(width, height);
  if (before(FramePass::kHiZ) && runs(FramePass::kSsrTrace)) {
    frame.hiz.levels.resize(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k)
      LoadPlane(dump, file, DumpPartName(DumpPart::kHiZLevels, int(k)), "Y", sizes[k].width, sizes[k].height,
                frame.hiz.levels[k]);
  }
  if (before(FramePass::kColorPyramid) && runs(FramePass::kSsrCone)) {
    frame.colorPyramid.levels.resize(sizes.size());
    for (size_t k = 0; k < sizes.size(); ++k)
      LoadPlane3(dump, file, DumpPartName(DumpPart::kPyramidLevels, int(k)), "", sizes[k].width, sizes[k].height,
                 frame.colorPyramid.levels[k]);
  }
  if (before(FramePass::kSsrTrace) && (runs(FramePass::kSsrCone) || runs(FramePass::kComposite))) {
    LoadPlane(dump, file, image, "ssr.hitX", width, height, frame.ssrTrace.hitX);
    LoadPlane(dump, file, image, "ssr.hitY", width, height, frame.ssrTrace.hitY);
    LoadPlane(dump, file, image, "ssr.confidence", width, height, frame.ssrTrace.confidence);
    if (HasLayer(dump, image, "ssr.iterations"))
      LoadPlane(dump, file, image, "ssr.iterations", width, height, frame.ssrTrace.iterations);
  }
  if (before(FramePass::kSsrCone) && runs(FramePass::kComposite))
    LoadPlane3(dump, file, image, "ssr.reflected.", width, height, frame.ssrCone.reflected);
  if (before(FramePass::kComposite) && runs(FramePass::kTonemap)) {
    LoadPlane3(dump, file, image, "result.", width, height, frame.composite.result);
    if (HasLayer(dump, image, "indirect.R")) LoadPlane3(dump, file, image, "indirect.", width, height, frame.composite.indirect);
  }
}

}  // namespace ssgi
