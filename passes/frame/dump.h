// The frame's buffers as named EXR layers (docs/pipeline.md §Dumps): what `ssgi render --dump`
// writes, what `ssgi passes` reads a port's buffers from and what `ssgi diff` compares, pass by pass.
// One catalogue, DumpLayers(), names every layer, its pass, type and meaning; the file holds a part
// "frame" of the image's size, a part "shadowmap" of the shadow map's, and a part per Hi-Z level
// ("hiz.0", "hiz.1", ...) and colour-pyramid level ("pyramid.0", ...).
#pragma once

#include <deque>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/image_io.h"
#include "core/scene.h"
#include "passes/frame/config.h"
#include "passes/frame/frame.h"
#include "passes/frame/registry.h"

namespace ssgi {

// Every layer a frame can have, in pipeline order: each pass's layers (PassDeclaration in
// passes/frame/registry.h), those of the buffers it makes, then those it writes into earlier ones.
const std::vector<DumpLayer>& DumpLayers();

// The name of the part holding `layer` at `level` (levels: 0 .. for the pyramids, ignored else).
std::string DumpPartName(DumpPart part, int level);

// The layer `name` of part `part` of a dump, or null. A port's single-part file may leave its part
// unnamed: that part is the image part "frame".
const ExrLayer* FindDumpLayer(const ExrFile& dump, const std::string& part, const std::string& name);

// Metadata a dump carries so that `ssgi passes` can rebuild the frame's configuration without the
// command line that made it: "ssgi:scene" (the scene file's absolute path) and "ssgi:settings"
// (every setting the table stores, "name=value" lines).
std::map<std::string, std::string> DumpMetadata(const std::string& scene, const FrameConfig& config);
// Applies a dump's "ssgi:settings" to config. Throws InputError naming `file` for a bad line.
void ApplyDumpSettings(const ExrFile& dump, const std::filesystem::path& file, FrameConfig& config);

// The scene a dump was rendered from and its frame configuration as the dump records it: the scene
// file `sceneFile`, or the one the dump names ("" for that), its render block, the dump's settings,
// and the image size of the dump's G-buffer words where it has them. Throws InputError naming
// `file` when it names no scene and none is given.
struct DumpScene {
  Scene scene;
  FrameConfig config;
};
DumpScene LoadDumpScene(const ExrFile& dump, const std::filesystem::path& file,
                        const std::filesystem::path& sceneFile);

// A dump being written: each buffer's declaration adds the layers the frame holds (BufferDeclaration::dump),
// as channels of named parts, a part per name in order of first appearance.
class DumpSink {
 public:
  // A channel of a plane the frame holds: the plane must outlive the write.
  template <class T>
  void Add(DumpPart part, int level, std::string_view name, const Plane<T>& plane);
  // Three channels prefix + "R", "G", "B".
  void Add3(DumpPart part, int level, std::string_view prefix, const Plane3<float>& planes);
  // The words 0-2 and their decoded fields; word 3 and its two fields; the display image's codes.
  void AddGBufferWords(const GBuffer& gbuffer);
  void AddShadowTerm(const Plane<uint32_t>& word3);
  void AddDisplay(const TonemapOutputs& display);
  // The sky visibility volume (layer k) and, where the frame made one, the interreflection volume on
  // its grid (layers interreflection.R, .G, .B), each as rows of 4 * cellsX floats, rows y then z.
  void AddSkyVolume(const SkyVisibilityVolume& volume, const WorldBounceVolume* interreflection);
  const std::vector<ExrPart>& Parts() const { return parts_; }

 private:
  ExrPart& PartFor(DumpPart part, int level, size_t width, size_t height);
  template <class T>
  void AddOwned(DumpPart part, int level, std::string_view name, Plane<T> plane);

  std::vector<ExrPart> parts_;
  // Planes decoded or converted for the dump; a deque keeps their addresses.
  std::deque<Plane<float>> floats_;
  std::deque<Plane<uint32_t>> uints_;
};

// A dump being read into a frame (BufferDeclaration::load): every layer checked as LoadFrameDump
// documents, sized by the image (`width` x `height`) or the pyramid level it belongs to.
class DumpSource {
 public:
  DumpSource(const ExrFile& dump, const std::filesystem::path& file, size_t width, size_t height);
  bool Has(DumpPart part, int level, std::string_view name) const;
  template <class T>
  void Load(DumpPart part, int level, std::string_view name, Plane<T>& plane) const;
  void Load3(DumpPart part, int level, std::string_view prefix, Plane3<float>& planes) const;
  // Every level of a Hi-Z (Plane<float>, channel "Y") or colour pyramid (Plane3<float>).
  void LoadLevels(std::vector<Plane<float>>& levels) const;
  void LoadLevels(std::vector<Plane3<float>>& levels) const;
  // Words 0-2, and word 3 as the G-buffer pass leaves it (kShadowLit), for the shadow term to overwrite.
  void LoadGBufferWords(GBuffer& gbuffer) const;

 private:
  const ExrFile& dump_;
  const std::filesystem::path& file_;
  size_t width_, height_;
};

// Writes every buffer the frame holds (the passes that ran) as the catalogue's layers.
void WriteFrameDump(const std::filesystem::path& path, const Frame& frame,
                    const std::map<std::string, std::string>& metadata);

// Fills `frame` with the layers of `dump` that passes before `from` write, so that RunFramePasses
// can run `from` .. `to` on them: the frame's configuration (size, normal encoding, which effects
// run) must be the dump's. Throws InputError naming `file` and the layer for a layer that those
// passes read and the dump lacks, one of the wrong size or type, and a float sample that is NaN or
// infinite.
void LoadFrameDump(const ExrFile& dump, const std::filesystem::path& file, const Scene& scene,
                   const FrameConfig& config, FramePass from, FramePass to, Frame& frame);

}  // namespace ssgi
