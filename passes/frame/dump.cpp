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

bool HasLayer(const ExrFile& dump, const std::string& part, const std::string& name) {
  return dump.Find(part, name) != nullptr;
}

}  // namespace

const std::vector<DumpLayer>& DumpLayers() {
  static const std::vector<DumpLayer> layers = [] {
    std::vector<DumpLayer> all;
    for (const PassDeclaration& pass : FramePasses()) {
      const auto add = [&](FrameBuffer id) {
        for (const DumpLayer& layer : FrameBufferDeclaration(id).buffer->layers)
          if (layer.pass == pass.pass) all.push_back(layer);
      };
      for (const BufferDeclaration& buffer : pass.makes) add(buffer.id);
      for (FrameBuffer written : pass.writes) add(written);
    }
    return all;
  }();
  return layers;
}

std::string DumpPartName(DumpPart part, int level) {
  switch (part) {
    case DumpPart::kImage: return "frame";
    case DumpPart::kShadowMap: return "shadowmap";
    case DumpPart::kHiZLevels: return "hiz." + std::to_string(level);
    case DumpPart::kPyramidLevels: return "pyramid." + std::to_string(level);
    case DumpPart::kSkyVolume:
      return "skyvolume";
    case DumpPart::kBounceHalf:
      return "bounce.half";
  }
  return "";
}

std::map<std::string, std::string> DumpMetadata(const std::string& scene, const FrameConfig& config) {
  std::string settings;
  for (const FrameSetting& setting : FrameSettings()) {
    if (!setting.get || (setting.holdsValue && !setting.holdsValue(config))) continue;
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

template <class T>
void DumpSink::Add(DumpPart part, int level, std::string_view name, const Plane<T>& plane) {
  PartFor(part, level, plane.xsize(), plane.ysize()).channels.push_back(Channel(std::string(name), plane));
}

void DumpSink::Add3(DumpPart part, int level, std::string_view prefix, const Plane3<float>& planes) {
  for (int c = 0; c < 3; ++c) Add(part, level, std::string(prefix) + kRgb[c], planes.c[c]);
}

template <class T>
void DumpSink::AddOwned(DumpPart part, int level, std::string_view name, Plane<T> plane) {
  if constexpr (std::is_same_v<T, uint32_t>) {
    Add(part, level, name, uints_.emplace_back(std::move(plane)));
  } else {
    Add(part, level, name, floats_.emplace_back(std::move(plane)));
  }
}

void DumpSink::AddGBufferWords(const GBuffer& g) {
  Add(DumpPart::kImage, 0, "gbuffer.word0", g.word[GBufferWord::kAlbedoMetallic]);
  Add(DumpPart::kImage, 0, "gbuffer.word1", g.word[GBufferWord::kNormalRoughness]);
  Add(DumpPart::kImage, 0, "gbuffer.word2", g.word[GBufferWord::kDepth]);
  DecodedGBuffer decoded(g);
  for (int i = 0; i < DecodedGBuffer::kCount; ++i)
    AddOwned(DumpPart::kImage, 0, DecodedGBuffer::kNames[i], std::move(decoded.planes[size_t(i)]));
}

void DumpSink::AddShadowTerm(const Plane<uint32_t>& word3) {
  Add(DumpPart::kImage, 0, "gbuffer.word3", word3);
  DecodedShadowTerm decoded(word3);
  AddOwned(DumpPart::kImage, 0, "shadow.hard", std::move(decoded.hard));
  AddOwned(DumpPart::kImage, 0, "shadow.blocker", std::move(decoded.blocker));
}

void DumpSink::AddDisplay(const TonemapOutputs& display) {
  if (parts_.empty()) return;  // the image part sizes the display image
  const size_t width = size_t(parts_.front().width), height = size_t(parts_.front().height);
  if (display.rgb.size() != width * height * 3) return;
  Plane3<uint32_t> codes = DisplayCodes(display, width, height);
  for (int c = 0; c < 3; ++c) AddOwned(DumpPart::kImage, 0, std::string("display.") + kRgb[c], std::move(codes.c[c]));
}

void DumpSink::AddSkyVolume(const SkyVisibilityVolume& volume, const WorldBounceVolume* interreflection) {
  const size_t width = size_t(volume.cellsX) * 4, height = size_t(volume.cellsY) * size_t(volume.cellsZ);
  const auto add = [&](const std::string& name, const std::vector<float>& coefficients) {
    Plane<float> rows = MakePlane<float>(width, height, 0.0f);
    for (size_t y = 0; y < height; ++y) std::copy_n(&coefficients[y * width], width, rows.MutableRow(y));
    AddOwned(DumpPart::kSkyVolume, 0, name, std::move(rows));
  };
  add("k", volume.coefficients);
  if (interreflection)
    for (int c = 0; c < 3; ++c)
      add(std::string("interreflection.") + kRgb[c], interreflection->coefficients[size_t(c)]);
}

ExrPart& DumpSink::PartFor(DumpPart part, int level, size_t width, size_t height) {
  const std::string name = DumpPartName(part, level);
  for (ExrPart& existing : parts_)
    if (existing.name == name) return existing;
  return parts_.emplace_back(ExrPart{name, int(width), int(height), {}});
}

DumpSource::DumpSource(const ExrFile& dump, const std::filesystem::path& file, size_t width, size_t height)
    : dump_(dump), file_(file), width_(width), height_(height) {}

bool DumpSource::Has(DumpPart part, int level, std::string_view name) const {
  return HasLayer(dump_, DumpPartName(part, level), std::string(name));
}

template <class T>
void DumpSource::Load(DumpPart part, int level, std::string_view name, Plane<T>& plane) const {
  size_t width = width_, height = height_;
  if (part == DumpPart::kHiZLevels || part == DumpPart::kPyramidLevels) {
    const PyramidSize size = PyramidLevelSizes(width_, height_)[size_t(level)];
    width = size.width;
    height = size.height;
  }
  LoadPlane(dump_, file_, DumpPartName(part, level), std::string(name), width, height, plane);
}

void DumpSource::Load3(DumpPart part, int level, std::string_view prefix, Plane3<float>& planes) const {
  for (int c = 0; c < 3; ++c) Load(part, level, std::string(prefix) + kRgb[c], planes.c[c]);
}

void DumpSource::LoadLevels(std::vector<Plane<float>>& levels) const {
  levels.resize(PyramidLevelSizes(width_, height_).size());
  for (size_t k = 0; k < levels.size(); ++k) Load(DumpPart::kHiZLevels, int(k), "Y", levels[k]);
}

void DumpSource::LoadLevels(std::vector<Plane3<float>>& levels) const {
  levels.resize(PyramidLevelSizes(width_, height_).size());
  for (size_t k = 0; k < levels.size(); ++k) Load3(DumpPart::kPyramidLevels, int(k), "", levels[k]);
}

void DumpSource::LoadGBufferWords(GBuffer& g) const {
  for (int w = 0; w < 3; ++w) Load(DumpPart::kImage, 0, "gbuffer.word" + std::to_string(w), g.word[w]);
  g.word[GBufferWord::kShadowTerm] = MakePlane<uint32_t>(width_, height_, kShadowLit);
}

template void DumpSource::Load(DumpPart, int, std::string_view, Plane<float>&) const;
template void DumpSource::Load(DumpPart, int, std::string_view, Plane<uint32_t>&) const;
template void DumpSink::Add(DumpPart, int, std::string_view, const Plane<float>&);
template void DumpSink::Add(DumpPart, int, std::string_view, const Plane<uint32_t>&);

void WriteFrameDump(const std::filesystem::path& path, const Frame& frame,
                    const std::map<std::string, std::string>& metadata) {
  DumpSink sink;
  for (const MadeBuffer& made : FrameBuffers())
    if (made.buffer->dump) made.buffer->dump(frame, sink);
  WriteExrParts(path, sink.Parts(), metadata);
}

namespace {

// Which effects belong to the frame a dump is loaded into: all of them until the plan has decided.
struct EffectSet {
  bool shadows = true, reflections = true, sky = true, bounce = true, antialias = true;
  bool Has(FrameEffect effect) const { return EffectBelongs(effect, shadows, reflections, sky, bounce, antialias); }
};

}  // namespace

void LoadFrameDump(const ExrFile& dump, const std::filesystem::path& file, const Scene& scene,
                   const FrameConfig& config, FramePass from, FramePass to, Frame& frame) {
  frame.gbuffer.gbuffer.normalEncoding = config.normalEncoding;
  if (from == FramePass::kGBuffer) return;
  const DumpSource source(dump, file, size_t(config.width), size_t(config.height));
  // A buffer is loaded when every pass writing its layers comes before `from`, its effect belongs to
  // the frame, and a pass that runs reads it (or the frame plan does, or the dump has it and it is
  // carried through).
  EffectSet effects;
  const auto present = [&](FrameBuffer id) { return effects.Has(FrameBufferDeclaration(id).maker->effect); };
  const auto load = [&](const MadeBuffer& made) {
    const BufferDeclaration& buffer = *made.buffer;
    if (!buffer.load) return;
    for (const DumpLayer& layer : buffer.layers) {
      if (layer.pass >= from || !effects.Has(FramePassDeclaration(layer.pass).effect)) return;
    }
    bool read = buffer.readByPlan ||
                (buffer.carriedThrough && source.Has(buffer.layers.front().part, 0, buffer.layers.front().name));
    for (FramePass pass = from; pass <= to && !read; pass = FramePass(int(pass) + 1)) {
      const PassDeclaration& reader = FramePassDeclaration(pass);
      if (!effects.Has(reader.effect)) continue;
      for (FrameBuffer id : reader.reads) {
        // What the reader reads where the buffer's effect does not belong to the frame.
        while (!present(id) && FrameBufferDeclaration(id).buffer->absentAs)
          id = *FrameBufferDeclaration(id).buffer->absentAs;
        if (id == buffer.id) read = true;
      }
    }
    if (read) buffer.load(source, frame);
  };
  // The G-buffer pass's buffers first: the plan reads them and decides which effects belong.
  for (const MadeBuffer& made : FrameBuffers())
    if (made.maker->pass == FramePass::kGBuffer && made.buffer->readByPlan) load(made);
  const FramePlan plan = PlanFrame(scene, config, frame.gbuffer.gbuffer, frame.gbuffer.edgeCoverage,
                                   MakePerspective(scene.camera, config.width, config.height));
  effects = {plan.shadows.run, plan.reflections.run, plan.sky.run, plan.bounce.run, plan.antialias.run};
  for (const MadeBuffer& made : FrameBuffers())
    if (!made.buffer->readByPlan) load(made);
}

}  // namespace ssgi
