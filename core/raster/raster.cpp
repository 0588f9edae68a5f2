#include "core/raster/raster.h"

#include <algorithm>
#include <array>
#include <bit>
#include <memory>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"
#include "core/raster/raster_tile.h"

namespace ssgi {
namespace {

constexpr double kGuardBandPixels = 16384.0;
// Triangles are set up and binned in chunks; a tile reads the chunks' bins in chunk order, which is
// submission order, whatever thread built each chunk. A chunk has kMaxChunkTriangles, fewer for
// small meshes so that at least kMinChunks share the set-up between threads (with three chunks, two
// threads wait on one); not fewer than kMinChunkTriangles, since each tile reads every chunk's
// bins. The output does not depend on the chunk size.
constexpr size_t kMaxChunkTriangles = 8192;
constexpr size_t kMinChunkTriangles = 1024;
constexpr size_t kMinChunks = 8;
constexpr size_t kChunkVertices = 16384;
constexpr int kMaxClippedVertices = 3 + 6;  // one more vertex per clip plane at most

struct ChunkBins {
  std::vector<ScreenTriangle> triangles;
  std::vector<uint32_t> tileStart;  // tileCount + 1 offsets into entries
  std::vector<uint32_t> entries;    // indices into triangles, grouped by tile
  RasterStats stats;
};

// llround (half away from zero) without the library call GCC keeps for it; x - trunc(x) is exact.
int64_t RoundHalfAway(double x) {
  const int64_t truncated = int64_t(x);
  const double fraction = x - double(truncated);
  return truncated + int64_t(fraction >= 0.5) - int64_t(fraction <= -0.5);
}

int64_t FloorDiv(int64_t a, int64_t b) {
  const int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// Sutherland-Hodgman against one plane; returns the new vertex count.
int ClipPolygon(const glm::dvec4* in, int count, int plane, const ClipPlanes& planes, glm::dvec4* out) {
  int written = 0;
  for (int i = 0; i < count; ++i) {
    const glm::dvec4& a = in[i];
    const glm::dvec4& b = in[(i + 1) % count];
    const double da = planes.Distances(a)[plane];
    const double db = planes.Distances(b)[plane];
    if (da >= 0.0) out[written++] = a;
    if ((da >= 0.0) != (db >= 0.0)) {
      const double t = da / (da - db);
      out[written++] = a + (b - a) * t;
    }
  }
  return written;
}

// A clip-space position's screen position snapped to the sub-pixel grid, and its depth key.
SnappedVertex Snap(const glm::dvec4& v, int width, int height) {
  const double invW = 1.0 / v.w;
  const double sx = (v.x * invW * 0.5 + 0.5) * double(width);
  const double sy = (0.5 - v.y * invW * 0.5) * double(height);
  // Inside the guard band: 32 bits hold them.
  return {int32_t(RoundHalfAway(sx * double(kSubPixelScale))), int32_t(RoundHalfAway(sy * double(kSubPixelScale))),
          v.z * invW};
}

class Setup {
 public:
  Setup(const ViewProjection& view, int tilesX, int tilesY)
      : planes_(view.width, view.height), width_(view.width), height_(view.height), tilesX_(tilesX), tilesY_(tilesY) {}

  // Sets up triangles begin .. end - 1 into `bins`: in batches (SIMD across triangles), then taken in
  // submission order, the ones that cross a clip plane clipped here.
  void SetUp(const RasterInput& input, const glm::mat4& viewProjection, const ProjectedVertex* projected,
             KernelPath kernels, size_t begin, size_t end, ChunkBins& bins) const {
    const auto setUpTriangles = kernels == KernelPath::kSimd ? SetUpTrianglesSimd : SetUpTrianglesScalar;
    bins.triangles.reserve(end - begin);
    constexpr size_t kBatch = 256;
    ScreenTriangle batch[kBatch];
    TriangleSetUp status[kBatch];
    for (size_t i = begin; i < end; i += kBatch) {
      const size_t count = std::min(kBatch, end - i);
      for (size_t k = 3 * i; k < 3 * (i + count); ++k) SSGI_CHECK_LT(input.indices[k], input.vertexCount);
      const size_t setUp = setUpTriangles(projected, input.indices, input.triangleFlags, input.uniformFlags,
                                          uint32_t(i), count, width_, height_, batch, status);
      bins.stats.trianglesIn += count;
      bins.stats.trianglesSetUp += setUp;
      const size_t clipped = size_t(std::count(status, status + count, TriangleSetUp::kClip));
      bins.stats.trianglesCulled += count - setUp - clipped;
      if (clipped == 0) {
        bins.triangles.insert(bins.triangles.end(), batch, batch + setUp);
        continue;
      }
      size_t next = 0;
      for (size_t j = 0; j < count; ++j) {
        if (status[j] == TriangleSetUp::kSetUp) {
          bins.triangles.push_back(batch[next++]);
        } else if (status[j] == TriangleSetUp::kClip) {
          const uint32_t triangle = uint32_t(i + j);
          Clip(input.positions, viewProjection, input.indices + 3 * size_t(triangle), triangle,
               TriangleFlagsOf(input.triangleFlags, input.uniformFlags, triangle), bins);
        }
      }
    }
  }

  // A triangle that crosses a clip plane (TriangleSetUp::kClip): clipped in homogeneous space and
  // set up as a fan of the clipped polygon. Its vertices' clip positions are computed again, as
  // ProjectVerticesScalar computes them.
  void Clip(const glm::vec3* positions, const glm::mat4& viewProjection, const uint32_t* index, uint32_t triangle,
            uint8_t flags, ChunkBins& bins) const {
    ++bins.stats.trianglesClipped;
    glm::dvec4 polygon[2][kMaxClippedVertices];
    for (int i = 0; i < 3; ++i) polygon[0][i] = glm::dvec4(ClipPosition(positions[index[i]], viewProjection));
    int count = 3;
    int current = 0;
    for (int p = 0; p < ClipPlanes::kCount && count >= 3; ++p) {
      count = ClipPolygon(polygon[current], count, p, planes_, polygon[current ^ 1]);
      current ^= 1;
    }
    bool emitted = false;
    for (int i = 1; i + 1 < count; ++i) {
      ScreenTriangle t;
      if (!SetUpScreenTriangle(Snap(polygon[current][0], width_, height_), Snap(polygon[current][i], width_, height_),
                               Snap(polygon[current][i + 1], width_, height_), triangle, flags, width_, height_, t))
        continue;
      bins.triangles.push_back(t);
      ++bins.stats.trianglesSetUp;
      emitted = true;
    }
    if (!emitted) ++bins.stats.trianglesCulled;
  }

  // Counting sort of the chunk's triangles into the tiles their bounds overlap.
  void Bin(ChunkBins& bins) const {
    const size_t tileCount = size_t(tilesX_) * size_t(tilesY_);
    bins.tileStart.assign(tileCount + 1, 0);
    auto forEachTile = [&](const ScreenTriangle& t, auto&& fn) {
      for (int ty = t.minY / kRasterTileSize; ty <= t.maxY / kRasterTileSize; ++ty)
        for (int tx = t.minX / kRasterTileSize; tx <= t.maxX / kRasterTileSize; ++tx) fn(size_t(ty) * tilesX_ + tx);
    };
    for (const ScreenTriangle& t : bins.triangles) forEachTile(t, [&](size_t tile) { ++bins.tileStart[tile + 1]; });
    for (size_t i = 0; i < tileCount; ++i) bins.tileStart[i + 1] += bins.tileStart[i];
    bins.entries.resize(bins.tileStart[tileCount]);
    std::vector<uint32_t> cursor(bins.tileStart.begin(), bins.tileStart.end() - 1);
    for (uint32_t i = 0; i < bins.triangles.size(); ++i)
      forEachTile(bins.triangles[i], [&](size_t tile) { bins.entries[cursor[tile]++] = i; });
    bins.stats.binEntries = bins.entries.size();
  }

 private:
  ClipPlanes planes_;
  int width_, height_;
  int tilesX_, tilesY_;
};

template <bool kWriteTriangle, bool kCountCoverage>
void RasterizeInTile(const ScreenTriangle& t, const AlphaTest& alphaTest, TileTarget& tile) {
  const BoundsInTile bounds(t, tile);
  if (bounds.Empty()) return;
  const auto [x0, y0, x1, y1] = bounds;
  const bool alphaTested = (t.flags & kTriangleAlphaTested) && alphaTest.passes;
  const float keyBase = KeyAtTileOrigin(t, tile);
  const float keyDx = float(t.keyDx), keyDy = float(t.keyDy);
  const EdgeFunction edge[3] = {t.Edge(0), t.Edge(1), t.Edge(2)};

  // Hierarchical test on the tile's 8x8 blocks: an edge's extremes over the samples of a block
  // inside the bounds [x0, x1] x [y0, y1] are at two of their corners.
  const int firstBlockX = tile.x0 + (x0 - tile.x0) / kRasterBlockSize * kRasterBlockSize;
  const int firstBlockY = tile.y0 + (y0 - tile.y0) / kRasterBlockSize * kRasterBlockSize;
  for (int by = firstBlockY; by <= y1; by += kRasterBlockSize) {
    const int sy0 = std::max(by, y0), sy1 = std::min(by + kRasterBlockSize - 1, y1);
    for (int bx = firstBlockX; bx <= x1; bx += kRasterBlockSize) {
      const int sx0 = std::max(bx, x0), sx1 = std::min(bx + kRasterBlockSize - 1, x1);
      bool reject = false, accept = true;
      for (int e = 0; e < 3; ++e) {
        const int64_t corner = edge[e].AtPixelCentre(sx0, sy0);
        const int64_t spanX = edge[e].a * int64_t(sx1 - sx0) * kSubPixelScale;
        const int64_t spanY = edge[e].b * int64_t(sy1 - sy0) * kSubPixelScale;
        const int64_t lo = corner + std::min<int64_t>(spanX, 0) + std::min<int64_t>(spanY, 0);
        const int64_t hi = corner + std::max<int64_t>(spanX, 0) + std::max<int64_t>(spanY, 0);
        reject = reject || hi < 0;
        accept = accept && lo >= 0;
      }
      if (reject) continue;

      // The block's samples that are covered and pass the depth test (bit 8 j + i: pixel
      // (bx + i, by + j)), with their keys.
      uint64_t visible = 0;
      float keys[kRasterBlockSamples];
      const int64_t s0 = edge[0].a * kSubPixelScale, s1 = edge[1].a * kSubPixelScale;
      const int64_t s2 = edge[2].a * kSubPixelScale;
      for (int py = sy0; py <= sy1; ++py) {
        int64_t e0 = edge[0].AtPixelCentre(sx0, py), e1 = edge[1].AtPixelCentre(sx0, py);
        int64_t e2 = edge[2].AtPixelCentre(sx0, py);
        const int ly = py - tile.y0;
        for (int px = sx0; px <= sx1; ++px, e0 += s0, e1 += s1, e2 += s2) {
          if (!accept && (e0 | e1 | e2) < 0) continue;
          const int lx = px - tile.x0;
          const int i = TilePixelIndex(lx, ly);
          if constexpr (kCountCoverage) ++tile.coverage[i];
          const float key = keyBase + keyDx * float(lx) + keyDy * float(ly);
          if (!(key > tile.depth[i])) continue;
          const int sample = (py - by) * kRasterBlockSize + (px - bx);
          visible |= uint64_t(1) << sample;
          keys[sample] = key;
        }
      }
      if (alphaTested && visible != 0) visible = alphaTest.passes(alphaTest.context, t.triangle, bx, by, visible);
      for (; visible != 0; visible &= visible - 1) {
        const int sample = std::countr_zero(visible);
        const int i =
            TilePixelIndex(bx - tile.x0 + sample % kRasterBlockSize, by - tile.y0 + sample / kRasterBlockSize);
        tile.depth[i] = keys[sample];
        if constexpr (kWriteTriangle) tile.triangle[i] = t.triangle;
      }
    }
  }
}

// Projects every vertex once for all its triangles (ProjectedVertex), in chunks of kChunkVertices.
void ProjectAllVertices(const RasterInput& input, const ViewProjection& view, KernelPath kernels,
                        ProjectedVertex* projected) {
  const auto projectVertices = kernels == KernelPath::kSimd ? ProjectVerticesSimd : ProjectVerticesScalar;
  ParallelFor("raster.transform", (input.vertexCount + kChunkVertices - 1) / kChunkVertices, [&](size_t chunk) {
    const size_t begin = chunk * kChunkVertices, end = std::min(input.vertexCount, begin + kChunkVertices);
    projectVertices(input.positions + begin, end - begin, view.viewProjection, view.width, view.height,
                    projected + begin);
  });
}

// Sets up the triangles and bins them into the tilesX x tilesY tiles, a ChunkBins per chunk.
std::vector<ChunkBins> SetUpAndBin(const RasterInput& input, const ViewProjection& view,
                                   const ProjectedVertex* projected, KernelPath kernels, int tilesX, int tilesY) {
  const Setup setup(view, tilesX, tilesY);
  const size_t chunkTriangles =
      std::clamp((input.triangleCount + kMinChunks - 1) / kMinChunks, kMinChunkTriangles, kMaxChunkTriangles);
  std::vector<ChunkBins> chunks((input.triangleCount + chunkTriangles - 1) / chunkTriangles);
  ParallelFor("raster.setup_and_bin", chunks.size(), [&](size_t c) {
    const size_t begin = c * chunkTriangles;
    const size_t end = std::min(input.triangleCount, begin + chunkTriangles);
    ChunkBins& bins = chunks[c];
    setup.SetUp(input, view.viewProjection, projected, kernels, begin, end, bins);
    setup.Bin(bins);
  });
  return chunks;
}

// The calling thread's tile, set to tile tileIndex of the view's and cleared: the arrays this output
// needs; the others are never read. Kept from tile to tile and frame to frame: made anew for each,
// its 49 KB went back to the allocator and came again as fresh pages.
TileTarget& ClearedThreadTile(size_t tileIndex, int tilesX, const ViewProjection& view, bool writeTriangle,
                              bool countCoverage) {
  static thread_local const auto threadTile = std::make_unique_for_overwrite<TileTarget>();
  TileTarget& tile = *threadTile;
  tile.x0 = int(tileIndex % tilesX) * kRasterTileSize;
  tile.y0 = int(tileIndex / tilesX) * kRasterTileSize;
  tile.width = std::min(kRasterTileSize, view.width - tile.x0);
  tile.height = std::min(kRasterTileSize, view.height - tile.y0);
  std::fill(std::begin(tile.depth), std::end(tile.depth), 0.0f);
  std::fill(std::begin(tile.blockFarthest), std::end(tile.blockFarthest), 0.0f);
  if (writeTriangle) std::fill(std::begin(tile.triangle), std::end(tile.triangle), kNoTriangle);
  if (countCoverage) std::fill(std::begin(tile.coverage), std::end(tile.coverage), 0u);
  return tile;
}

// Draws into the tile the triangles every chunk binned to it (tile tileIndex), in chunk order, which
// is submission order.
void DrawBinnedTriangles(const std::vector<ChunkBins>& chunks, size_t tileIndex, const AlphaTest& alphaTest,
                         bool writeTriangle, bool countCoverage, KernelPath kernels, TileTarget& tile) {
  const auto rasterizeTile = kernels == KernelPath::kSimd ? RasterizeTileSimd : RasterizeTileScalar;
  size_t tileTriangles = 0;
  for (const ChunkBins& bins : chunks) tileTriangles += bins.tileStart[tileIndex + 1] - bins.tileStart[tileIndex];
  const bool smallTriangles = tileTriangles * kSmallTrianglePixels >= size_t(tile.width) * size_t(tile.height);
  for (const ChunkBins& bins : chunks) {
    const uint32_t begin = bins.tileStart[tileIndex], end = bins.tileStart[tileIndex + 1];
    if (begin == end) continue;
    const TileTriangles batch{
        bins.triangles.data(), bins.entries.data() + begin, end - begin, &alphaTest, writeTriangle, countCoverage,
        smallTriangles};
    rasterizeTile(batch, tile);
  }
}

// Copies the drawn tile into the target (its triangle indices where writeTriangle) and adds its
// coverage counts to `coverageCount`, if not null.
void CopyTileToTarget(const TileTarget& tile, bool writeTriangle, KernelPath kernels, VisibilityBuffer& target,
                      Plane<uint32_t>* coverageCount) {
  const auto copyTileOut = kernels == KernelPath::kSimd ? CopyTileOutSimd : CopyTileOutScalar;
  const auto copyOut = [&](const void* values, auto& image) {
    copyTileOut(tile, static_cast<const uint32_t*>(values),
                reinterpret_cast<uint8_t*>(image.MutableRow(size_t(tile.y0)) + tile.x0), image.bytes_per_row());
  };
  copyOut(tile.depth, target.depthKey);
  if (writeTriangle) copyOut(tile.triangle, target.triangle);
  if (coverageCount) {
    for (int y = 0; y < tile.height; ++y) {
      uint32_t* out = coverageCount->MutableRow(size_t(tile.y0 + y)) + tile.x0;
      for (int x = 0; x < tile.width; ++x) out[x] += tile.coverage[TilePixelIndex(x, y)];
    }
  }
}

RasterStats SumStats(const std::vector<ChunkBins>& chunks) {
  RasterStats stats;
  for (const ChunkBins& bins : chunks) {
    stats.trianglesIn += bins.stats.trianglesIn;
    stats.trianglesCulled += bins.stats.trianglesCulled;
    stats.trianglesClipped += bins.stats.trianglesClipped;
    stats.trianglesSetUp += bins.stats.trianglesSetUp;
    stats.binEntries += bins.stats.binEntries;
  }
  return stats;
}

}  // namespace

bool SetUpScreenTriangle(const SnappedVertex& s0, const SnappedVertex& s1, const SnappedVertex& s2, uint32_t triangle,
                         uint8_t flags, int width, int height, ScreenTriangle& t) {
  struct Vertex {
    int64_t x, y;
    double key;
  };
  Vertex v[3] = {{s0.x, s0.y, s0.key}, {s1.x, s1.y, s1.key}, {s2.x, s2.y, s2.key}};
  int64_t area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
  if (area2 == 0) return false;
  // Counter-clockwise front faces turn clockwise in y-down screen space, i.e. negative area.
  const bool backFacing = area2 > 0;
  if (backFacing && (flags & kTriangleCullBackFace)) return false;
  if (!backFacing) {
    std::swap(v[1], v[2]);
    area2 = -area2;
  }
  const int64_t minSx = std::min({v[0].x, v[1].x, v[2].x});
  const int64_t maxSx = std::max({v[0].x, v[1].x, v[2].x});
  const int64_t minSy = std::min({v[0].y, v[1].y, v[2].y});
  const int64_t maxSy = std::max({v[0].y, v[1].y, v[2].y});
  // Pixels whose centre sample px * 256 + 128 lies inside the snapped bounds.
  const int64_t minX = std::max<int64_t>(0, FloorDiv(minSx - kHalfPixel + kSubPixelScale - 1, kSubPixelScale));
  const int64_t maxX = std::min<int64_t>(width - 1, FloorDiv(maxSx - kHalfPixel, kSubPixelScale));
  const int64_t minY = std::max<int64_t>(0, FloorDiv(minSy - kHalfPixel + kSubPixelScale - 1, kSubPixelScale));
  const int64_t maxY = std::min<int64_t>(height - 1, FloorDiv(maxSy - kHalfPixel, kSubPixelScale));
  if (minX > maxX || minY > maxY) return false;
  t.minX = int16_t(minX);
  t.maxX = int16_t(maxX);
  t.minY = int16_t(minY);
  t.maxY = int16_t(maxY);
  // Inside the guard band |x|, |y| < 3 * 16384 * 256 (2^23.6): the vertices fit 32 bits.
  for (int i = 0; i < 3; ++i) {
    t.x[i] = int32_t(v[i].x);
    t.y[i] = int32_t(v[i].y);
  }
  t.edgesFit32Bits = true;
  for (int e = 0; e < 3; ++e) {
    const EdgeFunction edge = t.Edge(e);
    t.edgesFit32Bits = t.edgesFit32Bits && std::abs(edge.a) + std::abs(edge.b) <= kMaxEdgeSlopeFor32Bits;
  }
  // The depth key's plane in pixel units, through the snapped vertices: linear in screen space.
  const double x10 = double(v[1].x - v[0].x) / kSubPixelScale, y10 = double(v[1].y - v[0].y) / kSubPixelScale;
  const double x20 = double(v[2].x - v[0].x) / kSubPixelScale, y20 = double(v[2].y - v[0].y) / kSubPixelScale;
  const double k10 = v[1].key - v[0].key, k20 = v[2].key - v[0].key;
  const double det = double(area2) / double(kSubPixelScale * kSubPixelScale);
  t.keyDx = (k10 * y20 - k20 * y10) / det;
  t.keyDy = (k20 * x10 - k10 * x20) / det;
  const double x0 = double(v[0].x) / kSubPixelScale, y0 = double(v[0].y) / kSubPixelScale;
  t.keyAtOrigin = v[0].key + t.keyDx * (0.5 - x0) + t.keyDy * (0.5 - y0);
  t.triangle = triangle;
  t.flags = flags;
  return true;
}

ClipPlanes::ClipPlanes(int width, int height)
    : guardX(1.0 + 2.0 * kGuardBandPixels / double(width)), guardY(1.0 + 2.0 * kGuardBandPixels / double(height)) {}

void ProjectVerticesScalar(const glm::vec3* positions, size_t count, const glm::mat4& viewProjection, int width,
                           int height, ProjectedVertex* out) {
  const ClipPlanes planes(width, height);
  for (size_t i = 0; i < count; ++i) {
    const glm::dvec4 v(ClipPosition(positions[i], viewProjection));
    const std::array<double, ClipPlanes::kCount> distance = planes.Distances(v);
    int32_t outside = 0;
    for (int p = 0; p < ClipPlanes::kCount; ++p) outside |= int32_t(distance[p] >= 0.0 ? 0 : 1) << p;
    out[i] = outside != 0 ? ProjectedVertex{{outside, ProjectedVertex::kOutsideClipPlanes, 0.0}}
                          : ProjectedVertex{Snap(v, width, height)};
  }
}

size_t SetUpTrianglesScalar(const ProjectedVertex* projected, const uint32_t* indices, const uint8_t* flags,
                            uint8_t uniformFlags, uint32_t first, size_t count, int width, int height,
                            ScreenTriangle* out, TriangleSetUp* status) {
  size_t setUp = 0;
  for (size_t i = 0; i < count; ++i) {
    const uint32_t triangle = first + uint32_t(i);
    const uint32_t* index = indices + 3 * size_t(triangle);
    const ProjectedVertex& a = projected[index[0]];
    const ProjectedVertex& b = projected[index[1]];
    const ProjectedVertex& c = projected[index[2]];
    if (a.Outside() & b.Outside() & c.Outside()) {  // all three outside one plane
      status[i] = TriangleSetUp::kCulled;
    } else if ((a.Outside() | b.Outside() | c.Outside()) != 0) {
      status[i] = TriangleSetUp::kClip;
    } else {
      const bool kept = SetUpScreenTriangle(a.snapped, b.snapped, c.snapped, triangle,
                                            TriangleFlagsOf(flags, uniformFlags, triangle), width, height, out[setUp]);
      status[i] = kept ? TriangleSetUp::kSetUp : TriangleSetUp::kCulled;
      setUp += kept;
    }
  }
  return setUp;
}

void CopyTileOutScalar(const TileTarget& tile, const uint32_t* values, uint8_t* firstPixel, size_t rowBytes) {
  for (int y = 0; y < tile.height; ++y) {
    uint8_t* row = firstPixel + size_t(y) * rowBytes;
    for (int x = 0; x < tile.width; x += kRasterBlockSize) {
      const size_t count = size_t(std::min(kRasterBlockSize, tile.width - x));
      std::memcpy(row + size_t(x) * sizeof(uint32_t), values + TilePixelIndex(x, y), count * sizeof(uint32_t));
    }
  }
}

void RasterizeTileScalar(const TileTriangles& batch, TileTarget& tile) {
  ForEachTileTriangle(batch, [&](const ScreenTriangle& t, auto writeTriangle, auto countCoverage) {
    RasterizeInTile<writeTriangle, countCoverage>(t, *batch.alphaTest, tile);
  });
}

VisibilityBuffer MakeVisibilityBuffer(int width, int height, RasterOutput output) {
  VisibilityBuffer buffer;
  buffer.depthKey = MakePlane<float>(width, height, 0.0f);
  if (output == RasterOutput::kVisibility) buffer.triangle = MakePlane<uint32_t>(width, height, kNoTriangle);
  return buffer;
}

RasterStats Rasterize(const RasterInput& input, const ViewProjection& view, RasterOutput output,
                      VisibilityBuffer& target, Plane<uint32_t>* coverageCount, KernelPath kernels) {
  SSGI_CHECK_EQ(int(target.depthKey.xsize()), view.width);
  SSGI_CHECK_EQ(int(target.depthKey.ysize()), view.height);
  const bool writeTriangle = output == RasterOutput::kVisibility;
  if (writeTriangle) SSGI_CHECK_EQ(int(target.triangle.xsize()), view.width);
  const bool countCoverage = coverageCount != nullptr;

  // Written in full: not zeroed first (16 MB a frame for a million-triangle mesh).
  const auto projected = std::make_unique_for_overwrite<ProjectedVertex[]>(input.vertexCount);
  ProjectAllVertices(input, view, kernels, projected.get());
  const int tilesX = (view.width + kRasterTileSize - 1) / kRasterTileSize;
  const int tilesY = (view.height + kRasterTileSize - 1) / kRasterTileSize;
  const std::vector<ChunkBins> chunks = SetUpAndBin(input, view, projected.get(), kernels, tilesX, tilesY);
  ParallelFor("raster.tiles", size_t(tilesX) * size_t(tilesY), [&](size_t tileIndex) {
    TileTarget& tile = ClearedThreadTile(tileIndex, tilesX, view, writeTriangle, countCoverage);
    DrawBinnedTriangles(chunks, tileIndex, input.alphaTest, writeTriangle, countCoverage, kernels, tile);
    CopyTileToTarget(tile, writeTriangle, kernels, target, coverageCount);
  });
  return SumStats(chunks);
}

}  // namespace ssgi
