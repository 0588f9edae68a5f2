// Screen-space soft shadows from the G-buffer's shadow term (docs/design.md §5, §9; docs/pipeline.md
// §Shadow filter (SSABSS)). Blurs the hard-shadow mask of word 3 with a kernel whose size is the
// PCSS penumbra width (Fernando 2005, "Percentage-Closer Soft Shadows", eq. 1) of the word's average
// blocker distance, projected to pixels at the receiver's view depth:
//  - kSspcss: screen-aligned square kernel (MohammadBagher et al. 2010, "Screen-Space
//    Percentage-Closer Soft Shadows"): its world-space penumbra changes with the viewpoint;
//  - kSsabss: anisotropic kernel (Zheng & Saito, "Screen Space Anisotropic Blurred Soft Shadows"):
//    an ellipse from the receiver's normal and view ray, minor axis along the projected normal
//    foreshortened by |n . v|, so the penumbra keeps its world-space width from any viewpoint.
// Both run as two 1-D passes with bilateral weights (tangent-plane distance, normal), so shadows do
// not bleed across depth or orientation edges, and blur only the 16x16 tiles that need it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/lighting.h"
#include "core/plane.h"

namespace ssgi {

enum class ShadowFilter { kHard, kSspcss, kSsabss };

inline constexpr int kShadowFilterTileSize = 16;  // pixels; the unit of blur-area control

struct ShadowFilterParams {
  ShadowFilter filter = ShadowFilter::kSsabss;
  int maxRadiusPixels = 24;  // >= 0; clamp of the kernel's half-width (major axis) in pixels
  // 0: one tap per pixel of the axis length along each 1-D pass (box with a fractional last tap);
  // > 0: this many equal-weight taps per side, spread over the axis length.
  int taps = 0;
};

struct ShadowFilterInputs {
  const GBuffer& gbuffer;        // reads words 1 (normal), 2 (view depth), 3 (hard flag + blocker distance)
  const ViewProjection& view;    // the perspective camera the G-buffer was rendered with
  const PreparedLight& light;    // in VIEW space (PrepareLights(scene, view.view)); the light word 3 describes
};

struct ShadowFilterOutputs {
  // Light visibility in [0, 1] (1 = lit), the G-buffer's size; background pixels 1. Allocated by the
  // pass when its size differs from the G-buffer's.
  Plane<float> visibility;
};

struct ShadowFilterStats {
  double ms = 0;
  size_t tiles = 0;         // 16x16 tiles of the image
  size_t tilesBlurred = 0;  // tiles that ran the blur (the rest copy the hard value)
  size_t pixels = 0;        // pixels with geometry in the blurred tiles
};

// `kernels` chooses the row kernels' definition: the Highway twins (what frames use) or the scalar
// definitions below; both give the same bits.
ShadowFilterStats RunShadowFilter(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                  ShadowFilterOutputs& out, KernelPath kernels = KernelPath::kSimd);

// RunShadowFilter with blur-area control off (every tile blurred): the reference the tile skipping
// must match bit for bit (tests/passes/shadow_filter_test.cpp).
ShadowFilterStats RunShadowFilterEveryTile(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                           ShadowFilterOutputs& out, KernelPath kernels = KernelPath::kSimd);

// The shadow filter's scalar kernels below are the definitions their SIMD twins
// (passes/shadow_filter_simd.cpp, ...RowSimd, same signatures) must equal bit for bit. Per-pixel
// data is a structure of arrays: the twins' lanes are pixels.

// The definition's constants (docs/pipeline.md §Shadow filter), shared with the twins.
// Bilateral acceptance of a tap: the tap's normal within about 37 degrees of the centre's, and the
// tap's point within 2 % of the centre's view depth of the centre's tangent plane. The plane
// distance, unlike a raw depth difference, does not reject taps on the centre's own surface seen at
// a grazing angle, where depth changes quickly from pixel to pixel.
inline constexpr float kShadowFilterMinNormalDot = 0.8f;
inline constexpr float kShadowFilterMaxPlaneDistance = 0.02f;
// A projected normal shorter than this faces the camera: the ellipse's axes are undefined, so the
// kernel falls back to a circle with a screen-x major axis (Zheng & Saito's known degenerate case).
inline constexpr float kShadowFilterMinProjectedNormal = 1e-4f;
// Metres; keeps the spot light's PCSS denominator (light-to-blocker distance) away from 0.
inline constexpr float kShadowFilterMinLightToBlocker = 1e-3f;
// Kernels shorter than this (pixels) leave the hard value (a pixel's own tap only).
inline constexpr float kShadowFilterMinBlurRadius = 0.5f;

// What the set-up of every row shares: the frame's constants.
struct ShadowFilterSetupContext {
  PreparedLight light;            // ShadowFilterInputs::light, in view space
  const float* rayX;              // per column x: ViewProjection::PixelRay(x + 0.5, .).direction.x
  const float* rayY;              // per row y: PixelRay(., y + 0.5).direction.y (the direction's z is -1)
  NormalEncoding normalEncoding;  // decodes word 1
  ShadowFilter filter;
  float maxRadius;                  // pixels, ShadowFilterParams::maxRadiusPixels
  float pixelsPerMetreAtUnitDepth;  // the image's height over the view's height at view depth 1
};

// `rays`: the image's (MakePixelRayTables of its width and height), made once per frame, which the
// context points at.
ShadowFilterSetupContext MakeShadowFilterSetupContext(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                                      const PixelRayTables& rays);

// What the blur-area control needs of a tile: its pixels' largest penumbra radius in pixels (the
// PCSS width projected at the pixel's depth, in [0, maxRadius]; background pixels count as
// kShadowFilterNoRadius), and how many of its pixels have geometry and how many of those are lit.
inline constexpr float kShadowFilterNoRadius = -1.0f;
struct ShadowFilterTileSummary {
  float maxRadius = kShadowFilterNoRadius;
  int32_t geometryPixels = 0;
  int32_t litPixels = 0;
};

// The hard values of pixels x .. x + count - 1 of row y (the word pointers address pixel x of
// G-buffer words 2 and 3) into hard[i] (0 shadowed, 1 lit; background 1), each pixel added to the
// summary of its tile, tiles[(x + i) / kShadowFilterTileSize].
void ShadowFilterPenumbraRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word2,
                                   const uint32_t* word3, int x, int y, int count, float* hard,
                                   ShadowFilterTileSummary* tiles);

// The set-up's per-pixel results, structures of arrays: element i of each array for pixel i of a
// run. What a tap needs of a pixel: the view-space position in metres (background (0, 0, 0);
// positionZ < 0 marks geometry), the unit view-space normal (background 0) and the hard value (0
// shadowed, 1 lit; background 1).
struct ShadowFilterTexels {
  float* positionX;
  float* positionY;
  float* positionZ;
  float* normalX;
  float* normalY;
  float* normalZ;
  float* hard;

  ShadowFilterTexels operator+(size_t offset) const {
    return {positionX + offset, positionY + offset, positionZ + offset, normalX + offset,
            normalY + offset,   normalZ + offset,   hard + offset};
  }
};

// The screen-space kernel of a pixel: half-lengths in pixels along the major axis, a unit screen
// direction (y down), and along the minor axis (-majorY, majorX). No kernel: major (1, 0), lengths 0.
struct ShadowFilterKernels {
  float* majorX;
  float* majorY;
  float* majorLength;
  float* minorLength;

  ShadowFilterKernels operator+(size_t offset) const {
    return {majorX + offset, majorY + offset, majorLength + offset, minorLength + offset};
  }
};

// Per-pixel set-up of pixels x .. x + count - 1 of row y: the word pointers address pixel x of
// G-buffer words 1 (normal), 2 (view depth) and 3 (shadow term); pixel x + i's texel and, unless
// `kernels` is null (pixels the passes only tap), its kernel (the PCSS penumbra width, SSABSS or
// SSPCSS shape; none for kHard) go to element i of the arrays.
void ShadowFilterSetupRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                                const uint32_t* word3, int x, int y, int count, const ShadowFilterTexels& texels,
                                const ShadowFilterKernels* kernels);

// What the 1-D passes read: the set-up of the tiles the driver set up, stored tile by tile, each
// tile's kShadowFilterTileSize^2 pixels row-major in one slot (Index). Kernels are stored for the
// first slots only: the tiles the passes blur. The texel arrays and the passes' `values` must be
// readable kShadowFilterTileSize floats before their first element and after their last: the
// twins load a run of a tile's row that may reach past it (and do not use what they read there).
struct ShadowFilterImage {
  ShadowFilterTexels texels;
  ShadowFilterKernels kernels;
  const int32_t* tileSlots;  // per tile (row-major tiles): its slot, or -1 where it was not set up
  int width, height;         // pixels
  int tilesX;                // tiles per row

  size_t Index(int x, int y) const {
    const int tile = y / kShadowFilterTileSize * tilesX + x / kShadowFilterTileSize;
    return size_t(tileSlots[tile]) * size_t(kShadowFilterTileSize * kShadowFilterTileSize) +
           size_t(y % kShadowFilterTileSize * kShadowFilterTileSize + x % kShadowFilterTileSize);
  }
};

// The two bilateral 1-D passes on pixels [xBegin, xEnd) of row y, `taps` as in ShadowFilterParams,
// each pixel with its own kernel; `values` is indexed as the image (ShadowFilterImage::Index), and
// out[i] is pixel xBegin + i. Pass 1 blurs the set-up's hard values along each pixel's major axis;
// pass 2 blurs pass 1's values along each pixel's minor axis. The run's kernels must be set up, and
// the texels of every pixel within floor(kernel length) + 1 pixels of it (the taps' reach).
void ShadowFilterMajorRowScalar(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                                int xEnd, float* out);
void ShadowFilterMinorRowScalar(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                                int xEnd, float* out);

// The Highway twins (passes/shadow_filter_simd.cpp), dispatched to the machine's best target.
void ShadowFilterPenumbraRowSimd(const ShadowFilterSetupContext& context, const uint32_t* word2, const uint32_t* word3,
                                 int x, int y, int count, float* hard, ShadowFilterTileSummary* tiles);
void ShadowFilterSetupRowSimd(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                              const uint32_t* word3, int x, int y, int count, const ShadowFilterTexels& texels,
                              const ShadowFilterKernels* kernels);
void ShadowFilterMajorRowSimd(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                              int xEnd, float* out);
void ShadowFilterMinorRowSimd(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                              int xEnd, float* out);

}  // namespace ssgi
