#include "core/edge_masks.h"

#include <cmath>

#include "core/check.h"

namespace ssgi {
namespace {

double Luminance(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

double Display(double luminance) { return luminance / (1.0 + luminance); }

// Per pixel, the luminance of an RGB image of the pairs' size.
std::vector<double> Luminances(const FloatImage& rgb, const NeighbourPairs& pairs) {
  SSGI_CHECK(rgb.width == pairs.width && rgb.height == pairs.height && rgb.Channels() == 3);
  std::vector<double> luminance(pairs.bits.size());
  for (size_t i = 0; i < luminance.size(); ++i) luminance[i] = Luminance(&rgb.pixels[3 * i]);
  return luminance;
}

// The pairs on one surface (not in `geometric`) for which stepsAt(i, j), pixels i and j, holds.
template <typename Step>
NeighbourPairs PairsOnOneSurface(const NeighbourPairs& geometric, const Step& stepsAt) {
  NeighbourPairs pairs{geometric.width, geometric.height, std::vector<uint8_t>(geometric.bits.size(), 0)};
  const size_t width = size_t(geometric.width), height = size_t(geometric.height);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      const size_t i = y * width + x;
      if (x + 1 < width && !(geometric.bits[i] & kPairRight) && stepsAt(i, i + 1)) pairs.bits[i] |= kPairRight;
      if (y + 1 < height && !(geometric.bits[i] & kPairDown) && stepsAt(i, i + width)) pairs.bits[i] |= kPairDown;
    }
  return pairs;
}

// PairMask(pairs) less PairMask(geometric).
std::vector<uint8_t> OffGeometricEdges(const NeighbourPairs& pairs, const NeighbourPairs& geometric) {
  std::vector<uint8_t> mask = PairMask(pairs);
  const std::vector<uint8_t> edges = PairMask(geometric);
  for (size_t i = 0; i < mask.size(); ++i) mask[i] &= uint8_t(!edges[i]);
  return mask;
}

}  // namespace

std::vector<uint8_t> DilatedMask(const std::vector<uint8_t>& marked, int width, int height) {
  SSGI_CHECK_EQ(marked.size(), size_t(width) * size_t(height));
  std::vector<uint8_t> mask(marked.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int sx = x + dx, sy = y + dy;
          if (sx >= 0 && sy >= 0 && sx < width && sy < height && marked[size_t(sy) * size_t(width) + size_t(sx)])
            mask[size_t(y) * size_t(width) + size_t(x)] = 1;
        }
  return mask;
}

std::vector<uint8_t> PairMask(const NeighbourPairs& pairs) {
  const size_t width = size_t(pairs.width), height = size_t(pairs.height);
  SSGI_CHECK_EQ(pairs.bits.size(), width * height);
  std::vector<uint8_t> marked(pairs.bits.size(), 0);
  for (size_t y = 0; y < height; ++y)
    for (size_t x = 0; x < width; ++x) {
      const size_t i = y * width + x;
      if (pairs.bits[i] & kPairRight) marked[i] = marked[i + 1] = 1;
      if (pairs.bits[i] & kPairDown) marked[i] = marked[i + width] = 1;
    }
  return DilatedMask(marked, pairs.width, pairs.height);
}

std::vector<uint8_t> ShadowEdgeMask(const FloatImage& visibility, const FloatImage& direct,
                                    const NeighbourPairs& geometric) {
  SSGI_CHECK(visibility.width == geometric.width && visibility.height == geometric.height &&
             visibility.Channels() == 1);
  const std::vector<float>& v = visibility.pixels;
  const std::vector<double> light = Luminances(direct, geometric);
  const NeighbourPairs pairs = PairsOnOneSurface(geometric, [&](size_t i, size_t j) {
    return std::abs(v[i] - v[j]) >= kShadowEdgeStep &&
           std::abs(Display(light[i]) - Display(light[j])) >= kEdgeDisplayStep;
  });
  return OffGeometricEdges(pairs, geometric);
}

std::vector<uint8_t> ReflectionEdgeMask(const FloatImage& direct, const FloatImage& indirect,
                                        const std::vector<uint8_t>& reflective, const NeighbourPairs& geometric) {
  SSGI_CHECK_EQ(reflective.size(), geometric.bits.size());
  const std::vector<double> directLuma = Luminances(direct, geometric), indirectLuma = Luminances(indirect, geometric);
  const NeighbourPairs pairs = PairsOnOneSurface(geometric, [&](size_t i, size_t j) {
    return reflective[i] && reflective[j] &&
           std::abs(Display(directLuma[i] + indirectLuma[i]) - Display(directLuma[j] + indirectLuma[j])) >=
               kEdgeDisplayStep &&
           std::abs(indirectLuma[i] - indirectLuma[j]) >= std::abs(directLuma[i] - directLuma[j]);
  });
  return OffGeometricEdges(pairs, geometric);
}

}  // namespace ssgi
