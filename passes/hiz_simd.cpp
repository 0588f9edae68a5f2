// The Highway twins of the Hi-Z's row kernels (hiz.cpp): the same division and the same max, taken
// in the same order, so every target gives the scalar bytes (tests/passes/hiz_test.cpp checks each
// compiled target). Lanes are texels along the row.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/hiz_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include <algorithm>

#include "core/gbuffer-inl.h"
#include "core/gbuffer.h"
#include "core/math-inl.h"
#include "core/pyramid.h"
#include "core/row-inl.h"
#include "passes/hiz.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void HiZInverseDepthRow(const uint32_t* depthWord, size_t width, float* inverseDepth) {
  const hn::ScalableTag<float> df;
  const hn::RebindToUnsigned<decltype(df)> du;
  const auto one = hn::Set(df, 1.0f);
  for (size_t x = 0; x < width; x += hn::Lanes(df)) {
    const auto depth = UnpackDepthV(df, LoadRow(du, depthWord, x, width, PackDepth(kBackgroundDepth)));
    StoreRow(hn::Div(one, depth), df, inverseDepth, x, width);
  }
}

void HiZDownsampleRow(const float* const* sourceRows, size_t footprintRows, size_t sourceWidth, size_t width,
                      float* closestRow) {
  const hn::ScalableTag<float> df;
  const size_t lanes = hn::Lanes(df);
  // Whole vectors of the texels whose footprint columns are 2x and 2x + 1, the last vector
  // overlapping the one before where they are not a whole number of vectors (it writes the same
  // bytes again); the rest (a 1- or 3-wide last footprint, rows shorter than a vector): the scalar
  // kernel.
  const size_t paired = PyramidPairedTexels(width, sourceWidth);
  const size_t vectorEnd = paired >= lanes ? paired : 0;
  for (size_t x = 0; x < vectorEnd; x += lanes) {
    x = std::min(x, vectorEnd - lanes);
    auto closest = hn::Zero(df);
    for (size_t r = 0; r < footprintRows; ++r) {
      hn::Vec<decltype(df)> left, right;
      hn::LoadInterleaved2(df, sourceRows[r] + 2 * x, left, right);
      closest = MaxStd(closest, left);
      closest = MaxStd(closest, right);
    }
    hn::StoreU(closest, df, closestRow + x);
  }
  if (vectorEnd == width) return;
  const float* rest[kMaxPyramidFootprint];
  for (size_t r = 0; r < footprintRows; ++r) rest[r] = sourceRows[r] + 2 * vectorEnd;
  HiZDownsampleRowScalar(rest, footprintRows, sourceWidth - 2 * vectorEnd, width - vectorEnd, closestRow + vectorEnd);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(HiZInverseDepthRow);
HWY_EXPORT(HiZDownsampleRow);

void HiZInverseDepthRowSimd(const uint32_t* depthWord, size_t width, float* inverseDepth) {
  HWY_DYNAMIC_DISPATCH(HiZInverseDepthRow)(depthWord, width, inverseDepth);
}

void HiZDownsampleRowSimd(const float* const* sourceRows, size_t footprintRows, size_t sourceWidth,
                          size_t width, float* closestRow) {
  HWY_DYNAMIC_DISPATCH(HiZDownsampleRow)(sourceRows, footprintRows, sourceWidth, width, closestRow);
}

}  // namespace ssgi
#endif
