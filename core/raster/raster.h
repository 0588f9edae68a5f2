// The tile-based rasterizer (docs/design.md §4, docs/pipeline.md §Rasterizer).
//
// It writes a visibility buffer: per pixel the reversed-Z depth key of the nearest surface and the
// index of its triangle. Attributes are resolved afterwards, once per visible pixel, so overdraw
// costs a depth test and nothing more.
//
// Contract, in order of the pipeline:
//  - vertices are transformed to clip space by ViewProjection::viewProjection;
//  - triangles are clipped in homogeneous space against the near plane (z <= w), the far plane
//    (z >= 0, orthographic only in practice) and a guard band 16384 pixels beyond each image edge,
//    so no vertex with w <= 0 is ever divided by;
//  - screen positions are snapped to fixed point with 8 sub-pixel bits; edge functions are exact
//    64-bit integers with the top-left fill rule, sampled at pixel centres (x + 0.5, y + 0.5):
//    triangles sharing an edge cover each pixel on it exactly once (watertight);
//  - zero-area triangles (after snapping) are dropped; back faces (clockwise on screen for
//    counter-clockwise front faces) are dropped where the triangle's flags ask for culling;
//  - the depth key z_clip / w is interpolated linearly in screen space (exact for both projections)
//    and tested with GREATER against a buffer cleared to 0; ties keep the earlier triangle;
//  - triangles are binned into 64x64 tiles; each tile is rasterized by one thread in submission
//    order, so the output does not depend on the thread count; inside a tile, 8x8 blocks are
//    trivially rejected or accepted before samples are tested.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/camera.h"
#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
inline constexpr int kRasterTileSize = 64;
inline constexpr int kRasterBlockSize = 8;  // tiles are tested in blocks of 8x8 samples

enum TriangleFlags : uint8_t {
  kTriangleCullBackFace = 1u << 0,
  kTriangleAlphaTested = 1u << 1,  // the alpha test is asked before a sample is written
};

// Asked once per block of an alpha-tested triangle, for the block's samples that the triangle covers
// and that pass the depth test: bit kRasterBlockSize j + i of `samples` is pixel (x0 + i, y0 + j). Returns
// the subset that passes the alpha test; the others are discarded. `context` is AlphaTest::context.
// One call per block rather than per sample keeps the function pointer out of the sample loop.
struct AlphaTest {
  uint64_t (*passes)(const void* context, uint32_t triangle, int x0, int y0, uint64_t samples) = nullptr;
  const void* context = nullptr;
};

struct RasterInput {
  const glm::vec3* positions = nullptr;  // world space
  size_t vertexCount = 0;
  const uint32_t* indices = nullptr;     // 3 per triangle
  size_t triangleCount = 0;
  const uint8_t* triangleFlags = nullptr;  // one TriangleFlags mask per triangle; null: uniformFlags for all
  AlphaTest alphaTest;
  uint8_t uniformFlags = 0;  // every triangle's TriangleFlags mask where triangleFlags is null
};

struct VisibilityBuffer {
  Plane<float> depthKey;     // reversed-Z z_ndc of the nearest surface; 0 where nothing was drawn
  Plane<uint32_t> triangle;  // its triangle index, kNoTriangle where nothing was drawn
};

struct RasterStats {
  size_t trianglesIn = 0;
  size_t trianglesCulled = 0;     // back faces, outside the view, zero area or no pixel centre
  size_t trianglesClipped = 0;    // needed polygon clipping (near plane or guard band)
  size_t trianglesSetUp = 0;      // screen triangles binned (a clipped triangle may give several)
  size_t binEntries = 0;          // (triangle, tile) pairs rasterized
};

enum class RasterOutput {
  kVisibility,  // depth key and triangle index
  kDepthOnly,   // depth key only (shadow maps); `triangle` is left empty
};

VisibilityBuffer MakeVisibilityBuffer(int width, int height, RasterOutput output);

// Rasterizes every triangle into `target` (made by MakeVisibilityBuffer with the size of `view` and
// `output`), overwriting every pixel: a target kept from an earlier frame needs no clearing. If
// `coverageCount` is not null (same size, zeroed), every covered sample adds one to it before the
// depth test: a watertight mesh tiling the screen gives 1 everywhere. `kernels` picks the tile
// kernel (core/raster/raster_tile.h); both give the same bytes.
RasterStats Rasterize(const RasterInput& input, const ViewProjection& view, RasterOutput output,
                      VisibilityBuffer& target, Plane<uint32_t>* coverageCount = nullptr,
                      KernelPath kernels = KernelPath::kSimd);

}  // namespace ssgi
