// The edge coverage word (docs/pipeline.md §Edge coverage and anti-aliasing): per pixel, the shares of
// its area, in 1/256, covered by the surface of each 4-neighbour. The G-buffer pass writes it from the
// rasterizer's triangle edges (--aa edge), the morphological pass from the image's luma edges
// (--aa mlaa), and the anti-aliasing pass blends by it.
#pragma once

#include <cstdint>

namespace ssgi {

// Bytes 0-3 are the shares of the pixel's left, right, upper and lower neighbour; their sum is at
// most 256. 0: no edge.
inline uint32_t EdgeCoverageWord(uint32_t left, uint32_t right, uint32_t up, uint32_t down) {
  return left | right << 8 | up << 16 | down << 24;
}

}  // namespace ssgi
