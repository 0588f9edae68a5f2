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

// Clamp-to-edge: a zero outside the image would darken the borders of every level.
size_t ClampIndex(ptrdiff_t i, size_t size) {
  return size_t(std::clamp<ptrdiff_t>(i, 0, ptrdiff_t(size) - 1));
}

// Vertical taps of one row: taps[t] is the row t - kRadius rows away, clamped to the level; summed in
// tap order, as the horizontal blur sums its taps.
void BlurRowVertical(const float* const* taps, size_t width, float* out) {
  for (size_t x = 0; x < width; ++x) {
    float sum = 0.0f;
    for (size_t t = 0; t < kColorPyramidWeights.size(); ++t) sum += kColorPyramidWeights[t] * taps[t][x];
    out[x] = sum;
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

// The vertical taps of a row of the next level read at most this many rows of the horizontal blur:
// a 3-row footprint and the taps' reach on either side.
constexpr size_t kTapRows = kMaxPyramidFootprint + 2 * kRadius;

// Rows of the next level per parallel item. Fewer rows per band blur more rows twice (the 3 above
// and the 3 below a band, which its neighbours blur too). For level 1, a band's level-0 rows of one
// channel (twice as many) are sanitised in one sweep, then read again by the horizontal blur: at up
// to 256 KiB (32 rows of a 1024-wide level 0, 16 of a 2048-wide one) they stay in a 1 MiB L2 cache
// beside the radiance the sweep reads.
size_t BandRows(size_t sourceWidth) {
  constexpr size_t kBandBytes = size_t(256) << 10;
  return std::clamp<size_t>(kBandBytes / (2 * sourceWidth * sizeof(float)), 8, 32);
}

// One item's working rows, for levels up to `width` texels wide.
struct BandScratch {
  explicit BandScratch(size_t width)
      : ring(MakePlane<float>(width, kTapRows, 0.0f)),
        sanitized(MakePlane<float>(width, 2 * kRadius, 0.0f)),
        vertical(MakePlane<float>(kMaxPyramidFootprint * width, 1, 0.0f)) {}
  Plane<float> ring;       // row sy of the horizontal blur in row sy % kTapRows: the taps of one output row
  Plane<float> sanitized;  // the level-0 rows above and below the band, which other bands write
  Plane<float> vertical;   // the vertical kernel's scratch
};

// The first source texel the taps of the footprint starting at source texel `first` reach, along one
// axis: `first` less the taps' radius, within the level.
size_t FirstTap(size_t first) { return first > size_t(kRadius) ? first - kRadius : 0; }

// What one parallel item makes of a level: rows [yBegin, yEnd), columns [xBegin, xEnd) (empty when
// yBegin == yEnd).
struct BandJob {
  size_t yBegin = 0, yEnd = 0, xBegin = 0, xEnd = 0;
};

// The columns of level k - 1's rows the horizontal blur makes for level k's columns [xBegin, xEnd):
// the footprints' columns and the taps' reach, within the level. The blur of such a part of a row
// clamps at the part's ends, so only the footprints' columns are exact (their taps lie inside), or
// the level's own end is the part's.
void HorizontalColumns(size_t xBegin, size_t xEnd, size_t width, size_t sourceWidth, size_t& first, size_t& last) {
  first = FirstTap(2 * xBegin);
  last = std::min(sourceWidth - 1, PyramidFootprintEnd(xEnd - 1, width, sourceWidth) + kRadius);
}

// Every level's items, as BuildPyramid runs them: bands of BandRows rows while a level has more rows
// than that, then the rest of the levels whole, one item per channel. Without needs each item makes
// its whole band; with them, the rows and columns of its band that the needs name, and the needs of
// the level below grow by what those read (levels made coarsest first, so a level's needs are
// complete before its own items are planned).
std::vector<std::vector<BandJob>> PlanJobs(const std::vector<Plane3<float>>& levels, const ColorPyramidNeeds* needs,
                                          size_t& firstSmallLevel) {
  const size_t count = levels.size();
  const auto width = [&](size_t k) { return levels[k].c[0].xsize(); };
  const auto height = [&](size_t k) { return levels[k].c[0].ysize(); };
  firstSmallLevel = count;
  for (size_t k = 1; k < count; ++k) {
    if (height(k) <= BandRows(width(k - 1))) {
      firstSmallLevel = k;
      break;
    }
  }
  std::vector<std::vector<BandJob>> jobs(count);
  std::vector<std::vector<ColumnSpan>> need;
  if (needs) {
    SSGI_CHECK_EQ(needs->rows.size(), count);
    need = needs->rows;
    for (size_t k = 1; k < count; ++k) SSGI_CHECK_EQ(need[k].size(), height(k));
  }
  for (size_t k = count; k-- > 1;) {
    const size_t rows = height(k);
    const size_t bandRows = k < firstSmallLevel ? BandRows(width(k - 1)) : rows;
    for (size_t yBegin = 0; yBegin < rows; yBegin += bandRows) {
      const size_t yEnd = std::min(rows, yBegin + bandRows);
      BandJob job{yBegin, yEnd, 0, width(k)};
      if (needs) {
        ColumnSpan columns;
        job = {};
        for (size_t y = yBegin; y < yEnd; ++y) {
          if (need[k][y].Empty()) continue;
          if (columns.Empty()) job.yBegin = y;
          job.yEnd = y + 1;
          columns.Add(need[k][y].begin, need[k][y].end - 1);
        }
        job.xBegin = size_t(std::clamp(columns.begin, 0, int(width(k))));
        job.xEnd = size_t(std::clamp(columns.end, 0, int(width(k))));
        if (columns.Empty() || job.xBegin >= job.xEnd) job = {};
        if (job.yBegin < job.yEnd && k > 1) {
          size_t first = 0, last = 0;
          HorizontalColumns(job.xBegin, job.xEnd, width(k), width(k - 1), first, last);
          const size_t firstRow = FirstTap(2 * job.yBegin);
          const size_t lastRow =
              std::min(height(k - 1) - 1, PyramidFootprintEnd(job.yEnd - 1, rows, height(k - 1)) + kRadius);
          for (size_t sy = firstRow; sy <= lastRow; ++sy) need[k - 1][sy].Add(int(first), int(last));
        }
      }
      jobs[k].push_back(job);
    }
  }
  return jobs;
}

}  // namespace

void ColorPyramidSanitizeRowScalar(const float* radiance, size_t width, float* level0) {
  // NaN becomes 0 with the negatives: one NaN would otherwise poison every texel its footprint
  // reaches on every coarser level.
  for (size_t x = 0; x < width; ++x) level0[x] = SanitizeRadiance(radiance[x]);
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

namespace {

// radiance: the image to sanitise into level 0, or nullptr where out.levels[0] already holds it;
// needs: what to make of levels 1 and up (nullptr: all of them).
ColorPyramidStats BuildPyramid(const Plane3<float>* radiance, ColorPyramid& out, KernelPath kernels,
                               const ColorPyramidNeeds* needs) {
  SSGI_CHECK(!(radiance && needs));  // a sanitised level 0 is always made whole
  const Stopwatch watch;
  SSGI_CHECK(radiance || !out.levels.empty());
  const Plane3<float>& input = radiance ? *radiance : out.levels[0];
  const size_t width = input.c[0].xsize();
  const size_t height = input.c[0].ysize();
  SSGI_CHECK(width > 0 && height > 0);
  for (const Plane<float>& channel : input.c) {
    SSGI_CHECK_EQ(channel.xsize(), width);
    SSGI_CHECK_EQ(channel.ysize(), height);
  }
  ShapeLevels(width, height, out.levels);  // keeps a level 0 of the right size
  const size_t levels = out.levels.size();
  const bool simd = kernels == KernelPath::kSimd;
  const auto sanitizeRow = simd ? ColorPyramidSanitizeRowSimd : ColorPyramidSanitizeRowScalar;
  const auto horizontalRow = simd ? ColorPyramidHorizontalRowSimd : ColorPyramidHorizontalRowScalar;
  const auto verticalRow = simd ? ColorPyramidVerticalRowSimd : ColorPyramidVerticalRowScalar;

  // Level-0 texel counts covered per column and per row of each level (exact in float below 2^24).
  std::vector<std::vector<float>> columnCoverage{std::vector<float>(width, 1.0f)};
  std::vector<std::vector<float>> rowCoverage{std::vector<float>(height, 1.0f)};
  for (size_t k = 1; k < levels; ++k) {
    columnCoverage.push_back(NextCoverage(columnCoverage.back(), out.levels[k].c[0].xsize()));
    rowCoverage.push_back(NextCoverage(rowCoverage.back(), out.levels[k].c[0].ysize()));
  }

  // Rows [yBegin, yEnd) of channel c of level k >= 1. Level k - 1's horizontal blur is made row by
  // row, in order, into the scratch's ring, just before the first vertical taps that read it: the
  // taps of consecutive rows overlap in all but two rows, so a band blurs each row of its taps once
  // and the blur never goes to memory.
  // Columns [xBegin, xEnd) of the rows: the kernels run on that part of each row as on a whole row
  // (each texel is made by the same operations wherever its row starts), the horizontal blur on the
  // columns HorizontalColumns gives.
  const auto makeRows = [&](size_t c, size_t k, const BandJob& job, BandScratch& scratch) {
    const size_t yBegin = job.yBegin, yEnd = job.yEnd, xBegin = job.xBegin, xEnd = job.xEnd;
    const Plane<float>& source = out.levels[k - 1].c[c];
    Plane<float>& destination = out.levels[k].c[c];
    const size_t sourceWidth = source.xsize();
    const size_t sourceHeight = source.ysize();
    size_t firstColumn = 0, lastColumn = 0;
    HorizontalColumns(xBegin, xEnd, destination.xsize(), sourceWidth, firstColumn, lastColumn);
    // The part's footprints: up to the source's end where the part ends the row.
    const size_t partSourceWidth = xEnd == destination.xsize() ? sourceWidth - 2 * xBegin : 2 * (xEnd - xBegin);
    const size_t firstTap = FirstTap(2 * yBegin);
    const size_t lastTap = std::min(sourceHeight - 1, 2 * yEnd + kRadius - 1);
    // Level 1's source, level 0, is sanitised here, in one sweep over the band's taps before any
    // blur: streamed in one go, the reads keep the memory busy, where row by row between blurs each
    // row would wait for memory on its own. The band writes the level-0 rows of its own footprints
    // and sanitises again, into scratch, the rows of its neighbours' footprints that its taps reach.
    const size_t ownedEnd = yEnd == destination.ysize() ? sourceHeight : 2 * yEnd;
    const auto levelZeroRow = [&](size_t sy) {
      if (!radiance) return out.levels[0].c[c].MutableRow(sy);  // given: read only
      if (sy < 2 * yBegin) return scratch.sanitized.MutableRow(sy - firstTap);
      if (sy >= ownedEnd) return scratch.sanitized.MutableRow(kRadius + sy - ownedEnd);
      return out.levels[0].c[c].MutableRow(sy);
    };
    if (k == 1 && radiance) {
      for (size_t sy = firstTap; sy <= lastTap; ++sy)
        sanitizeRow(radiance->c[c].ConstRow(sy), sourceWidth, levelZeroRow(sy));
    }
    const auto sourceRow = [&](size_t sy) -> const float* { return k == 1 ? levelZeroRow(sy) : source.ConstRow(sy); };
    size_t nextBlurred = firstTap;
    for (size_t y = yBegin; y < yEnd; ++y) {
      const size_t footprintRows = PyramidFootprintEnd(y, destination.ysize(), sourceHeight) - 2 * y + 1;
      const size_t rowLastTap = std::min(sourceHeight - 1, 2 * y + footprintRows - 1 + kRadius);
      for (; nextBlurred <= rowLastTap; ++nextBlurred) {
        horizontalRow(sourceRow(nextBlurred) + firstColumn, lastColumn - firstColumn + 1,
                      scratch.ring.MutableRow(nextBlurred % kTapRows) + firstColumn);
      }
      const float* horizontalRows[kTapRows];
      for (size_t i = 0; i < footprintRows + 2 * kRadius; ++i) {
        horizontalRows[i] =
            scratch.ring.ConstRow(ClampIndex(ptrdiff_t(2 * y + i) - kRadius, sourceHeight) % kTapRows) + 2 * xBegin;
      }
      verticalRow(horizontalRows, footprintRows, rowCoverage[k - 1].data() + 2 * y,
                  columnCoverage[k - 1].data() + 2 * xBegin, partSourceWidth, xEnd - xBegin,
                  scratch.vertical.MutableRow(0), destination.MutableRow(y) + xBegin);
    }
  };

  // Levels in sequence (each reads the previous), by bands of rows with all three channels.
  size_t firstSmallLevel = levels;
  const std::vector<std::vector<BandJob>> jobs = PlanJobs(out.levels, needs, firstSmallLevel);
  size_t texels = 0;
  for (size_t k = 1; k < levels; ++k) {
    for (const BandJob& job : jobs[k]) texels += (job.yEnd - job.yBegin) * (job.xEnd - job.xBegin);
  }
  for (size_t k = 1; k < firstSmallLevel; ++k) {
    ParallelFor("color_pyramid.level", jobs[k].size(), [&](size_t band) {
      const BandJob& job = jobs[k][band];
      if (job.yBegin == job.yEnd) return;  // (only with needs, so level 0 is already sanitised)
      BandScratch scratch(out.levels[k - 1].c[0].xsize());
      for (size_t c = 0; c < 3; ++c) makeRows(c, k, job, scratch);
    });
  }
  // The levels of one band or less: each channel makes all of them in one item, as a parallel region
  // per level would cost more than their work.
  if (firstSmallLevel < levels) {
    ParallelFor("color_pyramid.small_levels", 3, [&](size_t c) {
      BandScratch scratch(out.levels[firstSmallLevel - 1].c[0].xsize());
      for (size_t j = firstSmallLevel; j < levels; ++j) {
        if (jobs[j][0].yBegin < jobs[j][0].yEnd) makeRows(c, j, jobs[j][0], scratch);
      }
    });
  }
  // A 1 x 1 image has no level 1, in whose sweep level 0 is otherwise sanitised.
  if (levels == 1 && radiance) {
    for (size_t c = 0; c < 3; ++c) sanitizeRow(radiance->c[c].ConstRow(0), width, out.levels[0].c[c].MutableRow(0));
  }

  ColorPyramidStats stats;
  stats.texels = width * height + texels;
  stats.ms = watch.Milliseconds();
  return stats;
}

}  // namespace

ColorPyramidStats RunColorPyramid(const Plane3<float>& radiance, ColorPyramid& out, KernelPath kernels) {
  return BuildPyramid(&radiance, out, kernels, nullptr);
}

ColorPyramidStats RunColorPyramidOnLevelZero(ColorPyramid& pyramid, KernelPath kernels,
                                             const ColorPyramidNeeds* needs) {
  return BuildPyramid(nullptr, pyramid, kernels, needs);
}

}  // namespace ssgi
