// Image pyramid level sizes and footprints (docs/pipeline.md §Hi-Z pyramid), shared by the Hi-Z
// and the colour pyramid so one level index addresses both.
#pragma once

#include <cstddef>
#include <vector>

namespace ssgi {

// The next level's size along one axis: floor halving, never below 1 (67 -> 33 -> 16 -> 8 -> 4 -> 2 -> 1).
inline size_t PyramidHalvedSize(size_t size) { return size / 2 > 0 ? size / 2 : 1; }

// The last source texel (inclusive) of the footprint of destination texel `x` along one axis, whose
// first source texel is 2x. Normally 2x + 1; the last destination texel takes everything up to the
// source's end, so an odd source's last texel is covered (3-wide footprint) and a 1-texel source is
// never read past.
inline size_t PyramidFootprintEnd(size_t x, size_t destinationSize, size_t sourceSize) {
  return x + 1 == destinationSize ? sourceSize - 1 : 2 * x + 1;
}
// The widest footprint along one axis, in source texels: an odd source's last texel.
inline constexpr size_t kMaxPyramidFootprint = 3;
// How many destination texels 0, 1, ... have the footprint 2x, 2x + 1 along one axis: all of them
// when the source is twice as long, else all but the last (an odd source's 3-wide footprint, or a
// 1-texel source's 1-wide one).
inline size_t PyramidPairedTexels(size_t destinationSize, size_t sourceSize) {
  return sourceSize == 2 * destinationSize ? destinationSize : destinationSize - 1;
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

}  // namespace ssgi
