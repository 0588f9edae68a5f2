// SSR Hi-Z trace (docs/design.md §7; docs/pipeline.md §SSR: Hi-Z trace): per pixel, reflect the view ray
// about the G-buffer normal and march the reflected ray in screen space through the Hi-Z pyramid,
// after Uludag (GPU Pro 5, "Hi-Z Screen-Space Cone-Traced Reflections"), with the fixes of the
// Bitsquid/Stingray notes and AMD FidelityFX SSSR (origin snapped into its cell, un-offset cell planes
// with a nudge along the winning axis only, safe reciprocals, a fixed iteration cap). The cone trace
// that turns a hit into radiance is a separate pass.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/plane.h"
#include "core/tile_mask.h"
#include "passes/hiz.h"

namespace ssgi {

struct SsrTraceParams {
  int maxIterations = 64;         // Hi-Z steps per ray (>= 1); a ray still marching then is a miss
  // Pyramid level the march continues at once the ray has left its origin's level-0 cell (>= 0,
  // clamped to the top level). Higher starts stride faster through open space but must descend
  // again past the reflector's own neighbourhood; see docs/pipeline.md.
  int startLevel = 1;
  float roughnessCutoff = 0.7f;   // perceptual roughness; pixels with roughness >= cutoff are not traced
  // Relative thickness assumed behind every depth sample: a hit where the ray's view depth exceeds
  // the surface's by up to thickness * d has full confidence, fading linearly to 0 at 2 * thickness * d
  // (the ray then passed behind the surface rather than hitting it). > 0.
  float thickness = 0.05f;
  // Screen-edge fade width, as a fraction of the image width (x) and height (y): confidence falls
  // linearly to 0 as the hit approaches an image border. 0 disables the fade.
  float edgeFade = 0.05f;
  // Rays toward the camera (view-space r.z > 0) are traced with the max pyramid, which cannot tell
  // whether the ray passes in front of or behind a surface; their confidence fades linearly from 1
  // at r.z = 0 to 0 at r.z = towardCameraFade (continuous at r.z = 0: no seam). Rays with r.z >=
  // towardCameraFade are not traced. > 0.
  float towardCameraFade = 0.3f;
  // Shared rays: a pixel at least this rough takes the ray of its 2x2 quad's top-left pixel, when
  // that pixel is as rough and lies on the same surface (SsrRaySource); the cone trace then widens
  // the shared hit by each pixel's own roughness. At or above roughnessCutoff: every pixel traces.
  float quadRoughness = 0.1f;
  // The same over the 4x4 block's top-left pixel, for rougher pixels still.
  float blockRoughness = 0.3f;
};

struct SsrTraceInputs {
  const GBuffer& gbuffer;        // words 1 (normal, roughness) and 2 (view depth)
  const ViewProjection& view;    // the perspective camera of the G-buffer's size
  const HiZ& hiz;                // RunHiZ of gbuffer.word[GBufferWord::kDepth]
  // FramePlan::reflectionTiles of this G-buffer, or null: its 32x32 tiles hold every pixel that can
  // trace, and the others get "no hit" stored without reading anything (the same bytes).
  const TileMask* tiles = nullptr;
  // With tiles: the other tiles' outputs are left as they are, for readers that skip them too (a
  // frame that no dump reads: BufferLifetime::kUntilLastReader and kKeepForReuse).
  bool leaveSkippedTiles = false;
};

struct SsrTraceOutputs {
  // G-buffer size. Hit position in level-0 pixel coordinates (origin top-left, pixel centres at
  // +0.5), inside [0, width) x [0, height); -1 in both where there is no hit (untraced pixel, miss,
  // or rejected hit). Never NaN.
  Plane<float> hitX;
  Plane<float> hitY;
  // In [0, 1]: thickness x screen-edge x toward-camera fades; 0 exactly where hitX is -1.
  Plane<float> confidence;
  // The Hi-Z steps the pixel's ray took (a whole number in [0, maxIterations]; 0 where no ray was
  // traced): where a port's march and the oracle's part ways, and what the trace costs where.
  Plane<float> iterations;
};

// Row y of out.iterations, or nullptr where it is not recorded (empty).
inline float* IterationsRow(SsrTraceOutputs& out, int y) {
  return out.iterations.ysize() > 0 ? out.iterations.MutableRow(size_t(y)) : nullptr;
}

struct SsrTraceStats {
  double ms = 0;
  size_t rays = 0;             // pixels traced
  double meanIterations = 0;   // Hi-Z steps per traced ray
  size_t tiles = 0;            // 32 x 32 tiles in the image
  size_t tilesTraced = 0;      // tiles with at least one traced ray
};

// One screen-space ray march through the Hi-Z. Positions are (x, y, 1/d): level-0 pixel coordinates
// and inverse view depth in 1/metres, in which a perspective ray is linear.
struct HiZRay {
  glm::vec3 origin;  // inside the image; its own cell is skipped (the reflecting surface itself)
  glm::vec3 end;     // anywhere; the march stops at the segment's end or the image border
};

struct HiZMarch {
  bool hit = false;     // the ray reached the depth of a level-0 texel inside that texel
  glm::vec3 position{}; // (x, y, 1/d) of the hit; the last position reached on a miss
  int iterations = 0;   // <= maxIterations
};

// MarchHiZ's constants, shared with the SIMD twin of the trace (passes/ssr_trace_simd.cpp).
// Stands in for 1/0 and "never": finite, so products with it stay finite and comparable (the
// largest step distance, 16384 pixels, times it is still far below FLT_MAX).
inline constexpr float kHiZNever = 1e30f;
// Direction components below this are treated as 0 (their reciprocal would overflow to inf).
inline constexpr float kHiZTinyComponent = 1e-20f;
// How far past a crossed cell boundary the ray is put, in level-0 pixels, along the winning axis
// only: several ulps at the largest image coordinate (16384, ulp 1/512), a negligible offset.
inline constexpr float kHiZBoundaryNudge = 1.0f / 64.0f;
// Level-0 coordinates are clamped to [0, this] before they become cell indices, so a stray
// coordinate can never overflow the int.
inline constexpr float kHiZMaxCoordinate = 16384.0f * 2.0f;
// Reflected segments are cut at this many view depths of their origin: farther hits are sub-pixel
// next to the vanishing point, and the bound keeps the projected end finite for rays parallel to
// the image plane.
inline constexpr float kSsrMaxRayLengthInDepths = 1000.0f;

// Uludag's march: at level k the ray steps to the nearer of the current cell's boundary (then
// k + 1) and the cell's closest-depth plane 1/d = max (then k - 1, a hit below level 0). The first
// step leaves the origin's level-0 cell; the march goes on at startLevel.
HiZMarch MarchHiZ(const HiZ& hiz, const HiZRay& ray, int maxIterations, int startLevel);

// Whether RunSsrTrace writes SsrTraceOutputs::iterations (dumps and tests read it; a frame that
// frees buffers early has no reader for it and saves its memory).
enum class SsrTraceSteps { kRecord, kSkip };

// Reuses out's planes when their sizes already match, else allocates them; with SsrTraceSteps::kSkip
// out.iterations is left empty. `kernels` chooses the row kernel; both give the same bytes.
SsrTraceStats RunSsrTrace(const SsrTraceInputs& in, const SsrTraceParams& params, SsrTraceOutputs& out,
                          KernelPath kernels = KernelPath::kSimd, SsrTraceSteps steps = SsrTraceSteps::kRecord);

struct SsrTraceCounts {
  size_t rays = 0;          // pixels traced
  uint64_t iterations = 0;  // Hi-Z steps over those rays
};

// Whose ray a pixel takes: its own (also every pixel that traces none), its 2x2 quad's top-left
// pixel's or its 4x4 block's top-left pixel's.
enum class SsrRaySource : uint8_t { kOwn, kQuad, kBlock };

// A shared ray goes only between pixels on one surface: view depths within this fraction of the
// source pixel's, ...
inline constexpr float kSharedRayDepthTolerance = 1.0f / 16.0f;
// ... and packed normal codes within these steps on each axis (about 3 degrees either way).
inline constexpr int32_t kSharedRayOctStepsOct24 = 96;
inline constexpr int32_t kSharedRayOctStepsXyz8 = 6;

// Pixel (x, y)'s source (docs/pipeline.md §SSR: Hi-Z trace, "Shared rays"): kBlock when the pixel
// and its block's top-left pixel both trace (geometry, roughness below the cut-off), are both at
// least blockRoughness rough and lie on one surface; else kQuad by the same test with the quad's
// top-left pixel and quadRoughness; else kOwn. A top-left pixel is its own source.
SsrRaySource SsrRaySourceOf(const SsrTraceInputs& in, const SsrTraceParams& params, int x, int y);

// The trace works in the frame plan's tiles of this many pixels a side.
inline constexpr int kSsrTraceTileSize = TileMask::kTileSize;

// A rectangle of pixels [x0, x1) x [y0, y1) whose corner (x0, y0) lies on the 4x4 block grid, so
// that every pixel's quad and block sources are inside it (the SIMD kernel takes at most a tile).
struct SsrTraceTile {
  int x0, y0, x1, y1;
};

// The trace's scalar tile kernel, the definition a SIMD twin (passes/ssr_trace_simd.cpp) must equal
// bit for bit: traces the tile's pixels whose source is their own, then gives each other pixel its
// source's hit and confidence (and 0 steps) in out's planes (of the G-buffer's size, iterations
// skipped when empty), and adds the rays and steps to `counts`.
void SsrTraceTileScalar(const SsrTraceInputs& in, const SsrTraceParams& params, const SsrTraceTile& tile,
                        SsrTraceOutputs& out, SsrTraceCounts& counts);
// Its Highway twin, dispatched to the machine's best target: lanes are the tile's rays.
void SsrTraceTileSimd(const SsrTraceInputs& in, const SsrTraceParams& params, const SsrTraceTile& tile,
                      SsrTraceOutputs& out, SsrTraceCounts& counts);

}  // namespace ssgi
