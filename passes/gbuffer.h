// G-buffer pass (docs/design.md §3-4, docs/pipeline.md §G-buffer): rasterizes the scene's triangles into a
// visibility buffer (core/raster/raster.h, core/raster/scene_raster_input.h), then resolves each visible pixel
// once: barycentrics from the view ray through the pixel centre and the original (unclipped)
// triangle, interpolated normal and UV, mip-mapped texture lookups with the UV footprint of the
// neighbouring pixels' rays (core/surface.h), and packs the 128-bit G-buffer. Alpha cut-out (map_d)
// is tested during rasterization.
#pragma once

#include <cstddef>

#include "core/camera.h"
#include "core/gbuffer.h"
#include "core/kernel_path.h"
#include "core/raster/raster.h"
#include "core/scene.h"
#include "core/surface.h"

namespace ssgi {

struct GBufferParams {
  NormalEncoding normalEncoding = NormalEncoding::kOct24;
};

struct GBufferInputs {
  const Scene& scene;
  const ViewProjection& view;  // perspective camera view of the G-buffer's size
};

// May hold the buffers of an earlier frame: those of the view's size are overwritten in place.
struct GBufferOutputs {
  GBuffer gbuffer;             // words 0-2 filled; word 3 set to kShadowLit (in the resolve's pass over the rows)
  VisibilityBuffer visibility; // the triangle index per pixel (for dumps and tests)
};

struct GBufferStats {
  RasterStats raster;
  double rasterMs = 0.0;
  double resolveMs = 0.0;
  size_t coveredPixels = 0;
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
  // 0, 1, or kGBufferResolvedPerPixel for a material with a normal texture or vertex colours.
  const uint32_t* textured;
  glm::mat3 normalToView;           // world -> view for normals: view.view's rotation
  NormalEncoding normalEncoding;
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

}  // namespace ssgi
