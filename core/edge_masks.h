// Where anti-aliasing is measured (README "Anti-aliasing", bench/aa_accuracy.cpp): masks of the
// pixels along one kind of edge each (geometric, shadow, reflection), so that a technique's error
// against a box-filtered truth can be told apart by what made the edge. A mask is width * height
// bytes, row-major, 1 = in.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image_compare.h"

namespace ssgi {

// Marked pairs of 4-neighbours: bit kPairRight of pixel (x, y) marks the pair it makes with (x + 1,
// y), kPairDown the one with (x, y + 1).
enum NeighbourPair : uint8_t { kPairRight = 1, kPairDown = 2 };
struct NeighbourPairs {
  int width = 0, height = 0;
  std::vector<uint8_t> bits;  // width * height, row-major
};

// The marked pixels and their 8 neighbours (a 3x3 dilation).
std::vector<uint8_t> DilatedMask(const std::vector<uint8_t>& marked, int width, int height);

// The pixels of the marked pairs, dilated: the edge and the pixels a blend across it reaches.
std::vector<uint8_t> PairMask(const NeighbourPairs& pairs);

// The step in display luma, y / (1 + y) of the Rec. 709 luminance (x / (1 + x), the display RMSE's
// curve), that makes an edge worth measuring: a twentieth of that curve's range [0, 1). Smaller steps
// hardly show.
inline constexpr double kEdgeDisplayStep = 0.05;

// The step in light visibility between neighbours that makes a shadow edge: a quarter of the light,
// so penumbrae narrower than about four pixels, where the shadow filter's blur is too narrow to hide
// the hard test's steps. Wider ones have no steps to anti-alias and would only dilute the figures.
inline constexpr float kShadowEdgeStep = 0.25f;

// Shadow edges: the pairs on one surface (not in `geometric`, the pairs across a geometric edge)
// whose light visibility (`visibility`, one channel in [0, 1]: the truth's fraction of the light
// reaching the pixel) differs by at least kShadowEdgeStep and whose direct light's display luma
// (`direct`, linear RGB) differs by at least kEdgeDisplayStep, as PairMask, less PairMask(geometric):
// a shadow meeting its caster belongs to the geometric edge. The second condition leaves out the
// terminators of curved surfaces, where the visibility drops as the surface turns from the light but
// the light there is already nearly zero, and shadows on surfaces too dark to show them. Both images
// are the truth's, box-filtered.
std::vector<uint8_t> ShadowEdgeMask(const FloatImage& visibility, const FloatImage& direct,
                                    const NeighbourPairs& geometric);

// Reflection edges: the pairs on one surface (not in `geometric`) of two `reflective` pixels
// (non-zero: the trace reflects them) whose display luma of direct + indirect differs by at least
// kEdgeDisplayStep, and whose indirect (reflected) luminance steps at least as much as their direct
// luminance: the step is the reflected image's, not a shadow's or a texture's. As PairMask, less
// PairMask(geometric). `direct` and `indirect` are the truth's linear RGB, box-filtered.
std::vector<uint8_t> ReflectionEdgeMask(const FloatImage& direct, const FloatImage& indirect,
                                        const std::vector<uint8_t>& reflective, const NeighbourPairs& geometric);

}  // namespace ssgi
