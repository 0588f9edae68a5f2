// The Highway twin of RasterizeTileScalar (core/raster/raster.cpp, core/raster/raster_tile.h): lanes are the 64
// samples of an 8x8 block (a tile stores its blocks' samples consecutively, so a block is a few
// whole vectors). Per triangle and block, the edge functions at the block's corners (exact, 64-bit)
// reject or accept the whole block, as in Abrash's "Rasterization on Larrabee"; in a block that an
// edge crosses, the edge's values at a vector's samples are its value at the vector's first sample
// row plus per-lane steps set up once per triangle and tile, in 32-bit lanes (exact: a crossed
// block's values are within (|a| + |b|) 7 * 256 of 0, ScreenTriangle::edgesFit32Bits; a longer edge
// is evaluated per sample in 64 bits). Only the vectors of rows inside the triangle's bounds are
// visited; a triangle of up to 32x32 pixels takes a shorter path (RasterizeBoxInTile) in visibility
// rasters, and in depth-only ones where the tile is dense with small triangles.
// Depth keys are computed, compared and written in vectors with the scalar kernel's
// operations in its order (no fused multiply-add), so every target gives the scalar bytes
// (tests/core/raster/raster_simd_test.cpp checks each compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/raster/raster_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/cache_control.h"
#include "hwy/highway.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#include "core/math-inl.h"
#include "core/raster/raster_tile.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Lanes are samples of one block, at most a block per vector.
using DS = hn::CappedTag<int32_t, kRasterBlockSamples>;
using DK = hn::Rebind<float, DS>;
using DT = hn::Rebind<uint32_t, DS>;

// Sample k of a block is its pixel (k % 8, k / 8): its column, or with `row` its row.
template <class T>
constexpr std::array<T, kRasterBlockSamples> SampleOffsets(bool row) {
  std::array<T, kRasterBlockSamples> offsets{};
  for (int k = 0; k < kRasterBlockSamples; ++k)
    offsets[size_t(k)] = T(row ? k / kRasterBlockSize : k % kRasterBlockSize);
  return offsets;
}
alignas(64) constexpr auto kSampleX = SampleOffsets<int32_t>(false);
alignas(64) constexpr auto kSampleY = SampleOffsets<int32_t>(true);
alignas(64) constexpr auto kSampleXf = SampleOffsets<float>(false);
alignas(64) constexpr auto kSampleYf = SampleOffsets<float>(true);
// A vector of at least a block row holds the same columns in every vector of a block.
constexpr bool kWholeBlockRows = hn::MaxLanes(DS()) >= kRasterBlockSize;
// Vector k / lanes of a block starts at sample row k / 8, column k % 8: its samples' edge values are
// the row's first plus those of samples k % 8 ... k % 8 + lanes - 1 of the block's first rows.
constexpr size_t kStepSamples = kWholeBlockRows ? hn::MaxLanes(DS()) : kRasterBlockSize;

// Triangles of up to kBoxSpan x kBoxSpan pixels in a tile (most of a dense mesh's: the 100k-triangle
// knot's at 1024x1024 cover 18 samples on average, and 99.8% of its front faces fit 16x16) take a
// box path: the box of samples from the triangle's first column and row (the row rounded down to a
// multiple of the rows a vector holds) is drawn in parts of 8x8 samples, each a few vectors of whole
// part rows, or one row's part; its edge functions are stepped from the part's first sample in 32
// bits (exact: the vertices span at most kBoxVertexSpan); and each vector's samples, which lie in one
// or two blocks of the tile, are read from and written to both at once: the lanes in the first block
// at one address, those in the next block 56 values on (a block row on, less the part's row). For a
// triangle of a few blocks the block machinery costs more than its samples. Boxes of 32x32 rather
// than 16x16 take the larger triangles of a 10k-triangle knot (and triangles of 100 pixels) too;
// larger boxes lose on triangles many layers deep, whose hidden blocks the block path passes over.
constexpr int kBoxSpan = 32;
constexpr int kBoxPart = kRasterBlockSize;
constexpr int64_t kBoxVertexSpan = (kBoxSpan + 1) * kSubPixelScale;
// Where a part row's samples pass into the next block, their addresses jump this much further.
constexpr size_t kNextBlockOffset = kRasterBlockSamples - kRasterBlockSize;
// A vector of the box holds whole part rows (this many; kWholeBlockRows) or a part of one (1).
constexpr int kBoxRowsPerVector = int(std::max<size_t>(1, hn::MaxLanes(DS()) / kBoxPart));

// Counts, depth-tests and writes one vector of a box part's samples: the `covered` ones, whose keys
// are `key`. Those of `first` are in the block of the part's first column, at tile index `at`; the
// others in the next block, kNextBlockOffset further on, which only a part in two blocks (`twoBlocks`)
// reaches.
template <bool kWriteTriangle, bool kCountCoverage>
HWY_INLINE void DrawBoxVector(hn::Vec<DK> key, hn::Mask<DS> covered, hn::Mask<DS> first, bool twoBlocks, size_t at,
                              hn::Vec<DT> triangleId, TileTarget& tile) {
  const DK dk;
  const DT dt;
  const auto next = hn::AndNot(first, covered);
  if constexpr (kCountCoverage) {
    const auto one = hn::Set(dt, 1u);
    hn::BlendedStore(hn::Add(hn::LoadU(dt, tile.coverage + at), one), hn::RebindMask(dt, first), dt,
                     tile.coverage + at);
    if (twoBlocks) {
      uint32_t* coverage = tile.coverage + at + kNextBlockOffset;
      hn::BlendedStore(hn::Add(hn::LoadU(dt, coverage), one), hn::RebindMask(dt, next), dt, coverage);
    }
  }
  auto stored = hn::LoadU(dk, tile.depth + at);
  if (twoBlocks) {
    stored = hn::IfThenElse(hn::RebindMask(dk, next), hn::LoadU(dk, tile.depth + at + kNextBlockOffset), stored);
  }
  const auto nearer = hn::And(hn::RebindMask(dk, covered), hn::Gt(key, stored));
  const auto nearerFirst = hn::And(nearer, hn::RebindMask(dk, first));
  hn::BlendedStore(key, nearerFirst, dk, tile.depth + at);
  if constexpr (kWriteTriangle) hn::BlendedStore(triangleId, hn::RebindMask(dt, nearerFirst), dt, tile.triangle + at);
  if (twoBlocks) {
    const auto nearerNext = hn::And(nearer, hn::RebindMask(dk, next));
    hn::BlendedStore(key, nearerNext, dk, tile.depth + at + kNextBlockOffset);
    if constexpr (kWriteTriangle) {
      hn::BlendedStore(triangleId, hn::RebindMask(dt, nearerNext), dt, tile.triangle + at + kNextBlockOffset);
    }
  }
}

// The samples of one 8x8 part of the box, from (x0, y0) (tile x0 + lx0, y0 + ly0) to its last column
// x1 and row y1 (those of the triangle's bounds in it), as RasterizeBoxInTile draws them.
template <bool kWriteTriangle, bool kCountCoverage>
HWY_INLINE void RasterizeBoxPart(const ScreenTriangle& t, const EdgeFunction edge[3], float keyBase, int x0, int y0,
                                 int x1, int firstRow, int y1, TileTarget& tile) {
  const DS ds;
  const DK dk;
  const DT dt;
  const size_t lanes = hn::Lanes(ds);
  // Edge values at the part's first sample, and their steps per sample along x and y: every sample
  // of the box is within kBoxVertexSpan + kBoxSpan * 256 sub-pixel units of each vertex on each axis
  // and |a|, |b| <= kBoxVertexSpan, so the values are below 2^29 in magnitude.
  hn::Vec<DS> origin[3], stepX[3], stepY[3];
  for (int e = 0; e < 3; ++e) {
    origin[e] = hn::Set(ds, int32_t(edge[e].AtPixelCentre(x0, y0)));
    stepX[e] = hn::Set(ds, int32_t(edge[e].a * kSubPixelScale));
    stepY[e] = hn::Set(ds, int32_t(edge[e].b * kSubPixelScale));
  }
  const int lx0 = x0 - tile.x0, ly0 = y0 - tile.y0;
  // The part's columns in the block of its first (its first 8 - lx0 % 8), the rest in the next.
  const auto inFirstBlock = hn::Set(ds, kBoxPart - lx0 % kRasterBlockSize);
  const bool twoBlocks = lx0 % kRasterBlockSize + (x1 - x0) >= kRasterBlockSize;
  // Samples past the bounds' last column and row are masked (the tile's or the image's edge may have
  // cut them); rows above its first need no mask: their centres are above every vertex.
  const auto columns = hn::Set(ds, x1 - x0 + 1), rows = hn::Set(ds, y1 - y0 + 1);
  const auto minusOne = hn::Set(ds, -1);
  const auto keyBaseV = hn::Set(dk, keyBase);
  const auto keyDx = hn::Set(dk, float(t.keyDx)), keyDy = hn::Set(dk, float(t.keyDy));
  const auto lx0V = hn::Set(dk, float(lx0)), ly0V = hn::Set(dk, float(ly0));
  const auto triangleId = hn::Set(dt, t.triangle);
  const size_t firstSample = size_t(firstRow - y0) * kBoxPart / lanes * lanes;
  const size_t endSample = size_t(y1 - y0 + 1) * kBoxPart;
  // Where a vector holds whole part rows, every vector holds the same columns: their terms are
  // computed once and the rows' stepped from vector to vector, with the same values (the edge values
  // are exact integers, the rows small integers in floats). The box of a 10k-triangle knot's
  // triangle is mostly a few vectors, each of them cheaper so.
  const auto firstDx = hn::Load(ds, kSampleX.data() + firstSample);
  auto rowDy = hn::Load(ds, kSampleY.data() + firstSample);
  auto rowY = hn::Add(ly0V, hn::Load(dk, kSampleYf.data() + firstSample));
  const auto keyColumns =
      hn::Add(keyBaseV, hn::Mul(keyDx, hn::Add(lx0V, hn::Load(dk, kSampleXf.data() + firstSample))));
  const auto inColumns = hn::Lt(firstDx, columns);
  hn::Vec<DS> rowEdge[3], edgeRowStep[3];
  for (int e = 0; e < 3; ++e) {
    rowEdge[e] = hn::Add(origin[e], hn::Add(hn::Mul(stepX[e], firstDx), hn::Mul(stepY[e], rowDy)));
    edgeRowStep[e] = hn::Mul(stepY[e], hn::Set(ds, kBoxRowsPerVector));
  }
  for (size_t k = firstSample; k < endSample; k += lanes) {
    hn::Vec<DS> dx, inside;
    hn::Mask<DS> covered;
    hn::Vec<DK> key;
    if constexpr (kWholeBlockRows) {
      dx = firstDx;
      inside = hn::Or(rowEdge[0], hn::Or(rowEdge[1], rowEdge[2]));
      covered = hn::And(hn::Gt(inside, minusOne), hn::And(inColumns, hn::Lt(rowDy, rows)));
      key = hn::Add(keyColumns, hn::Mul(keyDy, rowY));
      for (int e = 0; e < 3; ++e) rowEdge[e] = hn::Add(rowEdge[e], edgeRowStep[e]);
      rowDy = hn::Add(rowDy, hn::Set(ds, kBoxRowsPerVector));
      rowY = hn::Add(rowY, hn::Set(dk, float(kBoxRowsPerVector)));
    } else {
      dx = hn::Load(ds, kSampleX.data() + k);
      const auto dy = hn::Load(ds, kSampleY.data() + k);
      inside = hn::Zero(ds);
      for (int e = 0; e < 3; ++e) {
        inside = hn::Or(inside, hn::Add(origin[e], hn::Add(hn::Mul(stepX[e], dx), hn::Mul(stepY[e], dy))));
      }
      covered = hn::And(hn::Gt(inside, minusOne), hn::And(hn::Lt(dx, columns), hn::Lt(dy, rows)));
      key = hn::Add(hn::Add(keyBaseV, hn::Mul(keyDx, hn::Add(lx0V, hn::Load(dk, kSampleXf.data() + k)))),
                    hn::Mul(keyDy, hn::Add(ly0V, hn::Load(dk, kSampleYf.data() + k))));
    }
    const auto first = hn::And(covered, hn::Lt(dx, inFirstBlock));
    // The vector's samples at `at` (the first block's lanes) and at + kNextBlockOffset (the next's).
    const size_t at = size_t(TilePixelIndex(lx0, ly0 + int(k) / kBoxPart)) + k % kBoxPart;
    DrawBoxVector<kWriteTriangle, kCountCoverage>(key, covered, first, twoBlocks, at, triangleId, tile);
  }
}

// Draws the triangle as RasterizeTileScalar does and returns true where its samples in the tile fit
// the box (and it has no alpha test); else returns false, having drawn nothing. It leaves
// blockFarthest as it was: keys only rise, so it still holds.
template <bool kWriteTriangle, bool kCountCoverage>
HWY_INLINE bool RasterizeBoxInTile(const ScreenTriangle& t, const AlphaTest& alphaTest, TileTarget& tile) {
  const BoundsInTile bounds(t, tile);
  if (bounds.Empty()) return true;
  const auto [x0, y0, x1, y1] = bounds;
  // Tiles start at multiples of 64 rows and parts at multiples of 8 rows from the box's first, so
  // a vector's part rows stay in one block row.
  const int boxY = y0 - (y0 - tile.y0) % kBoxRowsPerVector;
  if (x1 - x0 >= kBoxSpan || y1 - boxY >= kBoxSpan) return false;
  if ((t.flags & kTriangleAlphaTested) && alphaTest.passes) return false;
  const int32_t spanX = std::max({t.x[0], t.x[1], t.x[2]}) - std::min({t.x[0], t.x[1], t.x[2]});
  const int32_t spanY = std::max({t.y[0], t.y[1], t.y[2]}) - std::min({t.y[0], t.y[1], t.y[2]});
  if (spanX > kBoxVertexSpan || spanY > kBoxVertexSpan) return false;
  const float keyBase = KeyAtTileOrigin(t, tile);
  const EdgeFunction edge[3] = {t.Edge(0), t.Edge(1), t.Edge(2)};
  for (int partY = boxY; partY <= y1; partY += kBoxPart) {
    for (int partX = x0; partX <= x1; partX += kBoxPart) {
      RasterizeBoxPart<kWriteTriangle, kCountCoverage>(t, edge, keyBase, partX, partY,
                                                       std::min(x1, partX + kBoxPart - 1), std::max(y0, partY),
                                                       std::min(y1, partY + kBoxPart - 1), tile);
    }
  }
  return true;
}

// Hidden blocks, in depth-only rasters: a block whose farthest key (TileTarget::blockFarthest) is at
// or above every key the triangle can give its samples is passed over, and the triangle where that
// holds for the whole tile. A shadow map draws both faces of every caster, and most of its blocks
// are hidden when a triangle reaches them (Sponza's 2048 map: 69%); the camera's front faces hide
// few, and there the bookkeeping costs more than it saves, as it would where coverage is counted,
// before the depth test. Those keys are below the key plane's highest over the triangle (at a
// vertex: the samples are inside it) and over the block (at a corner), plus a margin for the float
// evaluation's roundings (a few, each within 2^-24 of the largest term; the margin is 16 times that).
struct HiddenBlocks {
  HiddenBlocks() = default;
  HWY_INLINE HiddenBlocks(const ScreenTriangle& t, const TileTarget& tile, float keyBase) {
    const double tileSpan = double(kRasterTileSize);
    const double margin =
        0x1p-20 * (std::abs(double(keyBase)) + tileSpan * (std::abs(double(t.keyDx)) + std::abs(double(t.keyDy)))) +
        0x1p-40 * (std::abs(t.keyAtOrigin) + std::abs(t.keyDx) * (tile.x0 + tileSpan) +
                   std::abs(t.keyDy) * (tile.y0 + tileSpan));
    keyCeiling = -std::numeric_limits<double>::infinity();
    for (int v = 0; v < 3; ++v) {
      keyCeiling = std::max(keyCeiling, t.keyAtOrigin + t.keyDx * (double(t.x[v]) * (1.0 / kSubPixelScale) - 0.5) +
                                            t.keyDy * (double(t.y[v]) * (1.0 / kSubPixelScale) - 0.5));
    }
    keyCeiling += margin;
    blockCeilingBase = double(keyBase) + margin;
    blockCeilingDx = double(float(t.keyDx));
    blockCeilingDy = double(float(t.keyDy));
    cornerX = blockCeilingDx > 0.0 ? kRasterBlockSize - 1 : 0;
    cornerY = blockCeilingDy > 0.0 ? kRasterBlockSize - 1 : 0;
  }

  // Every block of the tile is hidden: the triangle draws nothing there.
  HWY_INLINE bool HidesTile(const TileTarget& tile) const {
    const DK dk;
    const size_t lanes = hn::Lanes(dk);
    auto least = hn::Load(dk, tile.blockFarthest);
    for (size_t k = lanes; k < std::size(tile.blockFarthest); k += lanes)
      least = hn::Min(least, hn::Load(dk, tile.blockFarthest + k));
    return double(hn::GetLane(hn::MinOfLanes(dk, least))) >= keyCeiling;
  }

  // The block at tile pixel (lx, ly), whose farthest key is `farthest`, is hidden.
  HWY_INLINE bool HidesBlock(float farthest, int lx, int ly) const {
    const double blockCeiling = blockCeilingBase + blockCeilingDx * (lx + cornerX) + blockCeilingDy * (ly + cornerY);
    return double(farthest) >= std::min(keyCeiling, blockCeiling);
  }

  double keyCeiling = 0.0;  // over the triangle
  // Over a block: the key plane at its corner (lx + cornerX, ly + cornerY).
  double blockCeilingBase = 0.0, blockCeilingDx = 0.0, blockCeilingDy = 0.0;
  int cornerX = 0, cornerY = 0;
};

// An 8x8 block of the tile: its first pixel, in the image (bx, by) and in the tile (lx, ly), and the
// index of its first sample in the tile's arrays.
struct TileBlock {
  int bx, by, lx, ly;
  size_t index;
};

// The edges that cross a block (BlockEdges::Classify); the block's other edges hold all its samples
// inside.
struct CrossingEdges {
  int count;
  int index[3];       // which edges, in order
  int64_t corner[3];  // their values at the block's first sample
  // What the sample loop reads of them (BlockEdges::PrepareCrossing): where the edges fit 32 bits,
  // their values at the block's first sample, which it steps; else every sample's, evaluated in 64
  // bits, as 0 (inside) or -1 (outside).
  int32_t corner32[3];
  HWY_ALIGN int32_t outside[3][kRasterBlockSamples];
};

// A triangle's edges over the 8x8 blocks of a tile, set up once per triangle and tile. kEdges32:
// ScreenTriangle::edgesFit32Bits.
template <bool kEdges32>
struct BlockEdges {
  HWY_INLINE explicit BlockEdges(const ScreenTriangle& t) : edge{t.Edge(0), t.Edge(1), t.Edge(2)} {
    const DS ds;
    const size_t lanes = hn::Lanes(ds);
    constexpr int64_t kBlockSpan = (kRasterBlockSize - 1) * kSubPixelScale;
    for (int e = 0; e < 3; ++e) {
      const int64_t spanX = edge[e].a * kBlockSpan, spanY = edge[e].b * kBlockSpan;
      lowest[e] = std::min<int64_t>(spanX, 0) + std::min<int64_t>(spanY, 0);
      highest[e] = std::max<int64_t>(spanX, 0) + std::max<int64_t>(spanY, 0);
      if (!kEdges32) continue;
      const auto stepX = hn::Set(ds, int32_t(edge[e].a * kSubPixelScale));
      rowStep[e] = int32_t(edge[e].b * kSubPixelScale);
      for (size_t k = 0; k < kStepSamples; k += lanes) {
        const auto step = hn::Add(hn::Mul(stepX, hn::Load(ds, kSampleX.data() + k)),
                                  hn::Mul(hn::Set(ds, rowStep[e]), hn::Load(ds, kSampleY.data() + k)));
        hn::Store(step, ds, sampleStep[e] + k);
      }
    }
  }

  // False where an edge has all the block's samples outside (`corner`: the edges' values at its first
  // sample); else the edges that cross it go to `crossing`. Without branches on the edges: which way
  // a block goes is data, and mispredicted branches cost more than the tests.
  HWY_INLINE bool Classify(const int64_t corner[3], CrossingEdges& crossing) const {
    bool reject = false;
    crossing.count = 0;
    for (int e = 0; e < 3; ++e) {
      reject |= corner[e] + highest[e] < 0;
      crossing.index[crossing.count] = e;
      crossing.corner[crossing.count] = corner[e];
      crossing.count += corner[e] + lowest[e] < 0;
    }
    return !reject;
  }

  // The crossing edges' values as InsideSamples reads them.
  HWY_INLINE void PrepareCrossing(CrossingEdges& crossing) const {
    for (int c = 0; c < crossing.count; ++c) {
      if constexpr (kEdges32) {
        crossing.corner32[c] = int32_t(crossing.corner[c]);
      } else {
        const EdgeFunction& crossed = edge[crossing.index[c]];
        for (int k = 0; k < kRasterBlockSamples; ++k) {
          const int64_t value = crossing.corner[c] + crossed.a * kSampleX[size_t(k)] * kSubPixelScale +
                                crossed.b * kSampleY[size_t(k)] * kSubPixelScale;
          crossing.outside[c][k] = value >= 0 ? 0 : -1;
        }
      }
    }
  }

  // Which of the block's samples k .. k + lanes - 1 are inside every crossing edge: the OR of their
  // values is >= 0, i.e. > -1.
  HWY_INLINE hn::Mask<DS> InsideSamples(const CrossingEdges& crossing, size_t k) const {
    const DS ds;
    const size_t row = k / kRasterBlockSize, column = k % kRasterBlockSize;
    auto inside = hn::Zero(ds);
    for (int c = 0; c < crossing.count; ++c) {
      const int e = crossing.index[c];
      inside = hn::Or(inside, kEdges32 ? hn::Add(hn::Set(ds, crossing.corner32[c] + rowStep[e] * int32_t(row)),
                                                 hn::Load(ds, sampleStep[e] + column))
                                       : hn::Load(ds, crossing.outside[c] + k));
    }
    return hn::Gt(inside, hn::Set(ds, -1));
  }

  EdgeFunction edge[3];
  // Per edge: its extremes over a block relative to the block's first sample, and (32-bit edges) its
  // change from there to the first kStepSamples samples, and per sample row.
  int64_t lowest[3], highest[3];
  HWY_ALIGN int32_t sampleStep[3][kStepSamples];
  int32_t rowStep[3];
};

// Calls visit(block, corner) for each 8x8 block of the tile that the bounds overlap, row by row, with
// the edges' values at the block's first sample, stepped from block to block (exact integers).
template <bool kEdges32, class Visit>
HWY_INLINE void ForEachBlock(const BlockEdges<kEdges32>& edges, const BoundsInTile& bounds, const TileTarget& tile,
                             const Visit& visit) {
  const int firstBlockX = tile.x0 + (bounds.x0 - tile.x0) / kRasterBlockSize * kRasterBlockSize;
  const int firstBlockY = tile.y0 + (bounds.y0 - tile.y0) / kRasterBlockSize * kRasterBlockSize;
  int64_t rowCorner[3], blockStepX[3], blockStepY[3];
  for (int e = 0; e < 3; ++e) {
    rowCorner[e] = edges.edge[e].AtPixelCentre(firstBlockX, firstBlockY);
    blockStepX[e] = edges.edge[e].a * kRasterBlockSize * kSubPixelScale;
    blockStepY[e] = edges.edge[e].b * kRasterBlockSize * kSubPixelScale;
  }
  for (int by = firstBlockY; by <= bounds.y1; by += kRasterBlockSize) {
    const int ly = by - tile.y0;
    int64_t corner[3] = {rowCorner[0], rowCorner[1], rowCorner[2]};
    for (int e = 0; e < 3; ++e) rowCorner[e] += blockStepY[e];
    for (int bx = firstBlockX; bx <= bounds.x1; bx += kRasterBlockSize) {
      const int lx = bx - tile.x0;
      visit(TileBlock{bx, by, lx, ly, size_t(TilePixelIndex(lx, ly))}, corner);
      for (int e = 0; e < 3; ++e) corner[e] += blockStepX[e];
    }
  }
}

// What every block's samples take from the triangle, as vectors set once per triangle and tile: its
// key plane (the key at the tile's first pixel, and the steps per pixel in floats) and its index.
struct TriangleVectors {
  HWY_INLINE TriangleVectors(const ScreenTriangle& t, float keyAtTileOrigin)
      : keyBase(hn::Set(DK(), keyAtTileOrigin)),
        keyDx(hn::Set(DK(), float(t.keyDx))),
        keyDy(hn::Set(DK(), float(t.keyDy))),
        triangleId(hn::Set(DT(), t.triangle)) {}
  hn::Vec<DK> keyBase, keyDx, keyDy;
  hn::Vec<DT> triangleId;
};

// What DrawBlockSamples leaves to do.
struct BlockSamples {
  bool written = false;  // depth-only rasters: it wrote keys, which raise the block's farthest
  // An alpha-tested triangle's samples that are covered and nearer (bit k: sample k), with their keys,
  // for the test; another triangle's are written already.
  uint64_t visible = 0;
  HWY_ALIGN float keys[kRasterBlockSamples];
};

// Covers, counts and depth-tests the block's samples a vector at a time, over the vectors holding its
// sample rows inside the triangle's bounds (the others cover nothing), and writes those that pass;
// an alpha-tested triangle's are left in `samples` for the test.
template <bool kWriteTriangle, bool kCountCoverage, bool kEdges32>
HWY_INLINE void DrawBlockSamples(const TriangleVectors& vectors, const BoundsInTile& bounds,
                                 const BlockEdges<kEdges32>& edges, const CrossingEdges& crossing,
                                 const TileBlock& block, bool alphaTested, TileTarget& tile, BlockSamples& samples) {
  constexpr bool kSkipHidden = !kWriteTriangle && !kCountCoverage;
  const DS ds;
  const DK dk;
  const DT dt;
  const size_t lanes = hn::Lanes(ds);
  const auto keyBaseV = vectors.keyBase, keyDx = vectors.keyDx, keyDy = vectors.keyDy;
  const auto triangleId = vectors.triangleId;
  // Samples past the image's right or bottom edge are not the tile's.
  const bool clipped = block.lx + kRasterBlockSize > tile.width || block.ly + kRasterBlockSize > tile.height;
  const auto tileWidth = hn::Set(ds, tile.width - block.lx), tileHeight = hn::Set(ds, tile.height - block.ly);
  const auto lxV = hn::Set(dk, float(block.lx)), lyV = hn::Set(dk, float(block.ly));
  float* depth = tile.depth + block.index;
  auto written = hn::FirstN(dk, 0);  // kSkipHidden
  // The key keyBase + keyDx * float(lx) + keyDy * float(ly) in the scalar kernel's order; its
  // first sum depends only on the sample's column (k % 8).
  auto keyOfColumns = [&](size_t k) {
    return hn::Add(keyBaseV, hn::Mul(keyDx, hn::Add(lxV, hn::Load(dk, kSampleXf.data() + k % kRasterBlockSize))));
  };
  const auto blockKeyOfColumns = keyOfColumns(0);
  const size_t firstSample = size_t(std::max(bounds.y0, block.by) - block.by) * kRasterBlockSize / lanes * lanes;
  const size_t endSample =
      size_t(std::min(bounds.y1, block.by + kRasterBlockSize - 1) - block.by + 1) * kRasterBlockSize;
  for (size_t k = firstSample; k < endSample; k += lanes) {
    auto covered = edges.InsideSamples(crossing, k);
    if (clipped) {
      covered = hn::And(covered, hn::And(hn::Lt(hn::Load(ds, kSampleX.data() + k), tileWidth),
                                         hn::Lt(hn::Load(ds, kSampleY.data() + k), tileHeight)));
    }
    if constexpr (kCountCoverage) {
      uint32_t* coverage = tile.coverage + block.index + k;
      const auto count = hn::Load(dt, coverage);
      hn::Store(hn::Sub(count, hn::BitCast(dt, hn::VecFromMask(ds, covered))), dt, coverage);
    }
    // No test for a vector with nothing covered: it is rare outside the edges' blocks, and there
    // unpredictable; its store writes back what it loaded.
    const auto key = hn::Add(kWholeBlockRows ? blockKeyOfColumns : keyOfColumns(k),
                             hn::Mul(keyDy, hn::Add(lyV, hn::Load(dk, kSampleYf.data() + k))));
    const auto stored = hn::Load(dk, depth + k);
    const auto nearer = hn::And(hn::RebindMask(dk, covered), hn::Gt(key, stored));
    if (alphaTested) {
      hn::Store(key, dk, samples.keys + k);
      samples.visible |= LaneBits(dk, nearer) << k;
      continue;
    }
    if constexpr (kSkipHidden) written = hn::Or(written, nearer);
    hn::Store(hn::IfThenElse(nearer, key, stored), dk, depth + k);
    if constexpr (kWriteTriangle) {
      uint32_t* triangle = tile.triangle + block.index + k;
      hn::Store(hn::IfThenElse(hn::RebindMask(dt, nearer), triangleId, hn::Load(dt, triangle)), dt, triangle);
    }
  }
  if constexpr (kSkipHidden) samples.written = !hn::AllFalse(dk, written);
}

// Asks the alpha test, once for the block, about the samples DrawBlockSamples left, and writes those
// that pass; true where any did.
template <bool kWriteTriangle>
HWY_INLINE bool WriteAlphaTestedSamples(const ScreenTriangle& t, const AlphaTest& alphaTest, const TileBlock& block,
                                        const BlockSamples& samples, TileTarget& tile) {
  if (samples.visible == 0) return false;
  uint64_t passed = alphaTest.passes(alphaTest.context, t.triangle, block.bx, block.by, samples.visible);
  if (passed == 0) return false;
  for (; passed != 0; passed &= passed - 1) {
    const int sample = std::countr_zero(passed);
    tile.depth[block.index + size_t(sample)] = samples.keys[sample];
    if constexpr (kWriteTriangle) tile.triangle[block.index + size_t(sample)] = t.triangle;
  }
  return true;
}

// The farthest of a block's 64 keys `depth`, for TileTarget::blockFarthest.
HWY_INLINE float FarthestKeyOfBlock(const float* depth) {
  const DK dk;
  const size_t lanes = hn::Lanes(dk);
  auto least = hn::Load(dk, depth);
  for (size_t k = lanes; k < kRasterBlockSamples; k += lanes) least = hn::Min(least, hn::Load(dk, depth + k));
  return hn::GetLane(hn::MinOfLanes(dk, least));
}

// The block path: each 8x8 block of the tile that the triangle's bounds overlap is rejected or
// accepted on its edges' values at the block's corners, passed over where hidden (HiddenBlocks), and
// its samples drawn. kEdges32: t.edgesFit32Bits, as a template parameter so the sample loop has no
// branch on it. Flattened: its steps, the per-block lambda too, are inlined into one loop nest.
template <bool kWriteTriangle, bool kCountCoverage, bool kEdges32>
HWY_FLATTEN void RasterizeInTile(const ScreenTriangle& t, const AlphaTest& alphaTest, TileTarget& tile) {
  const BoundsInTile bounds(t, tile);
  if (bounds.Empty()) return;
  const float keyBase = KeyAtTileOrigin(t, tile);
  constexpr bool kSkipHidden = !kWriteTriangle && !kCountCoverage;  // HiddenBlocks says why
  HiddenBlocks hidden;
  if constexpr (kSkipHidden) {
    hidden = HiddenBlocks(t, tile, keyBase);
    if (hidden.HidesTile(tile)) return;
  }
  const bool alphaTested = (t.flags & kTriangleAlphaTested) && alphaTest.passes;
  const BlockEdges<kEdges32> edges(t);
  const TriangleVectors vectors(t, keyBase);
  ForEachBlock(edges, bounds, tile, [&](const TileBlock& block, const int64_t corner[3]) {
    CrossingEdges crossing;
    if (!edges.Classify(corner, crossing)) return;
    float& farthest = tile.blockFarthest[block.index / kRasterBlockSamples];
    if (kSkipHidden && hidden.HidesBlock(farthest, block.lx, block.ly)) return;
    edges.PrepareCrossing(crossing);
    BlockSamples samples;
    DrawBlockSamples<kWriteTriangle, kCountCoverage>(vectors, bounds, edges, crossing, block, alphaTested, tile,
                                                     samples);
    const bool wrote =
        alphaTested ? WriteAlphaTestedSamples<kWriteTriangle>(t, alphaTest, block, samples, tile) : samples.written;
    // Written keys only raise the block's farthest; kept up to date, it hides more of later triangles.
    if (kSkipHidden && wrote) farthest = FarthestKeyOfBlock(tile.depth + block.index);
  });
}

void RasterizeTile(const TileTriangles& batch, TileTarget& tile) {
  ForEachTileTriangle(batch, [&](const ScreenTriangle& t, auto writeTriangle, auto countCoverage) {
    // Depth-only rasters pass over hidden blocks in the block path, which saves them more where the
    // triangles are not tiny.
    if ((writeTriangle || countCoverage || batch.smallTriangles) &&
        RasterizeBoxInTile<writeTriangle, countCoverage>(t, *batch.alphaTest, tile)) {
      return;
    }
    if (t.edgesFit32Bits) {
      RasterizeInTile<writeTriangle, countCoverage, true>(t, *batch.alphaTest, tile);
    } else {
      RasterizeInTile<writeTriangle, countCoverage, false>(t, *batch.alphaTest, tile);
    }
  });
}

void CopyTileOut(const TileTarget& tile, const uint32_t* values, uint8_t* firstPixel, size_t rowBytes) {
  // Lanes are a block row's pixels (or a part of it): whole aligned vectors, as streaming wants.
  const hn::CappedTag<uint32_t, kRasterBlockSize> d;
  const size_t lanes = hn::Lanes(d);
  for (int y = 0; y < tile.height; ++y) {
    uint32_t* row = reinterpret_cast<uint32_t*>(firstPixel + size_t(y) * rowBytes);
    int x = 0;
    for (; x + kRasterBlockSize <= tile.width; x += kRasterBlockSize) {
      const uint32_t* block = values + TilePixelIndex(x, y);
      for (size_t i = 0; i < kRasterBlockSize; i += lanes) hn::Stream(hn::Load(d, block + i), d, row + x + i);
    }
    if (x < tile.width) std::memcpy(row + x, values + TilePixelIndex(x, y), size_t(tile.width - x) * sizeof(uint32_t));
  }
}

// The vertex projection and the triangle set-up work in doubles, as their definitions do.
using DD = hn::ScalableTag<double>;
using DL = hn::RebindToSigned<DD>;

// ProjectVerticesScalar's twin: lanes are vertices. The clip position in floats with glm's operations
// in their order (its w = 1 term m3 * 1 is m3 exactly), then the definition's double arithmetic;
// RoundHalfAway's truncation is ConvertTo's, exact for the snapped range.
void ProjectVertices(const glm::vec3* positions, size_t count, const glm::mat4& viewProjection, int width, int height,
                     ProjectedVertex* out) {
  const DD dd;
  const DL dl;
  const hn::Rebind<float, DD> df;
  using VD = hn::Vec<DD>;
  using VL = hn::Vec<DL>;
  constexpr size_t kMaxLanes = hn::MaxLanes(DD());
  const size_t lanes = hn::Lanes(dd);
  const ClipPlanes planes(width, height);
  const VD zero = hn::Zero(dd), half = hn::Set(dd, 0.5), one = hn::Set(dd, 1.0);
  const VD guardX = hn::Set(dd, planes.guardX), guardY = hn::Set(dd, planes.guardY);
  const VD widthV = hn::Set(dd, double(width)), heightV = hn::Set(dd, double(height));
  const VD subPixels = hn::Set(dd, double(kSubPixelScale));
  const VL lowHalf = hn::Set(dl, int64_t(0xFFFFFFFF));
  const VL outsideMarker = hn::Set(dl, int64_t(uint64_t(uint32_t(ProjectedVertex::kOutsideClipPlanes)) << 32));
  const auto roundHalfAway = [&](VD x) {  // RoundHalfAway (core/raster/raster.cpp)
    const VL truncated = hn::ConvertTo(dl, x);
    const VD fraction = hn::Sub(x, hn::ConvertTo(dd, truncated));
    const VL up = hn::IfThenElseZero(hn::RebindMask(dl, hn::Ge(fraction, half)), hn::Set(dl, 1));
    const VL down = hn::IfThenElseZero(hn::RebindMask(dl, hn::Le(fraction, hn::Neg(half))), hn::Set(dl, 1));
    return hn::Sub(hn::Add(truncated, up), down);
  };
  for (size_t i = 0; i < count; i += lanes) {
    const size_t n = std::min(lanes, count - i);
    HWY_ALIGN float staged[3 * kMaxLanes];
    const float* xyz = &positions[i].x;
    if (n < lanes) {  // the last vector's lanes past the end project the origin, never stored
      std::fill(std::begin(staged), std::end(staged), 0.0f);
      std::memcpy(staged, xyz, n * sizeof(glm::vec3));
      xyz = staged;
    }
    hn::Vec<decltype(df)> px, py, pz;
    hn::LoadInterleaved3(df, xyz, px, py, pz);
    VD clip[4];
    for (int r = 0; r < 4; ++r) {
      const auto column = [&](int c) { return hn::Set(df, viewProjection[c][r]); };
      clip[r] = hn::PromoteTo(dd, hn::Add(hn::Add(hn::Mul(column(0), px), hn::Mul(column(1), py)),
                                          hn::Add(hn::Mul(column(2), pz), column(3))));
    }
    const VD &x = clip[0], &y = clip[1], &z = clip[2], &w = clip[3];
    const VD distance[ClipPlanes::kCount] = {hn::Sub(w, z),
                                             z,
                                             hn::Sub(hn::Mul(guardX, w), x),
                                             hn::Add(hn::Mul(guardX, w), x),
                                             hn::Sub(hn::Mul(guardY, w), y),
                                             hn::Add(hn::Mul(guardY, w), y)};
    VL outside = hn::Zero(dl);
    for (int p = 0; p < ClipPlanes::kCount; ++p)
      outside = hn::Or(outside, hn::IfThenZeroElse(hn::RebindMask(dl, hn::Ge(distance[p], zero)), hn::Set(dl, 1 << p)));
    // Snap (core/raster/raster.cpp)
    const VD invW = hn::Div(one, w);
    const VD sx = hn::Mul(hn::Add(hn::Mul(hn::Mul(x, invW), half), half), widthV);
    const VD sy = hn::Mul(hn::Sub(half, hn::Mul(hn::Mul(y, invW), half)), heightV);
    const VL snappedX = roundHalfAway(hn::Mul(sx, subPixels)), snappedY = roundHalfAway(hn::Mul(sy, subPixels));
    const VD key = hn::Mul(z, invW);
    const auto inside = hn::Eq(outside, hn::Zero(dl));
    const VL position = hn::IfThenElse(inside, hn::Or(hn::And(snappedX, lowHalf), hn::ShiftLeft<32>(snappedY)),
                                       hn::Or(outside, outsideMarker));
    const VL keyBits = hn::IfThenElseZero(inside, hn::BitCast(dl, key));
    if (n == lanes) {
      hn::StoreInterleaved2(position, keyBits, dl, reinterpret_cast<int64_t*>(out + i));
    } else {
      HWY_ALIGN int64_t words[2 * kMaxLanes];
      hn::StoreInterleaved2(position, keyBits, dl, words);
      std::memcpy(out + i, words, n * sizeof(ProjectedVertex));
    }
  }
}

// A vector of triangles for SetUpTriangles (lanes are triangles): their corners' indices into the
// ProjectedVertex array, and whether their flags cull back faces (1 or 0).
struct TriangleCorners {
  hn::Vec<hn::Rebind<uint32_t, DD>> corner[3];
  hn::Vec<DL> cullsBackFace;
};

// Triangles first .. first + n - 1 (n at most a vector's lanes), read as vectors; a last, partial
// vector's lanes past the end repeat its last triangle.
HWY_INLINE TriangleCorners LoadTriangleCorners(const uint32_t* indices, const uint8_t* flags, uint8_t uniformFlags,
                                               size_t first, size_t n) {
  const DL dl;
  const hn::Rebind<uint32_t, DD> du32;
  const hn::Rebind<uint8_t, DD> du8;
  const hn::RebindToUnsigned<DL> du64;
  constexpr size_t kMaxLanes = hn::MaxLanes(DD());
  const size_t lanes = hn::Lanes(DD());
  const uint32_t* corners = indices + 3 * first;
  const uint8_t* triangleFlags = flags ? flags + first : nullptr;
  HWY_ALIGN uint32_t stagedCorners[3 * kMaxLanes];
  HWY_ALIGN uint8_t stagedFlags[kMaxLanes];
  if (n < lanes) {
    for (size_t j = 0; j < lanes; ++j) {
      const size_t from = std::min(j, n - 1);
      for (int k = 0; k < 3; ++k) stagedCorners[3 * j + size_t(k)] = corners[3 * from + size_t(k)];
      if (flags) stagedFlags[j] = triangleFlags[from];
    }
    corners = stagedCorners;
    if (flags) triangleFlags = stagedFlags;
  }
  TriangleCorners loaded;
  hn::LoadInterleaved3(du32, corners, loaded.corner[0], loaded.corner[1], loaded.corner[2]);
  loaded.cullsBackFace =
      triangleFlags
          ? hn::BitCast(dl, hn::PromoteTo(du64, hn::PromoteTo(du32, hn::And(hn::LoadU(du8, triangleFlags),
                                                                            hn::Set(du8, kTriangleCullBackFace)))))
          : hn::Set(dl, (uniformFlags & kTriangleCullBackFace) ? 1 : 0);
  return loaded;
}

// The vertices of a vector of triangles (lanes are triangles), gathered from their ProjectedVertex.
struct TriangleVertices {
  hn::Vec<DD> x[3], y[3], key[3];
  // ProjectedVertex::Outside of the three vertices, ORed and ANDed.
  hn::Vec<DL> outsideAny, outsideAll;
};

HWY_INLINE TriangleVertices GatherVertices(const ProjectedVertex* projected, const TriangleCorners& corners) {
  const DD dd;
  const DL dl;
  const hn::RebindToUnsigned<DL> du64;
  // ProjectedVertex is two 64-bit words: x and y (low and high halves), and the key.
  const int64_t* positions = reinterpret_cast<const int64_t*>(projected);
  const double* keys = reinterpret_cast<const double*>(projected) + 1;
  const auto outsideMarker = hn::Set(dl, int64_t(ProjectedVertex::kOutsideClipPlanes));
  TriangleVertices v;
  v.outsideAny = hn::Zero(dl);
  v.outsideAll = hn::Set(dl, -1);
  for (int k = 0; k < 3; ++k) {
    const auto word = hn::ShiftLeft<1>(hn::BitCast(dl, hn::PromoteTo(du64, corners.corner[k])));
    const auto position = hn::GatherIndex(dl, positions, word);
    const auto low = hn::ShiftRight<32>(hn::ShiftLeft<32>(position)), high = hn::ShiftRight<32>(position);
    v.x[k] = hn::ConvertTo(dd, low);
    v.y[k] = hn::ConvertTo(dd, high);
    v.key[k] = hn::GatherIndex(dd, keys, word);
    const auto outside = hn::IfThenElseZero(hn::Eq(high, outsideMarker), low);  // ProjectedVertex::Outside
    v.outsideAny = hn::Or(v.outsideAny, outside);
    v.outsideAll = hn::And(v.outsideAll, outside);
  }
  return v;
}

// SetUpScreenTriangle for a vector of triangles whose vertices are all inside the clip planes, its
// results stored a row per field (lanes are triangles) for SetUpTriangles to read back per triangle.
struct SetUpRows {
  static constexpr size_t kMaxLanes = hn::MaxLanes(DD());
  enum Field {
    kX0,
    kY0 = kX0 + 3,
    kMinX = kY0 + 3,
    kMaxX,
    kMinY,
    kMaxY,
    kKeyDx,
    kKeyDy,
    kKeyAtOrigin,
    kCulled,
    kEdgesFit,
    kFields
  };

  HWY_INLINE SetUpRows(TriangleVertices v, hn::Vec<DL> cullsBackFace, int width, int height) {
    const DD dd;
    const DL dl;
    using VD = hn::Vec<DD>;
    using MD = hn::Mask<DD>;
    const VD zero = hn::Zero(dd), half = hn::Set(dd, 0.5);
    const VD toPixels = hn::Set(dd, 1.0 / double(kSubPixelScale));
    const VD toPixelArea = hn::Set(dd, 1.0 / double(kSubPixelScale * kSubPixelScale));
    auto &x = v.x, &y = v.y, &key = v.key;
    VD area2 = hn::Sub(hn::Mul(hn::Sub(x[1], x[0]), hn::Sub(y[2], y[0])), hn::Mul(hn::Sub(y[1], y[0]), hn::Sub(x[2], x[0])));
    // Counter-clockwise front faces turn clockwise in y-down screen space: vertices 1 and 2 swap.
    const MD backFacing = hn::Gt(area2, zero);
    MD culled = hn::Or(hn::Eq(area2, zero),
                       hn::And(backFacing, hn::RebindMask(dd, hn::Ne(cullsBackFace, hn::Zero(dl)))));
    const VD x1 = hn::IfThenElse(backFacing, x[1], x[2]), x2 = hn::IfThenElse(backFacing, x[2], x[1]);
    const VD y1 = hn::IfThenElse(backFacing, y[1], y[2]), y2 = hn::IfThenElse(backFacing, y[2], y[1]);
    const VD key1 = hn::IfThenElse(backFacing, key[1], key[2]), key2 = hn::IfThenElse(backFacing, key[2], key[1]);
    x[1] = x1, x[2] = x2, y[1] = y1, y[2] = y2, key[1] = key1, key[2] = key2;
    area2 = hn::IfThenElse(backFacing, area2, hn::Neg(area2));
    // Pixels whose centre sample lies inside the snapped bounds.
    const VD minSx = hn::Min(hn::Min(x[0], x[1]), x[2]), maxSx = hn::Max(hn::Max(x[0], x[1]), x[2]);
    const VD minSy = hn::Min(hn::Min(y[0], y[1]), y[2]), maxSy = hn::Max(hn::Max(y[0], y[1]), y[2]);
    const VD startOffset = hn::Set(dd, double(kSubPixelScale - 1 - kHalfPixel));
    const VD halfPixel = hn::Set(dd, double(kHalfPixel));
    const VD minX = hn::Max(zero, hn::Floor(hn::Mul(hn::Add(minSx, startOffset), toPixels)));
    const VD maxX = hn::Min(hn::Set(dd, double(width - 1)), hn::Floor(hn::Mul(hn::Sub(maxSx, halfPixel), toPixels)));
    const VD minY = hn::Max(zero, hn::Floor(hn::Mul(hn::Add(minSy, startOffset), toPixels)));
    const VD maxY = hn::Min(hn::Set(dd, double(height - 1)), hn::Floor(hn::Mul(hn::Sub(maxSy, halfPixel), toPixels)));
    culled = hn::Or(culled, hn::Or(hn::Gt(minX, maxX), hn::Gt(minY, maxY)));
    // ScreenTriangle::Edge(e) runs from vertex e + 1 to e + 2: |a| + |b| = |dy| + |dx|.
    MD edgesFit = hn::Eq(zero, zero);
    for (int e = 0; e < 3; ++e) {
      const int from = (e + 1) % 3, to = (e + 2) % 3;
      const VD slope = hn::Add(hn::Abs(hn::Sub(y[to], y[from])), hn::Abs(hn::Sub(x[to], x[from])));
      edgesFit = hn::And(edgesFit, hn::Le(slope, hn::Set(dd, double(kMaxEdgeSlopeFor32Bits))));
    }
    // The depth key's plane in pixel units.
    const VD x10 = hn::Mul(hn::Sub(x[1], x[0]), toPixels), y10 = hn::Mul(hn::Sub(y[1], y[0]), toPixels);
    const VD x20 = hn::Mul(hn::Sub(x[2], x[0]), toPixels), y20 = hn::Mul(hn::Sub(y[2], y[0]), toPixels);
    const VD k10 = hn::Sub(key[1], key[0]), k20 = hn::Sub(key[2], key[0]);
    const VD det = hn::Mul(area2, toPixelArea);
    const VD keyDx = hn::Div(hn::Sub(hn::Mul(k10, y20), hn::Mul(k20, y10)), det);
    const VD keyDy = hn::Div(hn::Sub(hn::Mul(k20, x10), hn::Mul(k10, x20)), det);
    const VD keyAtOrigin = hn::Add(hn::Add(key[0], hn::Mul(keyDx, hn::Sub(half, hn::Mul(x[0], toPixels)))),
                                   hn::Mul(keyDy, hn::Sub(half, hn::Mul(y[0], toPixels))));
    const VD fields[kFields] = {x[0], x[1], x[2], y[0], y[1], y[2], minX, maxX, minY, maxY, keyDx, keyDy, keyAtOrigin,
                                hn::VecFromMask(dd, culled), hn::VecFromMask(dd, edgesFit)};
    for (int f = 0; f < kFields; ++f) hn::Store(fields[f], dd, lane[f]);
  }

  // Lane j's triangle, which SetUpScreenTriangle culls (an all-ones mask is a NaN, not 0).
  bool Culled(size_t j) const { return lane[kCulled][j] != 0.0; }

  // Lane j's ScreenTriangle but its triangle and flags.
  void Write(size_t j, ScreenTriangle& t) const {
    for (int k = 0; k < 3; ++k) {
      t.x[k] = int32_t(lane[kX0 + k][j]);
      t.y[k] = int32_t(lane[kY0 + k][j]);
    }
    t.minX = int16_t(lane[kMinX][j]);
    t.maxX = int16_t(lane[kMaxX][j]);
    t.minY = int16_t(lane[kMinY][j]);
    t.maxY = int16_t(lane[kMaxY][j]);
    t.keyDx = lane[kKeyDx][j];
    t.keyDy = lane[kKeyDy][j];
    t.keyAtOrigin = lane[kKeyAtOrigin][j];
    t.edgesFit32Bits = lane[kEdgesFit][j] != 0.0;
  }

  HWY_ALIGN double lane[kFields][kMaxLanes];
};

// SetUpTrianglesScalar's twin: lanes are triangles, in doubles. The snapped coordinates (|x| <
// 2^24), their differences' products and the doubled area are whole numbers below 2^53, so the
// integer definition's values come out exactly; the rest is the definition's double arithmetic in
// its order, and its floor divisions by 256 are exact scalings and Floor.
size_t SetUpTriangles(const ProjectedVertex* projected, const uint32_t* indices, const uint8_t* flags,
                      uint8_t uniformFlags, uint32_t first, size_t count, int width, int height, ScreenTriangle* out,
                      TriangleSetUp* status) {
  const DL dl;
  constexpr size_t kMaxLanes = hn::MaxLanes(DD());
  const size_t lanes = hn::Lanes(DD());
  size_t setUp = 0;
  for (size_t i = 0; i < count; i += lanes) {
    const size_t n = std::min(lanes, count - i);
    const TriangleCorners corners = LoadTriangleCorners(indices, flags, uniformFlags, size_t(first) + i, n);
    const TriangleVertices vertices = GatherVertices(projected, corners);
    const SetUpRows rows(vertices, corners.cullsBackFace, width, height);
    HWY_ALIGN int64_t any[kMaxLanes], all[kMaxLanes];
    hn::Store(vertices.outsideAny, dl, any);
    hn::Store(vertices.outsideAll, dl, all);
    for (size_t j = 0; j < n; ++j) {
      TriangleSetUp& result = status[i + j];
      if (all[j] != 0) {  // all three outside one plane
        result = TriangleSetUp::kCulled;
      } else if (any[j] != 0) {
        result = TriangleSetUp::kClip;
      } else if (rows.Culled(j)) {
        result = TriangleSetUp::kCulled;
      } else {
        result = TriangleSetUp::kSetUp;
        ScreenTriangle& t = out[setUp++];
        rows.Write(j, t);
        t.triangle = first + uint32_t(i + j);
        t.flags = TriangleFlagsOf(flags, uniformFlags, t.triangle);
      }
    }
  }
  return setUp;
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(RasterizeTile);
HWY_EXPORT(CopyTileOut);
HWY_EXPORT(SetUpTriangles);
HWY_EXPORT(ProjectVertices);

void ProjectVerticesSimd(const glm::vec3* positions, size_t count, const glm::mat4& viewProjection, int width,
                         int height, ProjectedVertex* out) {
  HWY_DYNAMIC_DISPATCH(ProjectVertices)(positions, count, viewProjection, width, height, out);
}

size_t SetUpTrianglesSimd(const ProjectedVertex* projected, const uint32_t* indices, const uint8_t* flags,
                          uint8_t uniformFlags, uint32_t first, size_t count, int width, int height,
                          ScreenTriangle* out, TriangleSetUp* status) {
  return HWY_DYNAMIC_DISPATCH(SetUpTriangles)(projected, indices, flags, uniformFlags, first, count, width, height,
                                              out, status);
}

void CopyTileOutSimd(const TileTarget& tile, const uint32_t* values, uint8_t* firstPixel, size_t rowBytes) {
  HWY_DYNAMIC_DISPATCH(CopyTileOut)(tile, values, firstPixel, rowBytes);
  // Streamed stores are weakly ordered: fence them before another thread reads the image.
  hwy::FlushStream();
}

void RasterizeTileSimd(const TileTriangles& batch, TileTarget& tile) {
  HWY_DYNAMIC_DISPATCH(RasterizeTile)(batch, tile);
}

}  // namespace ssgi
#endif
