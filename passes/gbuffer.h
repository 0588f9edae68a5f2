// G-buffer pass (docs/design.md §3-4, docs/pipeline.md §G-buffer): rasterizes the scene's triangles into a
// visibility buffer (core/raster/raster.h, core/raster/scene_raster_input.h), then resolves each visible pixel
// once: barycentrics from the view ray through the pixel centre and the original (unclipped)
// triangle, interpolated normal and UV, mip-mapped texture lookups with the UV footprint of the
// neighbouring pixels' rays (core/surface.h), and packs the 128-bit G-buffer. Alpha cut-out (map_d)
// is tested during rasterization.
#pragma once

#include <cstddef>

#include "core/camera.h"
#include "core/edge_coverage.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "core/surface.h"

namespace ssgi {

// Specular anti-aliasing (docs/pipeline.md §G-buffer "Specular anti-aliasing"): the roughness is
// widened by the shading normal's variance over the pixel, GGX alpha^2 += min(variance, kappa)
// (Kaplanyan, Hill, Patney & Lefohn 2016, in the isotropic form of Tokuyoshi & Kaplanyan 2019):
// variance from the interpolated vertex normal's change to the next pixel right and down, plus
// Toksvig's from a normal map's filtered texel. Off by default: against the supersampled truth the
// wider lobes' GGX tails spread a sun's highlight over the pixels around it, and the display error
// grows (README "Anti-aliasing"). kSpecularAaKappa is Tokuyoshi & Kaplanyan's bound, to turn it on with.
inline constexpr float kSpecularAaKappa = 0.18f;
// Tokuyoshi & Kaplanyan's 2 sigma^2 of the pixel's filter kernel, sigma^2 = 1 / (2 pi).
inline constexpr float kSpecularAaKernelVariance = 0.31830988f;
// How far from unit length a unit normal stored as three 8-bit codes may decode (each component
// within 1/255): a filtered texel no shorter than 1 minus this has no variance Toksvig could tell.
inline constexpr float kNormalTexelLengthTolerance = 0.0067923561f;  // sqrt(3) / 255

// The GGX alpha^2 variance of the unit shading normal over a pixel, from the interpolated vertex
// normal `m` (not normalised) and its steps to the next pixel right and down: the steps' parts
// across m, divided by |m| (the derivative of m / |m|), as squared lengths times
// kSpecularAaKernelVariance. NaN where m is zero.
float NormalVariance(const glm::vec3& m, const glm::vec3& stepX, const glm::vec3& stepY);
// Toksvig's (2005) alpha^2 variance 2 (1 - |N|) / |N| of a normal map's filtered texel, whose decoded
// tangent-space normal has length `texelLength`, with |N| = min(texelLength +
// kNormalTexelLengthTolerance, 1).
float ToksvigVariance(float texelLength);
// The perceptual roughness `roughness` (GGX alpha = roughness^2) widened by `variance`: alpha^2 +
// min(variance, kappa), at most 1, back to a perceptual roughness by two square roots. `roughness`
// itself, bit for bit, where min(variance, kappa) is not positive (kappa 0 is off; NaN adds nothing).
float WidenedRoughness(float roughness, float variance, float kappa);

struct GBufferParams {
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
  // Also write the edge coverage (GBufferOutputs::edgeCoverage), which the edge anti-aliasing reads.
  bool edgeCoverage = false;
  // The most the normal's variance may add to GGX alpha^2 (specular anti-aliasing); 0 = off.
  float specularAaKappa = 0.0f;
};

struct GBufferInputs {
  const Scene& scene;
  const ViewProjection& view;  // perspective camera view of the G-buffer's size
};

// May hold the buffers of an earlier frame: those of the view's size are overwritten in place.
struct GBufferOutputs {
  GBuffer gbuffer;             // words 0-2 filled; word 3 set to kShadowLit (in the resolve's pass over the rows)
  VisibilityBuffer visibility; // the triangle index per pixel (for dumps and tests)
  // With GBufferParams::edgeCoverage: per pixel, the share of its area that each 4-neighbour's
  // surface covers across a geometric edge (EdgeCoverageWord); otherwise empty.
  Plane<uint32_t> edgeCoverage;
};

struct GBufferStats {
  RasterStats raster;
  double rasterMs = 0.0;
  double resolveMs = 0.0;
  size_t coveredPixels = 0;
  // Pixels with a non-zero edge coverage word, when asked for: computed in the resolve's row bands
  // while their visibility rows are in cache, so resolveMs includes it.
  size_t edgePixels = 0;
};

// `kernels` picks the raster's tile kernel and the resolve's row kernel; both paths give the same
// bytes.
GBufferStats RunGBuffer(const GBufferInputs& in, const GBufferParams& params, GBufferOutputs& out,
                        KernelPath kernels = KernelPath::kSimd);

// What the resolve of every row shares: the frame's constants.
struct GBufferResolveContext {
  const Scene& scene;
  const ViewProjection& view;
  const SurfaceResolver& resolver;  // the scene's surface seen from `view` (SceneRasterInput::Resolver)
  const uint32_t* constantWord0;    // per material: its word 0 when it has no colour or metallic texture
  // Per material: bits 24-31 of word 1 (the roughness code) when it has no roughness texture, and
  // whether any texture feeds word 0 or 1 (the SIMD kernel then also samples the pixel's textures).
  const uint32_t* constantRoughnessBits;
  const float* constantRoughness;  // per material: its roughness factor (what the bits above encode)
  // 0, 1, or kGBufferResolvedPerPixel for a material with a normal texture or vertex colours.
  const uint32_t* textured;
  glm::mat3 normalToView;           // world -> view for normals: view.view's rotation
  NormalEncoding normalEncoding;
  float specularAaKappa;  // GBufferParams'
  // The view's PixelRayTables, for the twin, which would otherwise divide for them in every vector;
  // kGBufferRayPadding more than the image's width and height (the rays one pixel right and down,
  // and the image edges' blocks).
  const float* rayDirectionX;
  const float* rayDirectionY;
};
inline constexpr int kGBufferRayPadding = 8;
// GBufferResolveContext::textured of the materials whose pixels the twin resolves one lane at a time
// with GBufferResolvePixelScalar (normal mapping and vertex colours are not vectorised): their bits
// are the scalar definition's by construction.
inline constexpr uint32_t kGBufferResolvedPerPixel = 2;

// The resolve of one pixel (x, y) covered by `triangle` with depth key `depthKey`: its G-buffer
// words 0-2.
void GBufferResolvePixelScalar(const GBufferResolveContext& context, uint32_t triangle, float depthKey, int x, int y,
                               uint32_t& word0, uint32_t& word1, uint32_t& word2);

// The resolve's scalar row kernel, the definition its SIMD twin (passes/gbuffer_simd.cpp) must equal
// bit for bit. Resolves row y of the visibility buffer (`width` triangle indices and depth keys)
// into the row's G-buffer words 0-2 and sets its word 3 to kShadowLit; pixels without a triangle
// (kNoTriangle) get the background's (0, 0, +inf), so every pixel is written and the twin's vector
// stores need not read the row first. Returns how many pixels it resolved.
size_t GBufferResolveRowScalar(const GBufferResolveContext& context, const uint32_t* triangles,
                               const float* depthKeys, int y, int width, uint32_t* word0, uint32_t* word1,
                               uint32_t* word2, uint32_t* word3);
// Its Highway twin, which resolves `rowCount` rows from y (at most kGBufferResolveRowsPerCall) of
// `visibility` into `gbuffer`'s words 0-3 at once: its vectors are blocks of pixels of those rows
// (4x4 on AVX-512, 4x2 on AVX2), so they meet fewer triangles than runs of a row. Returns how many
// pixels it resolved.
inline constexpr int kGBufferResolveRowsPerCall = 4;
size_t GBufferResolveRowsSimd(const GBufferResolveContext& context, const VisibilityBuffer& visibility, int y,
                              int rowCount, GBuffer& gbuffer);
// Beyond this much vertex data (view positions and normals), a row's triangles are mostly far apart
// in it and their vertices come from the outer cache or memory, so the twin asks for them ahead: the
// 1M-triangle knot (12 MB) resolved with its fetches confined to 1024 triangles took 13% less time,
// the 100k knot (1.2 MB) the same.
inline constexpr size_t kGBufferCachedVertexBytes = size_t(4) << 20;

// ---- Edge coverage (passes/gbuffer_edges.cpp, docs/pipeline.md §Edge coverage) ----
//
// Where two 4-neighbouring pixels see different surfaces across a geometric edge (GeometricEdge),
// the nearer pixel's triangle has an edge between the two pixel centres. Its screen-space line gives,
// as a box filter would, the share of each pixel's square on the other side of it: the share of the
// near pixel outside its triangle (covered by the far pixel's surface) and the share of the far
// pixel inside it. Each pair counts only along the line's major axis (a pair along x when the line's
// normal is closer to x), so a pixel is not blended twice across one line (Persson's GBAA).

// Depth ratio beyond which two pixels of different triangles with the same material are apart.
inline constexpr float kEdgeDepthJump = 0.02f;

// Whether neighbouring pixels a and b (triangle indices from the visibility buffer, view depths
// from G-buffer word 2) are on two sides of a geometric edge: different triangles, and one is the
// background, their materials differ (`materials`: per triangle) or their depths differ by more than
// the ratio 1 + kEdgeDepthJump.
bool GeometricEdge(uint32_t triangleA, uint32_t triangleB, float depthA, float depthB, const uint32_t* materials);

// The share of a unit pixel square on the inside of a line (the box filter's coverage): `distance`
// is the signed distance of the square's centre from the line, positive inside, in pixels, and
// (nx, ny) the line's unit normal.
double BoxCoverage(double distance, double nx, double ny);

// The edge coverage of rows [y0, y1) of the visibility buffer (which `view` rasterized from
// `scene`), with the view depths of its depth keys (those of G-buffer word 2). Returns the pixels
// with a non-zero word.
// Computed in double by this one definition (no SIMD twin): it runs on edge pairs only, and its
// output is integer.
size_t EdgeCoverageRows(const Scene& scene, const ViewProjection& view, const VisibilityBuffer& visibility, size_t y0,
                        size_t y1, Plane<uint32_t>& coverage);

}  // namespace ssgi
