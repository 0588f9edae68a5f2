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

// One row of level 0: 1/d. 1/(+inf) is exactly 0, so background needs no branch.
void InverseDepthRow(const uint32_t* depth, size_t width, float* out) {
  for (size_t x = 0; x < width; ++x) out[x] = 1.0f / UnpackDepth(depth[x]);
}

// One row of level k + 1: the max over each texel's footprint in level k (2x2, or 3 wide / tall at
// an odd source's last column / row).
void DownsampleRow(const Plane<float>& source, size_t y, Plane<float>& destination) {
  const size_t width = destination.xsize();
  const size_t y1 = PyramidFootprintEnd(y, destination.ysize(), source.ysize());
  float* out = destination.MutableRow(y);
  for (size_t x = 0; x < width; ++x) {
    const size_t x1 = PyramidFootprintEnd(x, width, source.xsize());
    float closest = 0.0f;
    for (size_t sy = 2 * y; sy <= y1; ++sy) {
      const float* row = source.ConstRow(sy);
      for (size_t sx = 2 * x; sx <= x1; ++sx) closest = std::max(closest, row[sx]);
    }
    out[x] = closest;
  }
}

}  // namespace

HiZStats RunHiZ(const Plane<uint32_t>& depthWord, HiZ& out) {
  const Stopwatch watch;
  const size_t width = depthWord.xsize();
  const size_t height = depthWord.ysize();
  SSGI_CHECK(width > 0 && height > 0);
  ShapeLevels(width, height, out.levels);

  HiZStats stats;
  ParallelFor("hiz.level0", height, [&](size_t y) {
    InverseDepthRow(depthWord.ConstRow(y), width, out.levels[0].MutableRow(y));
  });
  stats.texels += width * height;
  // Levels are sequential (each reads the previous); rows of one level are independent.
  for (size_t k = 1; k < out.levels.size(); ++k) {
    Plane<float>& level = out.levels[k];
    ParallelFor("hiz.downsample", level.ysize(), [&](size_t y) { DownsampleRow(out.levels[k - 1], y, level); });
    stats.texels += level.xsize() * level.ysize();
  }
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace ssgi
