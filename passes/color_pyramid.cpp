// Colour pyramid: driver and scalar kernels (docs/pipeline.md §Colour pyramid).
#include "passes/color_pyramid.h"

#include <algorithm>

#include "core/check.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

constexpr int kRadius = kColorPyramidRadius;

void ShapeLevels(size_t width, size_t height, std::vector<Plane3<float>>& levels) {
  const std::vector<PyramidSize> sizes = PyramidLevelSizes(width, height);
  levels.resize(sizes.size());
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (levels[k].c[0].xsize() != sizes[k].width || levels[k].c[0].ysize() != sizes[k].height)
      levels[k] = MakePlane3<float>(sizes[k].width, sizes[k].height, 0.0f);
  }
}

// NaN fails the comparison and becomes 0 with the negatives: one NaN would otherwise poison every
// texel its footprint reaches on every coarser level.
float Sanitize(float v) { return v > 0.0f ? std::min(v, kColorPyramidMaxRadiance) : 0.0f; }

// Clamp-to-edge: a zero outside the image would darken the borders of every level.
size_t ClampIndex(ptrdiff_t i, size_t size) {
  return size_t(std::clamp<ptrdiff_t>(i, 0, ptrdiff_t(size) - 1));
}

// Vertical taps of one row: taps[t] is the row t - kRadius rows away, clamped to the level.
void BlurRowVertical(const float* const* taps, size_t width, float* out) {
  std::fill(out, out + width, 0.0f);
  for (int t = 0; t < int(kColorPyramidWeights.size()); ++t) {
    const float* row = taps[t];
    for (size_t x = 0; x < width; ++x) out[x] += kColorPyramidWeights[t] * row[x];
  }
}

// How many level-0 texels each texel of the next level covers along one axis, from this level's.
// The 3-wide footprint of an odd level's last texel makes these unequal (67 -> 33: the last texel
// covers 3 columns, the others 2), and the difference compounds level after level.
std::vector<float> NextCoverage(const std::vector<float>& coverage, size_t nextSize) {
  std::vector<float> next(nextSize, 0.0f);
  for (size_t x = 0; x < nextSize; ++x) {
    for (size_t sx = 2 * x; sx <= PyramidFootprintEnd(x, nextSize, coverage.size()); ++sx)
      next[x] += coverage[sx];
  }
  return next;
}

}  // namespace

void ColorPyramidSanitizeRowScalar(const float* radiance, size_t width, float* level0) {
  for (size_t x = 0; x < width; ++x) level0[x] = Sanitize(radiance[x]);
}

// Taps summed in tap order (deterministic).
void ColorPyramidHorizontalRowScalar(const float* level, size_t width, float* blurred) {
  for (size_t x = 0; x < width; ++x) {
    float sum = 0.0f;
    for (int t = 0; t < int(kColorPyramidWeights.size()); ++t)
      sum += kColorPyramidWeights[t] * level[ClampIndex(ptrdiff_t(x) + t - kRadius, width)];
    blurred[x] = sum;
  }
}

// Vertical taps on the footprint's rows, then the footprint's mean weighted by the level-0 area each
// source texel covers, so every texel is the mean of its own level-0 area and the 1 x 1 level is the
// image's mean.
void ColorPyramidVerticalRowScalar(const float* const* horizontalRows, size_t footprintRows,
                                   const float* rowCoverage, const float* columnCoverage, size_t sourceWidth,
                                   size_t width, float* scratch, float* out) {
  for (size_t r = 0; r < footprintRows; ++r)
    BlurRowVertical(horizontalRows + r, sourceWidth, scratch + r * sourceWidth);
  for (size_t x = 0; x < width; ++x) {
    const size_t x1 = PyramidFootprintEnd(x, width, sourceWidth);
    float sum = 0.0f;
    float area = 0.0f;
    for (size_t r = 0; r < footprintRows; ++r) {
      for (size_t sx = 2 * x; sx <= x1; ++sx) {
        const float weight = rowCoverage[r] * columnCoverage[sx];
        sum += weight * scratch[r * sourceWidth + sx];
        area += weight;
      }
    }
    out[x] = sum / area;
  }
}

ColorPyramidStats RunColorPyramid(const Plane3<float>& radiance, ColorPyramid& out, KernelPath kernels) {
  const Stopwatch watch;
  const size_t width = radiance.c[0].xsize();
  const size_t height = radiance.c[0].ysize();
  SSGI_CHECK(width > 0 && height > 0);
  for (const Plane<float>& channel : radiance.c) {
    SSGI_CHECK_EQ(channel.xsize(), width);
    SSGI_CHECK_EQ(channel.ysize(), height);
  }
  ShapeLevels(width, height, out.levels);
  const bool simd = kernels == KernelPath::kSimd;
  const auto sanitizeRow = simd ? ColorPyramidSanitizeRowSimd : ColorPyramidSanitizeRowScalar;
  const auto horizontalRow = simd ? ColorPyramidHorizontalRowSimd : ColorPyramidHorizontalRowScalar;
  const auto verticalRow = simd ? ColorPyramidVerticalRowSimd : ColorPyramidVerticalRowScalar;

  ColorPyramidStats stats;
  ParallelFor("color_pyramid.sanitize", 3 * height, [&](size_t item) {
    const size_t c = item / height;
    const size_t y = item % height;
    sanitizeRow(radiance.c[c].ConstRow(y), width, out.levels[0].c[c].MutableRow(y));
  });
  stats.texels += width * height;

  // Level k's horizontal blur, in planes of level 0's size reused by every level (each level uses
  // its top-left corner).
  Plane3<float> horizontal = MakePlane3<float>(width, height, 0.0f);
  // Level-0 texel counts covered per column and per row of level k (exact in float below 2^24).
  std::vector<float> columnCoverage(width, 1.0f);
  std::vector<float> rowCoverage(height, 1.0f);
  for (size_t k = 1; k < out.levels.size(); ++k) {
    const Plane3<float>& source = out.levels[k - 1];
    Plane3<float>& destination = out.levels[k];
    const size_t sourceWidth = source.c[0].xsize();
    const size_t sourceHeight = source.c[0].ysize();
    ParallelFor("color_pyramid.horizontal", 3 * sourceHeight, [&](size_t item) {
      const size_t c = item / sourceHeight;
      const size_t y = item % sourceHeight;
      horizontalRow(source.c[c].ConstRow(y), sourceWidth, horizontal.c[c].MutableRow(y));
    });
    const size_t destinationHeight = destination.c[0].ysize();
    ParallelFor("color_pyramid.vertical", 3 * destinationHeight, [&](size_t item) {
      const size_t c = item / destinationHeight;
      const size_t y = item % destinationHeight;
      const size_t footprintRows = PyramidFootprintEnd(y, destinationHeight, sourceHeight) - 2 * y + 1;
      const float* horizontalRows[kMaxPyramidFootprint + 2 * kRadius];
      for (size_t i = 0; i < footprintRows + 2 * kRadius; ++i)
        horizontalRows[i] = horizontal.c[c].ConstRow(ClampIndex(ptrdiff_t(2 * y + i) - kRadius, sourceHeight));
      std::vector<float> scratch(footprintRows * sourceWidth);
      verticalRow(horizontalRows, footprintRows, rowCoverage.data() + 2 * y, columnCoverage.data(), sourceWidth,
                  destination.c[c].xsize(), scratch.data(), destination.c[c].MutableRow(y));
    });
    columnCoverage = NextCoverage(columnCoverage, destination.c[0].xsize());
    rowCoverage = NextCoverage(rowCoverage, destinationHeight);
    stats.texels += destination.c[0].xsize() * destinationHeight;
  }
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace ssgi
