// Diffuse bounce and ambient occlusion by the visibility bitmask (docs/pipeline.md §Diffuse bounce and
// ambient occlusion (visibility bitmask)): Therrien, Levesque and Gilet, "Screen Space Indirect
// Lighting with Visibility Bitmask" (2023, arXiv 2301.11376), on the slice march of GTAO (Jimenez et
// al. 2016, "Practical Real-Time Strategies for Accurate Indirect Occlusion") as Intel's XeGTAO lays
// it out (slices, steps, the spatial denoiser).
//
// Per pixel of a half-resolution image, a few screen-space slice directions are marched both ways
// from the pixel. Each slice keeps a 32-bit mask of sectors of its half-circle of directions around
// the normal; every depth sample is taken as a slab of constant thickness behind it, and sets the
// sectors between the directions of its front and its back. The sectors split the slice's
// cosine-weighted solid angle into equal parts, so the share of unoccluded sectors is the ambient
// visibility, and each sample's newly covered sectors carry its lit radiance into the bounce. A
// depth- and normal-aware separable 7x7 filter removes the per-pixel rotation pattern, and a depth- and
// normal-aware upsample takes both to full resolution.
//
// Four steps, each a row kernel with a scalar definition (bounce.cpp) and a Highway twin
// (bounce_simd.cpp) that gives the same bytes on every SIMD target: prepare (the half-resolution
// inputs), march, filter, upsample.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

inline constexpr int kBounceMaxSlices = 16;
inline constexpr int kBounceMaxSteps = 32;
inline constexpr int kBounceMaxSectors = 32;  // one uint32 per slice

struct BounceParams {
  // Slice directions per pixel, each marched both ways (1 .. kBounceMaxSlices). Two, at per-pixel
  // rotations the filter averages over 4x4 pixels, sample 32 directions per neighbourhood.
  int slices = 2;
  // Samples per slice direction, i.e. per side (1 .. kBounceMaxSteps), spread as the square of
  // their rank (denser near the pixel, where occluders subtend the largest angles).
  int steps = 4;
  // Search radius in metres in view space, projected at the pixel's depth and capped at
  // maxRadiusPixels (full-resolution pixels), which bounds the cost and the cache footprint of
  // near pixels. >= 0.
  float radius = 1.0f;
  float maxRadiusPixels = 128.0f;
  // Every depth sample is a slab this thick (metres) behind what the camera sees: it occludes the
  // directions between its front and its back, and light passes behind it. >= 0.
  float thickness = 0.25f;
  // Sectors per slice (1 .. kBounceMaxSectors): the angular resolution of the visibility.
  int sectors = 32;
  // The filter and the upsample weigh a neighbour down linearly with its distance from the pixel's
  // tangent plane, to 0 at this fraction of the pixel's view depth. > 0.
  float depthTolerance = 0.01f;
};

struct BounceInputs {
  const GBuffer& gbuffer;      // words 1 (normal) and 2 (view depth)
  const ViewProjection& view;  // the perspective camera of the G-buffer's size
  // Radiance leaving each pixel toward the camera (the frame's Lit(): direct light plus the sky's
  // diffuse light), the G-buffer's size; sanitised as it is read (NaN and negatives 0, above 65504
  // 65504).
  const Plane3<float>& lit;
};

// The half-resolution buffers, (W + 1) / 2 x (H + 1) / 2: pixel (i, j) stands for full-resolution
// pixel (2i, 2j). Kept in the outputs so that a frame reuses them and a port can compare each step.
struct BounceHalfRes {
  Plane<float> depth;                 // view depth in metres; +inf where there is no geometry
  Plane3<float> normal;               // decoded unit view-space normal; 0 where there is no geometry
  Plane<uint32_t> normalCode;         // G-buffer word 1's normal code (bits 0-23); 0 where there is no geometry
  Plane3<float> lit;                  // sanitised lit radiance
  Plane<float> visibility;            // the march: ambient visibility in [0, 1]; 1 without geometry
  Plane3<float> bounce;               // the march: bounce (as BounceOutputs::bounce); 0 without geometry
  Plane<float> horizontalVisibility;  // the filter's horizontal pass over the march's
  Plane3<float> horizontalBounce;
  Plane<float> filteredVisibility;  // the filter's vertical pass over the horizontal one's
  Plane3<float> filteredBounce;
};

struct BounceOutputs {
  // Full resolution. Ambient visibility in [0, 1]: the cosine-weighted share of the hemisphere
  // around the normal that no on-screen surface (within the radius) covers; 1 = open, and 1 where
  // there is no geometry. For the frame to darken its sky light's diffuse term with (that term's
  // own visibility volume is coarse: it misses contact detail).
  Plane<float> visibility;
  // Full resolution, linear RGB in [0, 65504]: the irradiance from on-screen surfaces divided by pi,
  // E / pi, the cosine-weighted mean over the hemisphere of the radiance arriving from the lit image
  // (0 from open sectors). A Lambertian surface reflects albedo * (1 - metallic) * bounce; 0 where
  // there is no geometry.
  Plane3<float> bounce;
  BounceHalfRes half;
};

struct BounceStats {
  double ms = 0.0;
  double prepareMs = 0.0, marchMs = 0.0, filterMs = 0.0, upsampleMs = 0.0;
  size_t pixels = 0;  // full-resolution pixels written
  uint64_t taps = 0;  // depth samples the march read (inside the half-resolution image)
};

// Reuses out's planes when their sizes match, else allocates them; every output pixel is written.
// kernels: which definition of the row kernels runs (the same bytes either way).
BounceStats RunBounce(const BounceInputs& in, const BounceParams& params, BounceOutputs& out,
                      KernelPath kernels = KernelPath::kSimd);

// --- The definition's constants (docs/pipeline.md), shared by both kernel paths. ---

// A depth sample is geometry when its view depth lies in [kBounceMinDepth, kBounceMaxDepth] metres
// (G-buffer depths do; +inf is background): the bounds keep every square and reciprocal finite.
inline constexpr float kBounceMinDepth = 1e-6f;
inline constexpr float kBounceMaxDepth = 1e6f;
// The nearest sample lies this many half-resolution pixels out, as XeGTAO's
// pixelTooCloseThreshold: it rounds to a neighbour, never to the pixel itself.
inline constexpr float kBounceMinTapDistance = 1.3f;
// A sample whose point rises less than this sine of an angle above the pixel's tangent plane, 1 /
// sqrt(128) (5.07 degrees), covers no sector: tested as rise^2 * 128 <= |delta|^2 (no square root).
// Below it, an in-plane sample's interval would not reach the centre of the nearest sector (10 degrees
// and more up), so it would have set none; the test keeps the pixel's own surface out of reach of
// the rounding that snapping samples to pixels adds, and skips the march's work for it.
inline constexpr float kBounceMinRiseInverseSquare = 128.0f;
// A sample's normal serves the march only where its length does not matter (a plane's offset ratio,
// a sign), so it is the code's vector before the decode's normalisation, dequantised with one
// product: oct24 u = code * (2 / 4095) - 1 (likewise v), folded as the decode folds it; xyz8 each
// component code * (2 / 255) - 1.
inline constexpr float kBounceOct24Scale = 2.0f / 4095.0f;
inline constexpr float kBounceXyz8Scale = 2.0f / 255.0f;
// The filter's spatial weights per axis, offsets -3..3: a 4-wide box convolved with itself, so each
// of the 4x4 rotation pattern's 16 phases weighs the same (the pattern cancels where the weights are
// spatial only) and the kernel falls off smoothly (a plain 4-wide box leaves its steps).
inline constexpr int kBounceFilterRadius = 3;
inline constexpr float kBounceFilterSpatial[2 * kBounceFilterRadius + 1] = {1.0f, 2.0f, 3.0f, 4.0f, 3.0f, 2.0f, 1.0f};
// The upsample keeps this share of a candidate's bilinear weight however little it matches, so a
// pixel that matches none of its four takes their bilinear mean.
inline constexpr float kBounceUpsampleFloor = 1e-3f;

// --- Row kernels (the definitions and their twins), for the tests. ---

// The frame's constants every row kernel reads (MakeBounceSetup), plain values only.
struct BounceSetup {
  int width = 1, height = 1;          // full resolution
  int halfWidth = 1, halfHeight = 1;  // (width + 1) / 2, (height + 1) / 2
  // The view-space ray through the centre of full-resolution column X is (X + 0.5) rayScaleX +
  // rayOffsetX, of row Y (Y + 0.5) rayScaleY + rayOffsetY, z = -1.
  float rayScaleX = 0, rayOffsetX = 0, rayScaleY = 0, rayOffsetY = 0;
  float radiusPixelsAtUnitDepth = 0;  // radius * full-resolution pixels per metre at view depth 1
  float maxRadiusPixels = 0;
  float thickness = 0;
  int slices = 1, steps = 1, sectors = 32;
  float depthTolerance = 0;
  NormalEncoding encoding = NormalEncoding::kOct24;
  // Screen direction (x right, y down) of slice k at rotation phase r (0..15): entry 16 k + r.
  float directionX[16 * kBounceMaxSlices] = {};
  float directionY[16 * kBounceMaxSlices] = {};
  // The square of step j's rank at jitter phase q (0..15): entry 16 j + q.
  float stepSpread[16 * kBounceMaxSteps] = {};
};
BounceSetup MakeBounceSetup(const ViewProjection& view, const BounceParams& params, NormalEncoding encoding);

// The rotation phase of half-resolution pixel (i, j): the 4x4 Bayer matrix; the jitter phase is
// 5 r mod 16 (a rank-1 lattice: the 16 pairs of a 4x4 block spread over the unit square).
inline int BounceRotationPhase(int i, int j) {
  static constexpr int kBayer[4][4] = {{0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};
  return kBayer[j & 3][i & 3];
}
inline int BounceJitterPhase(int rotation) { return (5 * rotation) & 15; }

// The half-resolution planes as the kernels address them: each plane's pixel (0, 0) and the common
// row stride in elements.
struct BounceHalfView {
  const float* depth;
  const float* normal[3];
  const uint32_t* normalCode;
  const float* lit[3];
  const float* filteredVisibility;  // the filter's, read by the upsample
  const float* filteredBounce[3];
  size_t stride;
};

// Prepare, half-resolution row j: depth, normal, normal code and lit of full-resolution pixel (2i, 2j)
// for i in [0, halfWidth). word1Row, word2Row: G-buffer row 2j; litRow: the lit image's row 2j.
void BouncePrepareRowScalar(const BounceSetup& setup, const uint32_t* word1Row, const uint32_t* word2Row,
                            const float* const litRow[3], float* depth, float* const normal[3], uint32_t* normalCode,
                            float* const lit[3]);
void BouncePrepareRowSimd(const BounceSetup& setup, const uint32_t* word1Row, const uint32_t* word2Row,
                          const float* const litRow[3], float* depth, float* const normal[3], uint32_t* normalCode,
                          float* const lit[3]);

// March, half-resolution row j, pixels [0, halfWidth): visibility and bounce; returns the taps.
uint64_t BounceMarchRowScalar(const BounceSetup& setup, const BounceHalfView& half, int j, float* visibility,
                              float* const bounce[3]);
uint64_t BounceMarchRowSimd(const BounceSetup& setup, const BounceHalfView& half, int j, float* visibility,
                            float* const bounce[3]);

// One pass of the filter, half-resolution row j: the depth- and normal-aware mean of the 7 source
// values along the row (vertical false) or the column (vertical true) through each pixel. The
// sources are planes of the half-resolution size, at pixel (0, 0), rows half.stride apart.
void BounceFilterRowScalar(const BounceSetup& setup, const BounceHalfView& half, int j, bool vertical,
                           const float* sourceVisibility, const float* const sourceBounce[3], float* visibility,
                           float* const bounce[3]);
void BounceFilterRowSimd(const BounceSetup& setup, const BounceHalfView& half, int j, bool vertical,
                         const float* sourceVisibility, const float* const sourceBounce[3], float* visibility,
                         float* const bounce[3]);

// Upsample, full-resolution row y: the filtered half-resolution values at the pixel. word1Row,
// word2Row: G-buffer row y.
void BounceUpsampleRowScalar(const BounceSetup& setup, const BounceHalfView& half, int y, const uint32_t* word1Row,
                             const uint32_t* word2Row, float* visibility, float* const bounce[3]);
void BounceUpsampleRowSimd(const BounceSetup& setup, const BounceHalfView& half, int y, const uint32_t* word1Row,
                           const uint32_t* word2Row, float* visibility, float* const bounce[3]);

}  // namespace ssgi
