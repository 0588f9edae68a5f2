// Hi-Z pyramid (docs/design.md §6; docs/pipeline.md §Hi-Z pyramid): the closest depth per cell, level by
// level, for the hierarchical screen-space ray march of Uludag (GPU Pro 5, "Hi-Z Screen-Space
// Cone-Traced Reflections"). Stores INVERSE view depth 1/d, in 1/metres, because a screen-space ray
// is linear in (x, y, 1/d), not in d: the trace compares the quantity it interpolates. The closest
// depth is then the MAX of 1/d; background (+inf) is 0, so it never occludes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

struct HiZ {
  // levels[0]: the G-buffer's size; levels[k + 1]: PyramidHalvedSize (core/pyramid.h) of levels[k] on
  // each axis; the last level is 1 x 1. Texels: max of 1/d over the level-0 texels the cell covers,
  // in 1/metres, >= 0 (0 = background only).
  std::vector<Plane<float>> levels;
};

struct HiZStats {
  double ms = 0;
  size_t texels = 0;  // written over all levels
};

// depthWord: G-buffer word 2 (view depth d in metres as float bits, d > 0, +inf = background).
// Reuses out's planes when their sizes already match, else allocates them. kernels: which definition
// of the row kernels runs (the same bytes either way).
HiZStats RunHiZ(const Plane<uint32_t>& depthWord, HiZ& out, KernelPath kernels = KernelPath::kSimd);

// The Hi-Z's row kernels: the scalar definitions (hiz.cpp) and their Highway twins (hiz_simd.cpp),
// equal bit for bit on every SIMD target.
// Level 0, one row: inverseDepth[x] = 1/d of depthWord[x] (G-buffer word 2), for x in [0, width).
void HiZInverseDepthRowScalar(const uint32_t* depthWord, size_t width, float* inverseDepth);
void HiZInverseDepthRowSimd(const uint32_t* depthWord, size_t width, float* inverseDepth);
// Level k + 1, row y: closestRow[x] = the max of level k over texel x's footprint, for x in
// [0, width). sourceRows: level k's rows 2y .. PyramidFootprintEnd(y, ...), footprintRows of them (2,
// or 3 at an odd level's last row), each sourceWidth texels; columns as rows (PyramidFootprintEnd).
void HiZDownsampleRowScalar(const float* const* sourceRows, size_t footprintRows, size_t sourceWidth,
                            size_t width, float* closestRow);
void HiZDownsampleRowSimd(const float* const* sourceRows, size_t footprintRows, size_t sourceWidth,
                          size_t width, float* closestRow);

}  // namespace ssgi
