// SSR cone trace (docs/design.md §7; docs/pipeline.md §SSR: cone trace): turns each Hi-Z trace hit into
// reflected radiance by walking the circles inscribed in the roughness cone's screen-space triangle
// and reading the pre-blurred colour pyramid, after Uludag (GPU Pro 5, "Hi-Z Screen-Space
// Cone-Traced Reflections", cone tracing section).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/plane.h"
#include "core/tile_mask.h"
#include "passes/color_pyramid.h"
#include "passes/ssr_trace.h"

namespace ssgi {

// Below this screen distance (px) from origin to hit the cone has no direction to walk; the hit's
// own level-0 texel is the whole footprint anyway.
inline constexpr float kConeMinHeight = 0.5f;

// Phong exponent used for GGX alpha -> 0 (a mirror), where 2 / alpha^2 - 2 diverges.
inline constexpr double kConeMaxPhongExponent = 1e6;

// tan(theta) of the cone half-angle for each 8-bit perceptual roughness code r = code / 255:
// alpha = r^2 (GGX), Phong exponent n = min(2 / alpha^2 - 2, kConeMaxPhongExponent) (Walter et al.
// 2007's Beckmann/Phong equivalence, as Karis's "specular D" notes use it), theta =
// acos(0.244^(1 / (n + 1))) (Uludag: the lobe angle holding most of the Phong energy).
// Monotone non-decreasing in the code; tan(theta) in (0, 4.0] (code 255: n = 0, theta = 75.9 deg).
using ConeTanTable = std::array<float, 256>;
ConeTanTable BuildConeTanTable();
float ConeHalfAngleTan(uint8_t roughnessCode);  // looks up a table built once

struct SsrConeParams {
  // Pyramid fetches (circles) per pixel, >= 1; wider cones stop at the cap and are normalised over
  // the circles taken. 1 (the circle at the hit, as wide as the cone there) is the default because
  // it is the most accurate against the traced GGX bounce on both swept scenes (docs/user-guide.md "Accuracy and
  // time"): Uludag's inner circles, 7 of them in the paper, sample the screen between the reflector
  // and the hit, which the reflected lobe never sees.
  int maxSamples = 1;
};

struct SsrConeInputs {
  const GBuffer& gbuffer;          // word 1 (bits 24-31: perceptual roughness code)
  const ColorPyramid& pyramid;     // RunColorPyramid of the direct-light image, the G-buffer's size
  // RunSsrTrace's outputs for the same G-buffer. hitX and hitY may be the output's reflected.c[0] and
  // c[1] themselves (the frame's memory-saving mode): each pixel is read before it is written.
  const Plane<float>& hitX;
  const Plane<float>& hitY;
  const Plane<float>& confidence;
  // FramePlan::reflectionTiles, or null: its 32x32 tiles hold every pixel with confidence > 0 (the
  // trace was given the same mask), and the others get 0 stored without reading anything.
  const TileMask* tiles = nullptr;
  bool leaveSkippedTiles = false;  // as SsrTraceInputs::leaveSkippedTiles
};

struct SsrConeOutputs {
  // G-buffer size. Linear RGB radiance reflected toward the viewer before the specular weight,
  // finite, in [0, kMaxRadiance]; 0 where trace.confidence is 0 (no hit).
  Plane3<float> reflected;
};

struct SsrConeStats {
  double ms = 0;
  size_t samples = 0;  // circles sampled (each a trilinear pyramid fetch) over all pixels
  size_t pixels = 0;   // pixels with confidence > 0
};

// Reuses out's planes when their sizes already match, else allocates them. `kernels` chooses the row
// kernel; both give the same bytes.
SsrConeStats RunSsrCone(const SsrConeInputs& in, const SsrConeParams& params, SsrConeOutputs& out,
                        KernelPath kernels = KernelPath::kSimd);

// What the cone trace of every row shares: the frame's constants.
struct SsrConeContext {
  const ColorPyramid& pyramid;  // SsrConeInputs::pyramid
  const ConeTanTable& coneTan;  // BuildConeTanTable()
  int maxSamples;               // SsrConeParams::maxSamples
};

struct SsrConeCounts {
  size_t samples = 0;  // circles sampled
  size_t pixels = 0;   // pixels with confidence > 0
};

// The cone trace's scalar row kernel, the definition a SIMD twin (passes/ssr_cone_simd.cpp) must
// equal bit for bit: reflected radiance of the pixels [xBegin, xEnd) of row y, from G-buffer word 1
// and the trace's hitX, hitY and confidence (rows indexed by x), into red[x], green[x], blue[x].
SsrConeCounts SsrConeRowScalar(const SsrConeContext& context, const uint32_t* word1, const float* hitX,
                               const float* hitY, const float* confidence, size_t y, size_t xBegin, size_t xEnd,
                               float* red, float* green, float* blue);
// Its Highway twin, dispatched to the machine's best target: lanes are the row's pixels.
SsrConeCounts SsrConeRowSimd(const SsrConeContext& context, const uint32_t* word1, const float* hitX,
                             const float* hitY, const float* confidence, size_t y, size_t xBegin, size_t xEnd,
                             float* red, float* green, float* blue);
// The twin over rows [yBegin, yEnd) of the pass's inputs into out's planes (already of the
// G-buffer's size), reading the pyramid's layout once for all of them, skipping as in.tiles says;
// row y's counts into rowCounts[y].
void SsrConeRowsSimd(const SsrConeContext& context, const SsrConeInputs& in, size_t yBegin, size_t yEnd,
                     SsrConeOutputs& out, SsrConeCounts* rowCounts);

// The colour-pyramid texels of levels 1 and up that RunSsrCone reads for these hits (a superset):
// per pixel with confidence > 0 whose cone walks (roughness code above 0, a hit at least
// kConeMinHeight away), every level up to the one above its widest circle's, over the bilinear
// footprints of the segment from the pixel to its hit and a texel more on each side. `tiles` as
// SsrConeInputs::tiles. nullopt where listing them would cost more than `maxRowSpans` row spans:
// the whole pyramid is then as cheap.
std::optional<ColorPyramidNeeds> SsrConePyramidNeeds(const Plane<uint32_t>& word1, const Plane<float>& hitX,
                                                    const Plane<float>& hitY, const Plane<float>& confidence,
                                                    const TileMask* tiles, size_t maxRowSpans);

// Row y in runs of in.tiles' tiles: run(xBegin, xEnd) where a row kernel must run, and 0 (what it
// stores where the confidence is 0) stored into out's planes elsewhere.
template <class Run>
void ForEachConeRun(const SsrConeInputs& in, size_t y, SsrConeOutputs& out, const Run& run) {
  ForEachTileRun(
      in.tiles, int(y), int(in.confidence.xsize()), [&](int xBegin, int xEnd) { run(size_t(xBegin), size_t(xEnd)); },
      [&](int xBegin, int xEnd) {
        if (in.leaveSkippedTiles) return;
        for (Plane<float>& plane : out.reflected.c)
          std::fill(plane.MutableRow(y) + xBegin, plane.MutableRow(y) + xEnd, 0.0f);
      });
}

}  // namespace ssgi
