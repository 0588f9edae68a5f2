// Colour pyramid: driver and scalar kernels (docs/pipeline.md §Colour pyramid).
#include "passes/color_pyramid.h"

#include <algorithm>

#include "core/check.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

constexpr int kRadius = int(kColorPyramidWeights.size()) / 2;

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

// Horizontal taps of one row of width `width`, summed in tap order (deterministic).
void BlurRowHorizontal(const float* in, size_t width, float* out) {
  for (size_t x = 0; x < width; ++x) {
    float sum = 0.0f;
    for (int t = 0; t < int(kColorPyramidWeights.size()); ++t)
      sum += kColorPyramidWeights[t] * in[ClampIndex(ptrdiff_t(x) + t - kRadius, width)];
    out[x] = sum;
  }
}

// Vertical taps at row y of a plane whose first `width` columns and `height` rows are the level.
void BlurRowVertical(const Plane<float>& in, size_t width, size_t height, size_t y, float* out) {
  std::fill(out, out + width, 0.0f);
  for (int t = 0; t < int(kColorPyramidWeights.size()); ++t) {
    const float* row = in.ConstRow(ClampIndex(ptrdiff_t(y) + t - kRadius, height));
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

// One row of level k + 1 from the horizontally blurred level k (`horizontal`, level k's size in its
// first columns / rows): vertical taps on the footprint's rows, then the footprint's mean weighted
// by the level-0 area each source texel covers (columnCoverage, rowCoverage: level k's), so every
// texel is the mean of its own level-0 area and the 1 x 1 level is the image's mean.
void DecimateRow(const Plane<float>& horizontal, const std::vector<float>& columnCoverage,
                 const std::vector<float>& rowCoverage, size_t y, Plane<float>& destination,
                 std::vector<float>& blurred) {
  const size_t sourceWidth = columnCoverage.size();
  const size_t sourceHeight = rowCoverage.size();
  const size_t width = destination.xsize();
  const size_t y1 = PyramidFootprintEnd(y, destination.ysize(), sourceHeight);
  const size_t rows = y1 - 2 * y + 1;
  blurred.resize(rows * sourceWidth);
  for (size_t r = 0; r < rows; ++r)
    BlurRowVertical(horizontal, sourceWidth, sourceHeight, 2 * y + r, blurred.data() + r * sourceWidth);
  float* out = destination.MutableRow(y);
  for (size_t x = 0; x < width; ++x) {
    const size_t x1 = PyramidFootprintEnd(x, width, sourceWidth);
    float sum = 0.0f;
    float area = 0.0f;
    for (size_t r = 0; r < rows; ++r) {
      for (size_t sx = 2 * x; sx <= x1; ++sx) {
        const float weight = rowCoverage[2 * y + r] * columnCoverage[sx];
        sum += weight * blurred[r * sourceWidth + sx];
        area += weight;
      }
    }
    out[x] = sum / area;
  }
}

}  // namespace

ColorPyramidStats RunColorPyramid(const Plane3<float>& radiance, ColorPyramid& out) {
  const Stopwatch watch;
  const size_t width = radiance.c[0].xsize();
  const size_t height = radiance.c[0].ysize();
  SSGI_CHECK(width > 0 && height > 0);
  for (const Plane<float>& channel : radiance.c) {
    SSGI_CHECK_EQ(channel.xsize(), width);
    SSGI_CHECK_EQ(channel.ysize(), height);
  }
  ShapeLevels(width, height, out.levels);

  ColorPyramidStats stats;
  ParallelFor("color_pyramid.sanitize", 3 * height, [&](size_t item) {
    const size_t c = item / height;
    const size_t y = item % height;
    const float* in = radiance.c[c].ConstRow(y);
    float* level0 = out.levels[0].c[c].MutableRow(y);
    for (size_t x = 0; x < width; ++x) level0[x] = Sanitize(in[x]);
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
      BlurRowHorizontal(source.c[c].ConstRow(y), sourceWidth, horizontal.c[c].MutableRow(y));
    });
    const size_t destinationHeight = destination.c[0].ysize();
    ParallelFor("color_pyramid.vertical", 3 * destinationHeight, [&](size_t item) {
      const size_t c = item / destinationHeight;
      std::vector<float> blurred;
      DecimateRow(horizontal.c[c], columnCoverage, rowCoverage, item % destinationHeight, destination.c[c],
                  blurred);
    });
    columnCoverage = NextCoverage(columnCoverage, destination.c[0].xsize());
    rowCoverage = NextCoverage(rowCoverage, destinationHeight);
    stats.texels += destination.c[0].xsize() * destinationHeight;
  }
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace ssgi
