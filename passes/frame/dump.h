// The frame's buffers as named EXR layers (docs/pipeline.md §Dumps): what `ssgi render --dump`
// writes, what `ssgi passes` reads a port's buffers from and what `ssgi diff` compares, pass by pass.
// One catalogue, DumpLayers(), names every layer, its pass, type and meaning; the file holds a part
// "frame" of the image's size, a part "shadowmap" of the shadow map's, and a part per Hi-Z level
// ("hiz.0", "hiz.1", ...) and colour-pyramid level ("pyramid.0", ...).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/image_io.h"
#include "core/scene.h"
#include "passes/frame/frame.h"
#include "passes/frame/config.h"

namespace ssgi {

// Where a layer lives in the file.
enum class DumpPart {
  kImage,          // part "frame", the image's size
  kShadowMap,      // part "shadowmap", the shadow map's resolution squared
  kHiZLevels,      // parts "hiz.L", one per level, PyramidLevelSizes of the image
  kPyramidLevels,  // parts "pyramid.L", likewise
};

struct DumpLayer {
  std::string_view name;  // the channel's name in its part(s)
  FramePass pass;         // the pass that writes it
  bool isUint = false;    // uint32 samples (exact words, ids, codes); else float32
  DumpPart part = DumpPart::kImage;
  // Decoded from another layer for reading convenience (the G-buffer words' fields): no pass reads
  // it, so `ssgi passes` never takes it as an input.
  bool decoded = false;
  std::string_view meaning;  // units, space and range, as docs/pipeline.md §Dumps gives them
};

// Every layer a frame can have, in pipeline order.
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
