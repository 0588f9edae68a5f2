#include "passes/mlaa.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "core/color.h"
#include "core/edge_coverage.h"
#include "core/parallel.h"
#include "core/stopwatch.h"

namespace ssgi {

namespace {

// A run's end: the silhouette's height there, +1 (half a pixel toward the first side), -1 (toward
// the second) or 0, from whether the edge steps there to the first side's row (column) or the
// second's: an edge crosses the run's end on that side and the edge goes on from it, one row
// (column) over. A crossing edge without the edge going on is a corner or a T-junction of straight
// edges, which a stair step's silhouette would blur.
int EndHeight(bool stepsToFirstSide, bool stepsToSecondSide) {
  if (stepsToFirstSide == stepsToSecondSide) return 0;
  return stepsToFirstSide ? 1 : -1;
}

// The area numerator (in 1/(8 n)) under one half of a run's silhouette, the line from height 1/2 at the
// run's end to 0 at its middle n/2, over the pixel `k` pixels from that end: with a = 2k and
// b = min(2k + 2, n), the integral of (1/2)(1 - 2u/n) from a/2 to b/2 is (2 (b - a) n - (b^2 - a^2)) /
// (8 n). 0 beyond the middle.
uint64_t HalfRunArea(uint64_t n, uint64_t k) {
  const uint64_t a = 2 * k;
  if (a >= n) return 0;
  const uint64_t b = std::min(a + 2, n);
  return 2 * (b - a) * n - (b * b - a * a);
}

// Writes a run's weights: `store(k, codes)` for each of its n pixels.
template <class Store>
void WeighRun(uint32_t n, int startHeight, int endHeight, Store&& store) {
  if (startHeight == 0 && endHeight == 0) return;  // no step at either end: nothing to blend
  for (uint32_t k = 0; k < n; ++k) {
    uint32_t codes[2];
    MlaaRunWeights(n, k, startHeight, endHeight, codes);
    store(k, codes);
  }
}

}  // namespace

void MlaaLumaRowScalar(const float* const rgb[3], size_t width, float exposureScale, float* luma) {
  for (size_t x = 0; x < width; ++x) {
    const float y = (0.2126f * rgb[0][x] + 0.7152f * rgb[1][x]) + 0.0722f * rgb[2][x];
    const float t = SanitizeRadiance(y * exposureScale);
    luma[x] = std::sqrt(t / (1.0f + t));
  }
}

void MlaaEdgeRowScalar(const float* const rows[4], size_t width, float threshold, uint32_t* edges) {
  MlaaEdgePixelsScalar(rows, width, threshold, 0, width, edges);
}

void MlaaEdgePixelsScalar(const float* const rows[4], size_t width, float threshold, size_t begin, size_t end,
                          uint32_t* edges) {
  const float* upUp = rows[0];
  const float* up = rows[1];
  const float* row = rows[2];
  const float* down = rows[3];
  for (size_t x = begin; x < end; ++x) {
    const size_t left = x > 0 ? x - 1 : x, leftLeft = x > 1 ? x - 2 : left, right = x + 1 < width ? x + 1 : x;
    const float l = row[x];
    const float toLeft = std::abs(l - row[left]), toUp = std::abs(l - up[x]);
    const float toRight = std::abs(l - row[right]), toDown = std::abs(l - down[x]);
    const float leftToLeft = std::abs(row[left] - row[leftLeft]), upToUp = std::abs(up[x] - upUp[x]);
    const float largest =
        std::max(std::max(std::max(toLeft, toUp), std::max(toRight, toDown)), std::max(leftToLeft, upToUp));
    // SMAA's local contrast adaptation: a step next to a much larger one is part of that edge's
    // shading, not an edge of its own.
    const bool leftEdge = toLeft >= threshold && largest <= 2.0f * toLeft;
    const bool topEdge = toUp >= threshold && largest <= 2.0f * toUp;
    edges[x] = (leftEdge ? kMlaaLeftEdge : 0u) | (topEdge ? kMlaaTopEdge : 0u);
  }
}

size_t MlaaCoverageRowScalar(const uint32_t* weights, const uint32_t* below, size_t width, uint32_t* coverage) {
  return MlaaCoveragePixelsScalar(weights, below, width, 0, width, coverage);
}

size_t MlaaCoveragePixelsScalar(const uint32_t* weights, const uint32_t* below, size_t width, size_t begin, size_t end,
                                uint32_t* coverage) {
  size_t blended = 0;
  for (size_t x = begin; x < end; ++x) {
    const uint32_t left = (weights[x] >> 8) & 255u, right = x + 1 < width ? weights[x + 1] & 255u : 0u;
    const uint32_t up = weights[x] >> 24, down = (below[x] >> 16) & 255u;
    // One axis only, the one with the larger share (SMAA's neighbourhood blending): where a run meets
    // the short crossing edge at its end, both weigh the same corner of the silhouette. Each share is
    // at most 128, so the two kept sum to at most 256.
    const bool horizontal = std::max(left, right) > std::max(up, down);
    coverage[x] = horizontal ? EdgeCoverageWord(left, right, 0, 0) : EdgeCoverageWord(0, 0, up, down);
    blended += coverage[x] != 0;
  }
  return blended;
}

void MlaaRunWeights(uint32_t n, uint32_t k, int startHeight, int endHeight, uint32_t codes[2]) {
  uint64_t area[2] = {0, 0};  // numerators in 1/(8 n): the first side's, the second side's
  if (startHeight != 0) area[startHeight > 0 ? 0 : 1] += HalfRunArea(n, k);
  if (endHeight != 0) area[endHeight > 0 ? 0 : 1] += HalfRunArea(n, n - 1 - k);
  // round(256 area / (8 n)) = floor((64 area + n) / (2 n)).
  for (int side = 0; side < 2; ++side) codes[side] = uint32_t((64 * area[side] + n) / (2 * uint64_t(n)));
}

MlaaStats RunMlaa(const MlaaInputs& in, const MlaaParams& params, MlaaOutputs& out, KernelPath kernels) {
  Stopwatch stopwatch;
  const size_t width = in.image.c[0].xsize(), height = in.image.c[0].ysize();
  SSGI_CHECK(params.threshold > 0.0f);
  const auto resize = [&](auto& plane, auto fill) {
    if (plane.xsize() != width || plane.ysize() != height) plane = MakePlane(width, height, fill);
  };
  resize(out.luma, 0.0f);
  resize(out.edges, 0u);
  resize(out.weights, 0u);
  resize(out.coverage, 0u);
  const bool simd = kernels == KernelPath::kSimd;
  const float exposureScale = std::exp2(params.exposureEv);

  ParallelForRowBands("mlaa.luma", height, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const float* const rgb[3] = {in.image.c[0].ConstRow(y), in.image.c[1].ConstRow(y), in.image.c[2].ConstRow(y)};
      (simd ? MlaaLumaRowSimd : MlaaLumaRowScalar)(rgb, width, exposureScale, out.luma.MutableRow(y));
    }
  });

  std::vector<size_t> edgePixelsPerBand(RowBandCount(height), 0);
  ParallelForRowBands("mlaa.edges", height, [&](size_t band, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const size_t up = y > 0 ? y - 1 : y, upUp = y > 1 ? y - 2 : up, down = y + 1 < height ? y + 1 : y;
      const float* const rows[4] = {out.luma.ConstRow(upUp), out.luma.ConstRow(up), out.luma.ConstRow(y),
                                    out.luma.ConstRow(down)};
      uint32_t* edges = out.edges.MutableRow(y);
      (simd ? MlaaEdgeRowSimd : MlaaEdgeRowScalar)(rows, width, params.threshold, edges);
      edgePixelsPerBand[band] += size_t(std::count_if(edges, edges + width, [](uint32_t e) { return e != 0; }));
    }
  });

  // Horizontal edges (a pixel's top edge), followed along their row: bytes 2 and 3 of `weights`,
  // whose other bytes the vertical runs fill next.
  ParallelForRowBands("mlaa.rows", height, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      uint32_t* weights = out.weights.MutableRow(y);
      std::fill_n(weights, width, 0u);
      if (y == 0) continue;
      const uint32_t* above = out.edges.ConstRow(y - 1);
      const uint32_t* row = out.edges.ConstRow(y);
      const uint32_t* below = y + 1 < height ? out.edges.ConstRow(y + 1) : nullptr;
      // Whether an edge crosses the row's edge at the left border of pixel x.
      const auto crosses = [&](size_t x) { return ((above[x] | row[x]) & kMlaaLeftEdge) != 0; };
      // The height of a run's end at the left border of pixel x (0 < x < width), `beyond` the column
      // past the end (x at the run's end, x - 1 at its start): a step up is an edge crossing above
      // and the top edge of pixel (beyond, y - 1); a step down one crossing below and the top edge
      // of (beyond, y + 1).
      const auto endHeight = [&](size_t x, size_t beyond) {
        if (x == 0 || x >= width) return 0;
        const bool up = (above[x] & kMlaaLeftEdge) && (above[beyond] & kMlaaTopEdge);
        const bool down = (row[x] & kMlaaLeftEdge) && below && (below[beyond] & kMlaaTopEdge);
        return EndHeight(up, down);
      };
      for (size_t x = 0; x < width;) {
        if (!(row[x] & kMlaaTopEdge)) {
          ++x;
          continue;
        }
        const size_t start = x;
        do ++x;
        while (x < width && (row[x] & kMlaaTopEdge) && !crosses(x));
        WeighRun(uint32_t(x - start), endHeight(start, start - 1), endHeight(x, x),
                 [&](uint32_t k, const uint32_t codes[2]) { weights[start + k] = codes[0] << 16 | codes[1] << 24; });
      }
    }
  });

  // Vertical edges (a pixel's left edge), followed down their column from the row where the run
  // starts: bytes 0 and 1 of `weights`. Each run is written by the band of its first row alone.
  const auto edgeAt = [&](size_t x, size_t y) { return out.edges.ConstRow(y)[x]; };
  // Whether an edge crosses the column's edge x at the top border of row y.
  const auto crossed = [&](size_t x, size_t y) { return ((edgeAt(x - 1, y) | edgeAt(x, y)) & kMlaaTopEdge) != 0; };
  // The height of a run's end at the top border of row `boundary` (0 < boundary < height) in column
  // x, `beyond` the row past the end (the boundary's row at the run's end, the row above at its
  // start): a step left is an edge crossing on the left and the left edge of pixel (x - 1, beyond);
  // a step right one crossing on the right and the left edge of (x + 1, beyond).
  const auto endHeight = [&](size_t x, size_t boundary, size_t beyond) {
    if (boundary == 0 || boundary >= height) return 0;
    const bool left = (edgeAt(x - 1, boundary) & kMlaaTopEdge) && (edgeAt(x - 1, beyond) & kMlaaLeftEdge);
    const bool right = (edgeAt(x, boundary) & kMlaaTopEdge) && x + 1 < width && (edgeAt(x + 1, beyond) & kMlaaLeftEdge);
    return EndHeight(left, right);
  };
  ParallelForRowBands("mlaa.columns", height, [&](size_t, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const uint32_t* row = out.edges.ConstRow(y);
      const uint32_t* above = y > 0 ? out.edges.ConstRow(y - 1) : nullptr;
      for (size_t x = 1; x < width; ++x) {
        if (!(row[x] & kMlaaLeftEdge)) continue;
        if (above && (above[x] & kMlaaLeftEdge) && !crossed(x, y)) continue;  // not the run's first row
        size_t end = y + 1;
        while (end < height && (edgeAt(x, end) & kMlaaLeftEdge) && !crossed(x, end)) ++end;
        WeighRun(
            uint32_t(end - y), endHeight(x, y, y - 1), endHeight(x, end, end),
            [&](uint32_t k, const uint32_t codes[2]) { out.weights.MutableRow(y + k)[x] |= codes[0] | codes[1] << 8; });
      }
    }
  });

  std::vector<size_t> blendPixelsPerBand(RowBandCount(height), 0);
  const std::vector<uint32_t> noWeights(width, 0u);  // below the last row
  ParallelForRowBands("mlaa.coverage", height, [&](size_t band, size_t yBegin, size_t yEnd) {
    for (size_t y = yBegin; y < yEnd; ++y) {
      const uint32_t* below = y + 1 < height ? out.weights.ConstRow(y + 1) : noWeights.data();
      blendPixelsPerBand[band] += (simd ? MlaaCoverageRowSimd : MlaaCoverageRowScalar)(
          out.weights.ConstRow(y), below, width, out.coverage.MutableRow(y));
    }
  });

  MlaaStats stats;
  for (size_t n : edgePixelsPerBand) stats.edgePixels += n;
  for (size_t n : blendPixelsPerBand) stats.blendPixels += n;
  stats.ms = stopwatch.Lap();
  return stats;
}

}  // namespace ssgi
