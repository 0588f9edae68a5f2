// The tile kernel of the rasterizer (core/raster/raster.h, docs/pipeline.md §Rasterizer): the set-up
// triangles, the tile they are drawn into, and the kernel's two definitions, the scalar one
// (core/raster/raster.cpp, the readable definition) and its Highway twin (core/raster/raster_simd.cpp), which
// must give the same depth keys, triangle indices and coverage counts bit for bit on every target.
// Internal to the rasterizer and its tests.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "core/raster/raster.h"
#include "hwy/cache_control.h"

namespace ssgi {

inline constexpr int kSubPixelBits = 8;
inline constexpr int64_t kSubPixelScale = 1 << kSubPixelBits;
inline constexpr int64_t kHalfPixel = kSubPixelScale / 2;
// A block's 64 samples are one 64-bit mask.
inline constexpr int kRasterBlockSamples = kRasterBlockSize * kRasterBlockSize;
inline constexpr int kRasterTileBlocks = kRasterTileSize / kRasterBlockSize;
inline constexpr int kRasterTilePixels = kRasterTileSize * kRasterTileSize;

struct EdgeFunction {
  // E(sx, sy) = a * sx + b * sy + c over fixed-point sample positions; c carries the fill-rule bias,
  // so a sample is inside exactly when E >= 0.
  int64_t a, b, c;
  // E at the centre of pixel (px, py).
  int64_t AtPixelCentre(int px, int py) const {
    return a * (px * kSubPixelScale + kHalfPixel) + b * (py * kSubPixelScale + kHalfPixel) + c;
  }
};

// Above this |a| + |b|, an edge's values over one 8x8 block no longer fit in 32 bits: they span
// (kRasterBlockSize - 1) * kSubPixelScale * (|a| + |b|), and a block the edge crosses holds 0.
inline constexpr int64_t kMaxEdgeSlopeFor32Bits =
    std::numeric_limits<int32_t>::max() / ((kRasterBlockSize - 1) * kSubPixelScale);

// A set-up triangle in one cache line: a tile reads each of its triangles with one miss at most,
// however many triangles the mesh has.
struct alignas(64) ScreenTriangle {
  int32_t x[3], y[3];              // snapped vertices (8 sub-pixel bits), ordered for positive area
  int16_t minX, minY, maxX, maxY;  // inclusive pixel bounds, clipped to the image
  // Depth key at pixel centre (px + 0.5, py + 0.5) is keyAtOrigin + keyDx * px + keyDy * py.
  double keyAtOrigin, keyDx, keyDy;
  uint32_t triangle;
  uint8_t flags;
  bool edgesFit32Bits;  // every edge's |a| + |b| <= kMaxEdgeSlopeFor32Bits

  // Edge e runs from vertex e + 1 to vertex e + 2: E(P) = (to - from) x (P - from), positive
  // inside; not top-left edges (dy > 0, or dy = 0 and dx < 0) have c one lower, so that a sample on
  // them is outside.
  EdgeFunction Edge(int e) const {
    const int from = (e + 1) % 3, to = (e + 2) % 3;
    const int64_t dx = int64_t(x[to]) - x[from], dy = int64_t(y[to]) - y[from];
    const bool topLeft = dy < 0 || (dy == 0 && dx > 0);
    return {-dy, dx, dy * x[from] - dx * y[from] - (topLeft ? 0 : 1)};
  }
};
static_assert(sizeof(ScreenTriangle) == 64);

// A vertex in fixed-point screen space: 8 sub-pixel bits (inside the guard band, |x|, |y| < 3 *
// 16384 * 256 < 2^24), and the depth key z / w.
struct SnappedVertex {
  int32_t x, y;
  double key;
};

// A vertex projected once for all its triangles: where it lies inside every clip plane, its snapped
// position; else y is kOutsideClipPlanes and x the mask of the planes it is outside of (bit p: plane
// p). 16 bytes: the batched set-up gathers a vertex as two 64-bit words.
struct ProjectedVertex {
  static constexpr int32_t kOutsideClipPlanes = INT32_MIN;
  SnappedVertex snapped;
  int32_t Outside() const { return snapped.y == kOutsideClipPlanes ? snapped.x : 0; }
};
static_assert(sizeof(ProjectedVertex) == 2 * sizeof(int64_t));

// Signed distances of a clip-space vertex to the clip planes (core/raster/raster.h: near, far, and the guard
// band 16384 pixels beyond each image edge); inside where >= 0.
struct ClipPlanes {
  ClipPlanes(int width, int height);
  double guardX, guardY;
  static constexpr int kCount = 6;
  std::array<double, kCount> Distances(const glm::dvec4& v) const {
    return {v.w - v.z, v.z, guardX * v.w - v.x, guardX * v.w + v.x, guardY * v.w - v.y, guardY * v.w + v.y};
  }
};

// A world position in clip space: glm's matrix product, whose float operations (m0 x + m1 y) + (m2 z
// + m3 1) the twin repeats.
inline glm::vec4 ClipPosition(const glm::vec3& position, const glm::mat4& viewProjection) {
  return viewProjection * glm::vec4(position, 1.0f);
}

// Projects vertices 0 .. count - 1 once for all their triangles (docs/pipeline.md §Rasterizer, steps
// 1-2): each one's clip position tested against the clip planes, and where it is inside all of them
// snapped to the width x height image's sub-pixel grid with its depth key. The scalar definition
// (core/raster/raster.cpp) and its Highway twin (core/raster/raster_simd.cpp; lanes are vertices), equal byte for
// byte on every target.
void ProjectVerticesScalar(const glm::vec3* positions, size_t count, const glm::mat4& viewProjection, int width,
                           int height, ProjectedVertex* out);
void ProjectVerticesSimd(const glm::vec3* positions, size_t count, const glm::mat4& viewProjection, int width,
                         int height, ProjectedVertex* out);

// The set-up of one triangle from its snapped vertices (docs/pipeline.md §Rasterizer, step 3) into
// `out`: false, and `out` unspecified, where it is culled (zero area, a back face its flags cull, no
// pixel centre in the width x height image).
bool SetUpScreenTriangle(const SnappedVertex& s0, const SnappedVertex& s1, const SnappedVertex& s2, uint32_t triangle,
                         uint8_t flags, int width, int height, ScreenTriangle& out);

// Triangle t's TriangleFlags mask: flags[t], or `uniformFlags` where there is no per-triangle array
// (RasterInput::triangleFlags is null).
inline uint8_t TriangleFlagsOf(const uint8_t* flags, uint8_t uniformFlags, size_t t) {
  return flags ? flags[t] : uniformFlags;
}

enum class TriangleSetUp : uint8_t {
  kCulled,  // wholly outside one clip plane, or culled by SetUpScreenTriangle
  kSetUp,   // set up into its ScreenTriangle
  kClip,    // crosses a clip plane: the caller clips it
};

// The set-up of triangles first .. first + count - 1 (`indices` 3 per triangle into `projected`,
// `flags` one per triangle, or null for `uniformFlags` on every one): status[i] says what became of
// triangle first + i, and the ScreenTriangles of those set up (kSetUp) go to out[0], out[1], ... in
// that order. Returns how many. The scalar definition (core/raster/raster.cpp) and its Highway twin
// (core/raster/raster_simd.cpp; lanes are triangles), equal field for field on every target.
size_t SetUpTrianglesScalar(const ProjectedVertex* projected, const uint32_t* indices, const uint8_t* flags,
                            uint8_t uniformFlags, uint32_t first, size_t count, int width, int height,
                            ScreenTriangle* out, TriangleSetUp* status);
size_t SetUpTrianglesSimd(const ProjectedVertex* projected, const uint32_t* indices, const uint8_t* flags,
                          uint8_t uniformFlags, uint32_t first, size_t count, int width, int height,
                          ScreenTriangle* out, TriangleSetUp* status);

// Index of tile pixel (lx, ly) in a TileTarget's arrays: blocks row by row, and inside a block its
// 64 samples row by row, so a block is 64 consecutive values (one or a few vectors).
constexpr int TilePixelIndex(int lx, int ly) {
  return ((ly / kRasterBlockSize) * kRasterTileBlocks + lx / kRasterBlockSize) * kRasterBlockSamples +
         (ly % kRasterBlockSize) * kRasterBlockSize + lx % kRasterBlockSize;
}

// The SIMD kernel's box path (core/raster/raster_simd.cpp) loads whole vectors from a box row's first
// sample, whose lanes past the row are not used: they can reach this many values past a tile
// array's last, which the arrays hold (filled with the rest), so no load leaves them.
inline constexpr int kTileArraySlack = kRasterBlockSize;

struct TileTarget {
  int x0, y0, width, height;  // the tile's pixels in the image
  alignas(64) float depth[kRasterTilePixels + kTileArraySlack];
  // Per 8x8 block, a key at or below every depth key the block holds (the clear key, 0, at first).
  // Kept by the SIMD kernel, which passes over a block no key of the triangle can beat: an
  // optimisation with no effect on the bytes (the scalar kernel, the definition, does not read it).
  alignas(64) float blockFarthest[kRasterTileBlocks * kRasterTileBlocks];
  // Written when TileTriangles::writeTriangle.
  alignas(64) uint32_t triangle[kRasterTilePixels + kTileArraySlack];
  // Counted when TileTriangles::countCoverage.
  alignas(64) uint32_t coverage[kRasterTilePixels + kTileArraySlack];
};

// The pixels of a triangle's bounds inside a tile, x0..x1 by y0..y1 (none where x0 > x1 or y0 > y1).
struct BoundsInTile {
  BoundsInTile(const ScreenTriangle& t, const TileTarget& tile)
      : x0(std::max<int>(t.minX, tile.x0)),
        y0(std::max<int>(t.minY, tile.y0)),
        x1(std::min<int>(t.maxX, tile.x0 + tile.width - 1)),
        y1(std::min<int>(t.maxY, tile.y0 + tile.height - 1)) {}
  bool Empty() const { return x0 > x1 || y0 > y1; }
  int x0, y0, x1, y1;
};

// A triangle's depth key at the tile's first pixel, from which the kernels step it across the tile:
// the plane relative to the tile keeps the float evaluation's cancellation small.
inline float KeyAtTileOrigin(const ScreenTriangle& t, const TileTarget& tile) {
  return float(t.keyAtOrigin + t.keyDx * tile.x0 + t.keyDy * tile.y0);
}

// The triangles of one set-up chunk that overlap a tile, in submission order, and what to write.
struct TileTriangles {
  const ScreenTriangle* triangles;  // the chunk's set-up triangles
  const uint32_t* entries;          // indices into `triangles` of those binned to the tile
  size_t count;
  const AlphaTest* alphaTest;
  bool writeTriangle;  // TileTarget::triangle (visibility) or depth only
  bool countCoverage;  // TileTarget::coverage: +1 per covered sample, before the depth test
  // The tile has at least a triangle per kSmallTrianglePixels pixels (all chunks together), so most
  // of its triangles are a few pixels: where the SIMD kernel takes its box path in depth-only rasters
  // too (elsewhere their block path's hidden-block skipping saves more). No effect on the bytes.
  bool smallTriangles;
};
inline constexpr size_t kSmallTrianglePixels = 4;

// Calls draw(triangle, writeTriangle, countCoverage) for the batch's triangles in order, the two
// flags as std::bool_constant, so a kernel's inner loops are compiled once per output.
template <class Draw>
void ForEachTileTriangle(const TileTriangles& batch, const Draw& draw) {
  // With many small triangles the set-up triangles are far more than the caches hold, and a tile's
  // are scattered through its chunk: each is fetched kPrefetchTriangles ahead of its turn.
  constexpr size_t kPrefetchTriangles = 4;
  for (size_t k = 0; k < batch.count; ++k) {
    if (k + kPrefetchTriangles < batch.count) {
      const char* ahead = reinterpret_cast<const char*>(&batch.triangles[batch.entries[k + kPrefetchTriangles]]);
      hwy::Prefetch(ahead);
      hwy::Prefetch(ahead + sizeof(ScreenTriangle) - 1);
    }
    const ScreenTriangle& t = batch.triangles[batch.entries[k]];
    if (batch.countCoverage) {
      draw(t, std::true_type{}, std::true_type{});
    } else if (batch.writeTriangle) {
      draw(t, std::true_type{}, std::false_type{});
    } else {
      draw(t, std::false_type{}, std::false_type{});
    }
  }
}

// Draws the triangles into the tile (docs/pipeline.md §Rasterizer steps 4-7): for each triangle,
// each 8x8 block of the tile its bounds overlap is trivially rejected or accepted on the edge
// functions at the block's corners, then each covered sample's depth key is compared with the
// tile's (GREATER wins), the alpha test asked once per block for the samples that passed, and the
// survivors written.
void RasterizeTileScalar(const TileTriangles& batch, TileTarget& tile);
void RasterizeTileSimd(const TileTriangles& batch, TileTarget& tile);

// Copies the tile's `width` x `height` 4-byte values (TilePixelIndex order: its depth keys or
// triangle indices) into the image: `firstPixel` is the tile's first pixel there, rows `rowBytes`
// apart. The twin streams whole block rows past the caches (non-temporal stores): the image is
// written once here and read only by a later pass, and a 2048^2 shadow map (16 MiB) is larger than
// the caches anyway, so the stores need not read the lines they overwrite.
void CopyTileOutScalar(const TileTarget& tile, const uint32_t* values, uint8_t* firstPixel, size_t rowBytes);
void CopyTileOutSimd(const TileTarget& tile, const uint32_t* values, uint8_t* firstPixel, size_t rowBytes);

}  // namespace ssgi
