// Anti-aliasing pass (docs/pipeline.md §Anti-aliasing): the final linear HDR image, before the
// tonemap, blended across the geometric edges the rasterizer found. Each pixel with a non-zero
// edge coverage word (core/edge_coverage.h: from the G-buffer pass or the morphological pass) becomes the
// coverage-weighted mean of its own colour and its 4-neighbours' colours,
//   out = (c w0 + left wl + right wr + up wu + down wd) / 256,   w0 = 256 - (wl + wr + wu + wd),
// each product and sum rounded in float32 in that order. That is the box filter of a pixel cut by a
// straight edge, where the neighbour across the edge stands for the other surface's colour
// (Persson's geometric buffer anti-aliasing, with the coverage exact from the triangle's edge rather
// than interpolated in a geometry shader). Pixels with a zero word keep their bytes.
// The row kernel has a scalar definition (antialias.cpp) and a Highway twin (antialias_simd.cpp)
// that gives the same bytes on every SIMD target.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

struct AntialiasInputs {
  const Plane<uint32_t>& edgeCoverage;  // the G-buffer's edge coverage words
  const Plane3<float>& image;           // linear HDR radiance, finite
};

struct AntialiasStats {
  double ms = 0.0;
  size_t edgePixels = 0;  // pixels blended
};

// Writes the anti-aliased image into `out`, which may be `in.image` itself (the pass then works in
// place: it reads every neighbour before it writes a pixel) or a buffer of its size, whose every
// pixel it writes.
AntialiasStats RunAntialias(const AntialiasInputs& in, Plane3<float>& out, KernelPath kernels = KernelPath::kSimd);

// One row: for each x in [0, width) with coverage[x] != 0, blended[c][x] = the blend of
// rows[c][1][x] with rows[c][1][x -+ 1] (left, right) and rows[c][0][x], rows[c][2][x] (up, down),
// in the order the header gives. rows[c][0] and rows[c][2] may be row 1 itself at the image's top
// and bottom (the word's weight toward them is 0 there), as may x - 1 and x + 1 at its sides. Other
// entries of `blended` are left as they were.
void AntialiasRowScalar(const uint32_t* coverage, const float* const rows[3][3], size_t width, float* const blended[3]);
// The same for x in [begin, end) only (the twin's first pixel and its tail).
void AntialiasPixelsScalar(const uint32_t* coverage, const float* const rows[3][3], size_t width, size_t begin,
                           size_t end, float* const blended[3]);
void AntialiasRowSimd(const uint32_t* coverage, const float* const rows[3][3], size_t width, float* const blended[3]);

}  // namespace ssgi
