// Hi-Z pyramid: driver and scalar kernels (docs/pipeline.md §Hi-Z pyramid).
#include "passes/hiz.h"

#include <algorithm>

#include "core/check.h"
#include "core/gbuffer.h"
#include "core/parallel.h"
#include "core/pyramid.h"
#include "core/stopwatch.h"

namespace ssgi {
namespace {

// Makes `levels` hold planes of the pyramid sizes for a width x height level 0, keeping planes
// whose size already matches (a pass run every frame then allocates nothing).
void ShapeLevels(size_t width, size_t height, std::vector<Plane<float>>& levels) {
  const std::vector<PyramidSize> sizes = PyramidLevelSizes(width, height);
  levels.resize(sizes.size());
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (levels[k].xsize() != sizes[k].width || levels[k].ysize() != sizes[k].height)
      levels[k] = MakePlane<float>(sizes[k].width, sizes[k].height, 0.0f);
  }
}

// Levels per parallel region: a band of the first region is 16 rows of level 0 (kRowsPerBand,
// core/parallel.h) and the levels 1..4 they make.
constexpr size_t kLevelsPerRegion = 5;
// A region of levels from one this small (the last two of a 1024 or 2048 image) is microseconds of
// downsampling, less than waking a worker for it, so it is made inline.
constexpr size_t kTexelsMadeInline = size_t(128) * 128;

}  // namespace

// 1/(+inf) is exactly 0, so background needs no branch.
void HiZInverseDepthRowScalar(const uint32_t* depthWord, size_t width, float* inverseDepth) {
  for (size_t x = 0; x < width; ++x) inverseDepth[x] = 1.0f / UnpackDepth(depthWord[x]);
}

void HiZDownsampleRowScalar(const float* const* sourceRows, size_t footprintRows, size_t sourceWidth,
                            size_t width, float* closestRow) {
  for (size_t x = 0; x < width; ++x) {
    const size_t x1 = PyramidFootprintEnd(x, width, sourceWidth);
    float closest = 0.0f;
    for (size_t r = 0; r < footprintRows; ++r) {
      const float* row = sourceRows[r];
      for (size_t sx = 2 * x; sx <= x1; ++sx) closest = std::max(closest, row[sx]);
    }
    closestRow[x] = closest;
  }
}

HiZStats RunHiZ(const Plane<uint32_t>& depthWord, HiZ& out, KernelPath kernels) {
  const Stopwatch watch;
  const size_t width = depthWord.xsize();
  const size_t height = depthWord.ysize();
  SSGI_CHECK(width > 0 && height > 0);
  ShapeLevels(width, height, out.levels);
  const bool simd = kernels == KernelPath::kSimd;
  const auto inverseDepthRow = simd ? HiZInverseDepthRowSimd : HiZInverseDepthRowScalar;
  const auto downsampleRow = simd ? HiZDownsampleRowSimd : HiZDownsampleRowScalar;
  const auto makeRow = [&](size_t k, size_t y) {
    if (k == 0) return inverseDepthRow(depthWord.ConstRow(y), width, out.levels[0].MutableRow(y));
    const Plane<float>& source = out.levels[k - 1];
    Plane<float>& level = out.levels[k];
    const size_t footprintRows = PyramidFootprintEnd(y, level.ysize(), source.ysize()) - 2 * y + 1;
    const float* sourceRows[kMaxPyramidFootprint];
    for (size_t r = 0; r < footprintRows; ++r) sourceRows[r] = source.ConstRow(2 * y + r);
    downsampleRow(sourceRows, footprintRows, source.xsize(), level.xsize(), level.MutableRow(y));
  };

  // Levels first..last in one parallel region, band by band: a band is one row of level `last` and
  // the 2^(last - k) rows of each level k above it that the row covers (the last band also the rows
  // past a whole number of bands: the 3-row footprints of odd heights). Past level `first`, a band
  // reads only rows it has just written, from cache, and the small levels need no region of their
  // own. The bands depend only on the level sizes.
  HiZStats stats;
  const size_t levels = out.levels.size();
  for (size_t first = 0; first < levels;) {
    const size_t last = std::min(levels - 1, first + kLevelsPerRegion - 1);
    const size_t bands = out.levels[last].ysize();
    const auto makeBand = [&](size_t band) {
      for (size_t k = first; k <= last; ++k) {
        const size_t shift = last - k;
        const size_t yEnd = band + 1 == bands ? out.levels[k].ysize() : (band + 1) << shift;
        for (size_t y = band << shift; y < yEnd; ++y) makeRow(k, y);
      }
    };
    // A region this small takes less time than waking a worker: the calling thread makes it.
    if (out.levels[first].xsize() * out.levels[first].ysize() <= kTexelsMadeInline) {
      for (size_t band = 0; band < bands; ++band) makeBand(band);
    } else {
      ParallelFor("hiz.levels", bands, makeBand);
    }
    for (size_t k = first; k <= last; ++k) stats.texels += out.levels[k].xsize() * out.levels[k].ysize();
    first = last + 1;
  }
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace ssgi
