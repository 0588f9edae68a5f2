// Colour pyramid (docs/design.md §6; docs/pipeline.md §Colour pyramid): the direct-light image
// pre-convolved level by level, so the cone trace of Uludag (GPU Pro 5, "Hi-Z Screen-Space
// Cone-Traced Reflections") reads a blurred radiance whose footprint matches each cone circle with a
// single fetch. Level sizes equal the Hi-Z's (PyramidLevelSizes, core/pyramid.h), so one level index
// addresses both.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "core/color.h"
#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

// Uludag's separable 7-tap Gaussian (0.001, 0.028, 0.233, 0.474, 0.233, 0.028, 0.001) sums to 0.998;
// divided by that sum so a constant image stays constant and the pyramid neither gains nor loses
// energy level after level.
inline constexpr std::array<float, 7> kColorPyramidWeights = {
    float(0.001 / 0.998), float(0.028 / 0.998), float(0.233 / 0.998), float(0.474 / 0.998),
    float(0.233 / 0.998), float(0.028 / 0.998), float(0.001 / 0.998)};
// How far the taps reach on either side of the centre texel.
inline constexpr int kColorPyramidRadius = int(kColorPyramidWeights.size()) / 2;

struct ColorPyramid {
  // Linear RGB radiance, finite, in [0, kMaxRadiance]. levels[0]: the input's size, the input
  // sanitised (SanitizeRadiance: NaN and negatives -> 0, values above the cap and +inf -> the cap);
  // levels[k + 1]: PyramidHalvedSize of levels[k] on each axis, down to 1 x 1.
  std::vector<Plane3<float>> levels;
};

struct ColorPyramidStats {
  double ms = 0;
  size_t texels = 0;  // RGB texels written over all levels
};

// A reader's texels of levels 1 and up: per level, per row, the columns [begin, end) it reads (an
// empty span, begin >= end, where it reads none of the row).
struct ColumnSpan {
  int begin = 0, end = 0;
  bool Empty() const { return begin >= end; }
  void Add(int first, int last) {  // columns first .. last, inclusive
    if (Empty()) *this = {first, last + 1};
    else *this = {std::min(begin, first), std::max(end, last + 1)};
  }
};
struct ColorPyramidNeeds {
  std::vector<std::vector<ColumnSpan>> rows;  // rows[k][y] for every level k (level 0's unused)
};

// radiance: linear RGB (the direct-light image), any values (non-finite and negative sanitised).
// Level k + 1 texel (x, y) = the mean, over its Hi-Z footprint in level k (2x2; 3 wide / tall at an
// odd level's last column / row), of level k blurred by kColorPyramidWeights horizontally then
// vertically with clamp-to-edge addressing; each footprint texel weighted by the level-0 area it
// covers, so a texel is the mean of its own level-0 area at every size. Reuses out's planes when their sizes already match.
// kernels: which definition of the row kernels runs (the same bytes either way).
ColorPyramidStats RunColorPyramid(const Plane3<float>& radiance, ColorPyramid& out,
                                  KernelPath kernels = KernelPath::kSimd);

// The same pyramid built on a level 0 the caller has put in pyramid.levels[0] (moved in, not
// copied: the frame's memory-saving mode hands over the direct-light image): levels 1 and up are
// made from it as it is. It must already be sanitised, as the direct-light pass writes it; the
// bytes then equal RunColorPyramid's. With `needs`, only what they name is made, and what those
// texels are made from: every texel `needs` names holds RunColorPyramid's bytes, and the others of
// levels 1 and up hold anything (the frame's reader, the cone trace, reads none of them).
ColorPyramidStats RunColorPyramidOnLevelZero(ColorPyramid& pyramid, KernelPath kernels = KernelPath::kSimd,
                                             const ColorPyramidNeeds* needs = nullptr);

// The colour pyramid's row kernels, one channel row per call: the scalar definitions
// (color_pyramid.cpp) and their Highway twins (color_pyramid_simd.cpp), equal bit for bit on every
// SIMD target.
// Level 0: level0[x] = radiance[x] sanitised, for x in [0, width).
void ColorPyramidSanitizeRowScalar(const float* radiance, size_t width, float* level0);
void ColorPyramidSanitizeRowSimd(const float* radiance, size_t width, float* level0);
// Horizontal blur of one row of level k (width texels): kColorPyramidWeights, clamp-to-edge.
void ColorPyramidHorizontalRowScalar(const float* level, size_t width, float* blurred);
void ColorPyramidHorizontalRowSimd(const float* level, size_t width, float* blurred);
// Row y of level k + 1 (width texels) from level k's horizontal blur: the vertical blur, then the
// coverage-weighted mean over each texel's footprint.
//  horizontalRows: the blurred rows 2y - 3 .. 2y + footprintRows + 2 of level k, clamped to its rows
//    (footprintRows + 6 pointers), each sourceWidth texels;
//  footprintRows: PyramidFootprintEnd(y, ...) - 2y + 1, 2 or 3 (core/pyramid.h);
//  rowCoverage, columnCoverage: level-0 rows covered by each footprint row (footprintRows values),
//    level-0 columns covered by each of level k's columns (sourceWidth values);
//  scratch: footprintRows * sourceWidth floats the kernel may overwrite.
void ColorPyramidVerticalRowScalar(const float* const* horizontalRows, size_t footprintRows,
                                   const float* rowCoverage, const float* columnCoverage, size_t sourceWidth,
                                   size_t width, float* scratch, float* out);
void ColorPyramidVerticalRowSimd(const float* const* horizontalRows, size_t footprintRows,
                                 const float* rowCoverage, const float* columnCoverage, size_t sourceWidth,
                                 size_t width, float* scratch, float* out);

}  // namespace ssgi
