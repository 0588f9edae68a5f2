// Hi-Z pyramid (DESIGN.md §6; docs/pipeline.md §Hi-Z pyramid): the closest depth per cell, level by
// level, for the hierarchical screen-space ray march of Uludag (GPU Pro 5, "Hi-Z Screen-Space
// Cone-Traced Reflections"). Stores INVERSE view depth 1/d, in 1/metres, because a screen-space ray
// is linear in (x, y, 1/d), not in d: the trace compares the quantity it interpolates. The closest
// depth is then the MAX of 1/d; background (+inf) is 0, so it never occludes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/plane.h"

namespace ssgi {

// Pyramid level sizes, shared with the colour pyramid so one level index addresses both: floor
// halving, never below 1 (67 -> 33 -> 16 -> 8 -> 4 -> 2 -> 1).
inline size_t PyramidHalvedSize(size_t size) { return size / 2 > 0 ? size / 2 : 1; }

// The last source texel (inclusive) of the footprint of destination texel `x` along one axis, whose
// first source texel is 2x. Normally 2x + 1; the last destination texel takes everything up to the
// source's end, so an odd source's last texel is covered (3-wide footprint) and a 1-texel source is
// never read past.
inline size_t PyramidFootprintEnd(size_t x, size_t destinationSize, size_t sourceSize) {
  return x + 1 == destinationSize ? sourceSize - 1 : 2 * x + 1;
}

struct PyramidSize {
  size_t width = 0;
  size_t height = 0;
};

// Every level's size for a width x height level 0 (both > 0), from level 0 down to 1 x 1.
inline std::vector<PyramidSize> PyramidLevelSizes(size_t width, size_t height) {
  std::vector<PyramidSize> sizes{{width, height}};
  while (width > 1 || height > 1) {
    width = PyramidHalvedSize(width);
    height = PyramidHalvedSize(height);
    sizes.push_back({width, height});
  }
  return sizes;
}

struct HiZ {
  // levels[0]: the G-buffer's size; levels[k + 1]: PyramidHalvedSize of levels[k] on each axis; the
  // last level is 1 x 1. Texels: max of 1/d over the level-0 texels the cell covers, in 1/metres,
  // >= 0 (0 = background only).
  std::vector<Plane<float>> levels;
};

struct HiZStats {
  double ms = 0;
  size_t texels = 0;  // written over all levels
};

// depthWord: G-buffer word 2 (view depth d in metres as float bits, d > 0, +inf = background).
// Reuses out's planes when their sizes already match, else allocates them.
HiZStats RunHiZ(const Plane<uint32_t>& depthWord, HiZ& out);

}  // namespace ssgi
