// Morphological anti-aliasing (docs/pipeline.md §Morphological anti-aliasing, --aa mlaa): the edges
// of the final image itself, found where its perceptual luma jumps, turned into the edge coverage word
// (core/edge_coverage.h) that the anti-aliasing pass (passes/antialias.h) blends by. Reshetov's MLAA
// (HPG 2009) in the form of Jimenez et al.'s practical MLAA (GPU Pro 2, 2011) and SMAA 1x's orthogonal
// patterns (Jimenez et al. 2012):
//   1. luma: L = sqrt(t / (1 + t)), t the Rec. 709 luminance times 2^exposure: the display's
//      compression of HDR (the Reinhard curve) and roughly its gamma, so one threshold means one
//      visible step in shadow and in highlight alike;
//   2. edges: between 4-neighbours whose luma differs by at least `threshold` and by at least half the
//      largest difference around (SMAA's local contrast adaptation);
//   3. blend weights: each horizontal (vertical) edge followed along its whole run, which ends where
//      the edge ends or an edge crosses it; where the edge steps at an end to the next row (column),
//      the silhouette there is half a pixel off the edge on that side, which gives its shape (L, Z or
//      U: a line from each stepping end to the run's middle), and each pixel along the run gets the
//      exact area between that line and the edge, in integers (no area texture, no search limit);
//   4. coverage: per pixel, the weights of its four edges as an edge coverage word.
// What SMAA 1x adds and this does not: diagonal patterns, corner rounding and the search's bilinear
// tricks. The luma, the edges and the coverage have a scalar definition (mlaa.cpp) and a Highway twin
// (mlaa_simd.cpp) that gives the same bytes on every target; the runs are scalar, in integers.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/kernel_path.h"
#include "core/plane.h"

namespace ssgi {

struct MlaaParams {
  // The least luma difference that is an edge: SMAA's default (its "high" preset) on the luma above.
  float threshold = 0.1f;
  float exposureEv = 0.0f;  // the tonemap's exposure, which the luma sees the image through
};

struct MlaaInputs {
  const Plane3<float>& image;  // the final linear HDR image
};

// Edge bits (`edges`).
inline constexpr uint32_t kMlaaLeftEdge = 1;  // the pixel differs from its left neighbour
inline constexpr uint32_t kMlaaTopEdge = 2;   // the pixel differs from its upper neighbour

struct MlaaOutputs {
  Plane<float> luma;
  Plane<uint32_t> edges;  // kMlaaLeftEdge | kMlaaTopEdge per pixel
  // Per pixel, the blend weights of its left and top edges in 1/256 (SMAA's blend weight texture):
  // byte 0 the share of the left neighbour's area that this pixel's colour covers, byte 1 the share
  // of this pixel's area that the left neighbour's colour covers; bytes 2 and 3 the same with the
  // upper neighbour.
  Plane<uint32_t> weights;
  Plane<uint32_t> coverage;  // the edge coverage words the weights give each pixel
};

struct MlaaStats {
  double ms = 0.0;
  size_t edgePixels = 0;   // pixels with an edge bit
  size_t blendPixels = 0;  // pixels with a non-zero coverage word
};

// Fills `out` (sized to the image; kept buffers of that size are overwritten).
MlaaStats RunMlaa(const MlaaInputs& in, const MlaaParams& params, MlaaOutputs& out,
                  KernelPath kernels = KernelPath::kSimd);

// One row of luma: luma[x] = sqrt(t / (1 + t)), t = SanitizeRadiance(((0.2126 r + 0.7152 g) +
// 0.0722 b) * exposureScale), for x in [0, width).
void MlaaLumaRowScalar(const float* const rgb[3], size_t width, float exposureScale, float* luma);
void MlaaLumaRowSimd(const float* const rgb[3], size_t width, float exposureScale, float* luma);

// One row of edge bits from rows of luma: rows[0] two rows up, rows[1] one up, rows[2] this row,
// rows[3] one down. Where the image has no such row, pass the nearest row that exists (rows[1] for
// rows[0], this row for the others): a missing neighbour then differs by 0, as does x - 1 or x - 2
// past the left border and x + 1 past the right one.
void MlaaEdgeRowScalar(const float* const rows[4], size_t width, float threshold, uint32_t* edges);
// The same for x in [begin, end) only (the twin's first pixels and its tail).
void MlaaEdgePixelsScalar(const float* const rows[4], size_t width, float threshold, size_t begin, size_t end,
                          uint32_t* edges);
void MlaaEdgeRowSimd(const float* const rows[4], size_t width, float threshold, uint32_t* edges);

// One row of coverage words from rows of weights (`below`: the next row's, zeros below the last
// row), for x in [0, width); returns the words that are not 0.
size_t MlaaCoverageRowScalar(const uint32_t* weights, const uint32_t* below, size_t width, uint32_t* coverage);
// The same for x in [begin, end) only (the twin's tail).
size_t MlaaCoveragePixelsScalar(const uint32_t* weights, const uint32_t* below, size_t width, size_t begin, size_t end,
                                uint32_t* coverage);
size_t MlaaCoverageRowSimd(const uint32_t* weights, const uint32_t* below, size_t width, uint32_t* coverage);

// The weight codes of a pixel `k` pixels into a run of `n` edge pixels whose ends' silhouette heights
// are `startHeight` and `endHeight` (+1: half a pixel toward the edge's first side, the upper or left
// neighbour; -1: toward its second side; 0: no step, or a step to each side): the area between the
// silhouette and the edge on each side, in 1/256, rounded to nearest. [0] the first side's pixel's
// share of the second's colour, [1] the reverse.
void MlaaRunWeights(uint32_t n, uint32_t k, int startHeight, int endHeight, uint32_t codes[2]);

}  // namespace ssgi
