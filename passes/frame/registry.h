// The pass registry (docs/design.md §1, "Adding a pass" in §15): one declaration per pass of the frame,
// in pipeline order. Each declares its name, the effect it belongs to, the buffers it makes (with
// their size, their dump layers and how the frame frees them), the buffers made by earlier passes
// that it reads or writes, its `--stats` rows and the step that runs it. Everything else is derived
// from these declarations:
//   - the order in which RunFramePasses frees buffers (BufferLifetime::kUntilLastReader),
//   - the memory estimate (passes/frame/memory.h),
//   - the `--stats` rows (StageRows),
//   - the dump catalogue and the dump's writer and reader (passes/frame/dump.h),
//   - the names `ssgi passes --from / --to` take, and the CLI help that lists them.
// A buffer lives from the step of the pass that makes it to the step of its last reader, or to the
// frame's end when it is one of the frame's outputs. Freeing early, some buffers are written into
// the storage of an earlier one instead of their own (`storageOf`): the storage then lives until
// the last reader of what it holds.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ssgi {

struct Frame;
struct FrameStats;
struct FrameStep;
class DumpSink;
class DumpSource;

// The frame's passes in pipeline order, as `ssgi passes --from / --to` and the dump's layers name
// them (FramePassName). The order of the dump catalogue, the stats rows and pass ranges.
enum class FramePass {
  kGBuffer,
  kShadowMap,  // the shadow map and the blocker search: G-buffer word 3
  kShadowFilter,
  kDirectLight,
  kSkyLight,
  kBounce,
  kHiZ,
  kColorPyramid,
  kSsrTrace,
  kSsrCone,
  kComposite,
  kMlaa,  // the morphological anti-aliasing's edges and coverage (--aa mlaa)
  kAntialias,
  kTonemap,
};

// Which decision of the frame plan a pass or buffer belongs to (passes/frame/plan.h).
enum class FrameEffect {
  kAlways,
  kShadows,      // the first shadow-casting light's shadow map, blocker search and filter
  kReflections,  // screen-space reflections: Hi-Z, colour pyramid, trace, cone trace
  kSky,          // the environment's light: the sky light
  kBounce,       // the diffuse bounce and its ambient occlusion
  kIndirect,     // any light beyond the direct light (reflections, sky or bounce): the composite
  kAntialias,    // the anti-aliasing of the final image
};

// Every buffer of a frame, by what it holds.
enum class FrameBuffer {
  kGBufferWords,  // words 0-2
  kShadowTerm,    // word 3
  kVisibility,    // the G-buffer raster's depth keys and triangle indices
  kShadowMap,
  kShadowVisibility,  // the filtered visibility of the shadowed light
  kDirect,
  kSkyVolume,   // the world-space sky visibility, kept while the scene's geometry is the same
  kSkyDiffuse,  // the sky's diffuse light and its visibility
  kLit,         // direct + the sky's diffuse light
  kBounceHalf,  // the bounce's half-resolution steps: its inputs, the march, the filter's two passes
  kBounce,      // the bounce's light and its ambient visibility, at full resolution
  kHiZ,
  kColorPyramid,
  kSsrTrace,   // the trace's hits, confidence and steps
  kReflected,  // the cone-traced radiance
  kIndirect,
  kResult,
  kEdgeCoverage,  // the G-buffer's edge coverage words, for the edge anti-aliasing
  kMlaa,          // the morphological anti-aliasing's luma, edges, blend weights and coverage words
  kAntialiased,   // the anti-aliased final image
  kDisplay,
};

// Where a dump layer lives in the file.
enum class DumpPart {
  kImage,          // part "frame", the image's size
  kShadowMap,      // part "shadowmap", the shadow map's resolution squared
  kHiZLevels,      // parts "hiz.L", one per level, PyramidLevelSizes of the image
  kPyramidLevels,  // parts "pyramid.L", likewise
  kSkyVolume,      // part "skyvolume": the sky visibility volume's coefficients as rows
  kBounceHalf,     // part "bounce.half": the bounce's half resolution, (W + 1) / 2 x (H + 1) / 2
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

// What a frame's buffers are sized by.
struct FrameShape {
  size_t width = 0, height = 0;
  size_t triangles = 0;  // submitted to the rasterizer
  size_t shadowMapResolution = 0;
  size_t vertices = 0;             // the mesh's
  size_t skyVolumeBytes = 0;       // the sky visibility volume of the scene (SkyVisibilityBytes)
  size_t skyVolumeBuildBytes = 0;  // what making it holds besides the volume
  bool edgeCoverage = false;       // the G-buffer pass writes its edge coverage (--aa edge)
  bool mlaa = false;               // the morphological anti-aliasing runs (--aa mlaa)
  bool interreflection = false;    // the sky light makes the interreflection volume (SkyMakesInterreflection)
  // The frame frees buffers after their last reader and hands storage on (kUntilLastReader).
  bool handOver = false;
};

struct BufferDeclaration {
  FrameBuffer id;
  std::string_view name;  // as the memory estimate lists it
  // Kept to the frame's end in every lifetime: what callers read after the frame (the G-buffer
  // words, the final image and the display image).
  bool frameOutput = false;
  // Freeing early, the buffer is written into this buffer's storage, and `bytes` counts only what
  // it needs beyond that storage.
  std::optional<FrameBuffer> storageOf = {};
  size_t (*bytes)(const FrameShape&) = nullptr;
  std::vector<DumpLayer> layers = {};
  // The bytes the frame's copy holds now (0 when freed): what the lifetime test weighs against
  // `bytes`.
  size_t (*heldBytes)(const Frame&) = nullptr;
  void (*release)(Frame&) = nullptr;
  // Appends the layers the frame holds (none when the buffer is absent or freed).
  void (*dump)(const Frame&, DumpSink&) = nullptr;
  // Fills the buffer from a dump, for `ssgi passes` (DumpSource checks each layer).
  void (*load)(const DumpSource&, Frame&) = nullptr;
  // Loaded from a dump when the dump has it even if no pass that runs reads it, so that the dump
  // `ssgi passes` writes carries it on.
  bool carriedThrough = false;
  // Read by the frame plan: loaded from a dump whenever its pass does not run.
  bool readByPlan = false;
  // Where its effect does not belong to the frame, what its readers read instead.
  std::optional<FrameBuffer> absentAs = {};
};

// One stage of FrameStats as a row of a table (`--stats`, the sweep's CSV columns): its wall time
// and what it processed.
struct StageStats {
  std::string name;
  double ms = 0.0;
  double items = 0.0;    // what it processed, in itemUnit
  std::string itemUnit;  // "triangles", "pixels", "texels", "rays"
};

// One row of `--stats`: its name and how it reads the frame's stats (nullopt: the stage did not run).
struct StageRowDeclaration {
  std::string_view name;
  std::optional<StageStats> (*row)(const FrameStats&) = nullptr;
};

struct PassDeclaration {
  FramePass pass;
  std::string_view name;     // "gbuffer", "ssr_trace": `ssgi passes --from`, the dump's pass names
  std::string_view summary;  // one line for the CLI help
  FrameEffect effect = FrameEffect::kAlways;
  std::vector<BufferDeclaration> makes = {};
  std::vector<FrameBuffer> reads = {};   // made by earlier passes
  std::vector<FrameBuffer> writes = {};  // made by earlier passes and written again
  // Per-pass working memory that is not a frame buffer (the rasterizers' set-up triangles).
  std::string_view scratchName = {};
  size_t (*scratchBytes)(const FrameShape&) = nullptr;
  std::vector<StageRowDeclaration> stats = {};
  // Runs the pass within the frame (when it is in the run's range) and hands buffers on around it.
  // Called at the pass's step for every frame its effect belongs to.
  void (*step)(FrameStep&) = nullptr;
};

// Every pass, in pipeline order (FramePass order).
const std::vector<PassDeclaration>& FramePasses();
const PassDeclaration& FramePassDeclaration(FramePass pass);
// Every buffer, with the pass that makes it.
struct MadeBuffer {
  const BufferDeclaration* buffer;
  const PassDeclaration* maker;
};
const std::vector<MadeBuffer>& FrameBuffers();
const MadeBuffer& FrameBufferDeclaration(FrameBuffer buffer);

// The order in which the frame runs its passes: pipeline order, except that the colour pyramid is
// made after the trace, when the Hi-Z is no longer needed and the trace's hits say which texels the
// cone trace reads (docs/pipeline.md §Frame plan). Neither reads the other's output, so the bytes
// are those of pipeline order.
const std::vector<FramePass>& FrameSteps();
// The position of the pass in FrameSteps().
size_t StepOf(FramePass pass);

// The step after which the frame no longer needs the buffer, freeing early (kUntilLastReader):
// its last reader's, or that of what is written into its storage; nullopt for the frame's outputs.
std::optional<size_t> LastStepOf(FrameBuffer buffer);

}  // namespace ssgi
