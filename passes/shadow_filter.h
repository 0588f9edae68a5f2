// Screen-space soft shadows from the G-buffer's shadow term (DESIGN.md §5, §9; docs/pipeline.md
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

#include "core/camera.h"
#include "core/gbuffer.h"
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

ShadowFilterStats RunShadowFilter(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                  ShadowFilterOutputs& out);

// RunShadowFilter with blur-area control off (every tile blurred): the reference the tile skipping
// must match bit for bit (tests/passes/shadow_filter_test.cpp).
ShadowFilterStats RunShadowFilterEveryTile(const ShadowFilterInputs& in, const ShadowFilterParams& params,
                                           ShadowFilterOutputs& out);

// The shadow filter's scalar kernels below are the definitions SIMD twins
// (passes/shadow_filter_simd.cpp) must equal bit for bit.

// What the taps need of one pixel, decoded once.
struct ShadowFilterTexel {
  glm::vec3 position{0.0f};  // view space, metres
  glm::vec3 normal{0.0f};    // view space, unit
  bool geometry = false;     // false: background, never a tap
};

// The screen-space kernel of one pixel: half-lengths in pixels along the major axis (unit screen
// direction, y down) and the minor axis (the major rotated by 90 degrees).
struct ShadowFilterKernel {
  glm::vec2 major{1.0f, 0.0f};
  float majorLength = 0.0f;
  float minorLength = 0.0f;

  glm::vec2 Minor() const { return {-major.y, major.x}; }
};

// What the set-up of every row shares: the frame's constants.
struct ShadowFilterSetupContext {
  const ViewProjection& view;     // ShadowFilterInputs::view
  const PreparedLight& light;     // ShadowFilterInputs::light, in view space
  NormalEncoding normalEncoding;  // decodes word 1
  ShadowFilter filter;
  float maxRadius;                  // pixels, ShadowFilterParams::maxRadiusPixels
  float pixelsPerMetreAtUnitDepth;  // the image's height over the view's height at view depth 1
};

// Per-pixel set-up of row y, `width` pixels of G-buffer words 1 (normal), 2 (view depth) and
// 3 (shadow term): each pixel's texel, its kernel (PCSS penumbra width, SSABSS or SSPCSS shape;
// zero lengths for kHard) and its hard value (0 shadowed, 1 lit; background 1, texel and kernel
// defaults) into texels[x], kernels[x], hard[x].
void ShadowFilterSetupRowScalar(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                                const uint32_t* word3, int y, int width, ShadowFilterTexel* texels,
                                ShadowFilterKernel* kernels, float* hard);

// What the 1-D passes read of the whole image: the set-up's texels and kernels, row-major, width *
// height each.
struct ShadowFilterImage {
  const ShadowFilterTexel* texels;
  const ShadowFilterKernel* kernels;
  int width, height;
};

// The two bilateral 1-D passes on pixels [xBegin, xEnd) of row y, `taps` as in ShadowFilterParams.
// Pass 1 blurs `hard` (the set-up's, width * height) along each pixel's major axis into
// majorPass[x]; pass 2 blurs majorPass (width * height) along each pixel's minor axis into
// visibility[x]. The output pointers address the row's pixel 0.
void ShadowFilterMajorRowScalar(const ShadowFilterImage& image, const float* hard, int taps, int y, int xBegin,
                                int xEnd, float* majorPass);
void ShadowFilterMinorRowScalar(const ShadowFilterImage& image, const float* majorPass, int taps, int y, int xBegin,
                                int xEnd, float* visibility);

}  // namespace ssgi
