// The Highway twins of the colour pyramid's row kernels (color_pyramid.cpp): the same products and
// sums in the same order, no fused multiply-add, an exact division, so every target gives the scalar
// bytes (tests/passes/color_pyramid_test.cpp checks each compiled target). Lanes are texels along
// the row.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/color_pyramid_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include <algorithm>

#include "core/math-inl.h"
#include "core/pyramid.h"
#include "core/row-inl.h"
#include "passes/color_pyramid.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace {

// The 7 taps summed as the scalar kernels sum them: from 0, in tap order; tap(t) is tap t's texels.
template <class D, class Tap>
hn::Vec<D> Gaussian(D d, const Tap& tap) {
  auto sum = hn::Zero(d);
  for (size_t t = 0; t < kColorPyramidWeights.size(); ++t)
    sum = hn::Add(sum, hn::Mul(hn::Set(d, kColorPyramidWeights[t]), tap(t)));
  return sum;
}

// The vertical blur (lanes: source texels) of the kRows footprint rows into scratch rows
// 0 .. kRows - 1, columns [0, columns) (at least a vector; the last vector overlaps the one before
// where they are not a whole number of vectors). Each tap row is loaded once for all the footprint
// rows whose taps it is (the loads, not the arithmetic, bound this loop); each footprint row still
// adds its taps in tap order.
template <size_t kRows, class D>
void BlurFootprintRows(D d, const float* const* horizontalRows, size_t sourceWidth, size_t columns, float* scratch) {
  constexpr size_t kTaps = kColorPyramidWeights.size();
  const size_t lanes = hn::Lanes(d);
  // A local copy, which the compiler keeps in registers: hn::StoreU may alias any memory.
  const float* rows[kRows + kTaps - 1];
  std::copy(horizontalRows, horizontalRows + kRows + kTaps - 1, rows);
  for (size_t sx = 0; sx < columns; sx += lanes) {
    sx = std::min(sx, columns - lanes);
    auto blurred0 = hn::Zero(d), blurred1 = hn::Zero(d), blurred2 = hn::Zero(d);
    for (size_t i = 0; i < kRows + kTaps - 1; ++i) {
      // Row i is tap i - r of footprint row r.
      const auto v = hn::LoadU(d, rows[i] + sx);
      if (i < kTaps) blurred0 = hn::Add(blurred0, hn::Mul(hn::Set(d, kColorPyramidWeights[i]), v));
      if (kRows > 1 && i >= 1 && i < kTaps + 1)
        blurred1 = hn::Add(blurred1, hn::Mul(hn::Set(d, kColorPyramidWeights[i - 1]), v));
      if (kRows > 2 && i >= 2) blurred2 = hn::Add(blurred2, hn::Mul(hn::Set(d, kColorPyramidWeights[i - 2]), v));
    }
    hn::StoreU(blurred0, d, scratch + sx);
    if (kRows > 1) hn::StoreU(blurred1, d, scratch + sourceWidth + sx);
    if (kRows > 2) hn::StoreU(blurred2, d, scratch + 2 * sourceWidth + sx);
  }
}

}  // namespace

void ColorPyramidSanitizeRow(const float* radiance, size_t width, float* level0) {
  const hn::ScalableTag<float> df;
  for (size_t x = 0; x < width; x += hn::Lanes(df))
    StoreRow(SanitizeRadianceV(LoadRow(df, radiance, x, width, 0.0f)), df, level0, x, width);
}

void ColorPyramidHorizontalRow(const float* level, size_t width, float* blurred) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  constexpr size_t kRadius = kColorPyramidRadius;
  // Rows shorter than a vector and the taps' reach on both sides, and vectors too narrow to hold the
  // 3 clamped texels at either end (HWY_SCALAR): the scalar kernel.
  if (lanes <= kRadius || width < lanes + 2 * kRadius) return ColorPyramidHorizontalRowScalar(level, width, blurred);
  // Blurs texels x .. x + lanes - 1; tap(start) is a tap's texels start .. start + lanes - 1.
  const auto blur = [&](size_t x, const auto& tap) {
    hn::StoreU(Gaussian(df, [&](size_t t) { return tap(ptrdiff_t(x + t) - ptrdiff_t(kRadius)); }), df, blurred + x);
  };
  // The first vector: a tap starting left of texel 0 takes the first texels shifted right, texel 0
  // repeated (clamp-to-edge).
  const auto first = hn::LoadU(df, level);
  blur(0, [&](ptrdiff_t start) {
    if (start >= 0) return hn::LoadU(df, level + start);
    const auto indices = hn::Max(hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(start))), hn::Zero(di));
    return hn::TableLookupLanes(first, hn::IndicesFromVec(df, indices));
  });
  // Up to the last vector, vectors whose taps lie inside the row, the last of them overlapping the
  // one before where needed (it writes the same bytes again).
  const auto inside = [&](ptrdiff_t start) { return hn::LoadU(df, level + start); };
  for (size_t x = lanes; x < width - lanes; x += lanes) {
    x = std::min(x, width - lanes - kRadius);
    blur(x, inside);
  }
  // The last vector, ending at the row's end: a tap reaching past the last texel takes the last
  // texels shifted left, the last texel repeated.
  const size_t x = width - lanes;
  const auto last = hn::LoadU(df, level + x);
  const auto lastLane = hn::Set(di, int32_t(lanes - 1));
  blur(x, [&](ptrdiff_t start) {
    if (start <= ptrdiff_t(x)) return hn::LoadU(df, level + start);
    const auto indices = hn::Min(hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(start - ptrdiff_t(x)))), lastLane);
    return hn::TableLookupLanes(last, hn::IndicesFromVec(df, indices));
  });
}

void ColorPyramidVerticalRow(const float* const* horizontalRows, size_t footprintRows, const float* rowCoverage,
                             const float* columnCoverage, size_t sourceWidth, size_t width, float* scratch,
                             float* out) {
  const hn::ScalableTag<float> df;
  const size_t lanes = hn::Lanes(df);
  // Whole vectors of the texels whose footprint columns are 2x and 2x + 1, the last vector
  // overlapping the one before where they are not a whole number of vectors (it writes the same
  // bytes again); the rest (a 1- or 3-wide last footprint, rows shorter than a vector): the scalar
  // kernel, which may overwrite the scratch, read by then.
  const size_t paired = PyramidPairedTexels(width, sourceWidth);
  const size_t vectorEnd = paired >= lanes ? paired : 0;
  if (vectorEnd > 0) {
    if (footprintRows == 1) BlurFootprintRows<1>(df, horizontalRows, sourceWidth, 2 * vectorEnd, scratch);
    if (footprintRows == 2) BlurFootprintRows<2>(df, horizontalRows, sourceWidth, 2 * vectorEnd, scratch);
    if (footprintRows == 3) BlurFootprintRows<3>(df, horizontalRows, sourceWidth, 2 * vectorEnd, scratch);
  }
  // The coverage-weighted mean of each footprint, row by row and left column first, as the scalar
  // kernel adds them.
  for (size_t x = 0; x < vectorEnd; x += lanes) {
    x = std::min(x, vectorEnd - lanes);
    hn::Vec<decltype(df)> leftCoverage, rightCoverage, left, right;
    hn::LoadInterleaved2(df, columnCoverage + 2 * x, leftCoverage, rightCoverage);
    auto sum = hn::Zero(df);
    auto area = hn::Zero(df);
    for (size_t r = 0; r < footprintRows; ++r) {
      hn::LoadInterleaved2(df, scratch + r * sourceWidth + 2 * x, left, right);
      const auto rowWeight = hn::Set(df, rowCoverage[r]);
      const auto leftWeight = hn::Mul(rowWeight, leftCoverage);
      sum = hn::Add(sum, hn::Mul(leftWeight, left));
      area = hn::Add(area, leftWeight);
      const auto rightWeight = hn::Mul(rowWeight, rightCoverage);
      sum = hn::Add(sum, hn::Mul(rightWeight, right));
      area = hn::Add(area, rightWeight);
    }
    hn::StoreU(hn::Div(sum, area), df, out + x);
  }
  if (vectorEnd == width) return;
  const float* rest[kMaxPyramidFootprint + 2 * kColorPyramidRadius];
  for (size_t i = 0; i < footprintRows + 2 * kColorPyramidRadius; ++i) rest[i] = horizontalRows[i] + 2 * vectorEnd;
  ColorPyramidVerticalRowScalar(rest, footprintRows, rowCoverage, columnCoverage + 2 * vectorEnd,
                                sourceWidth - 2 * vectorEnd, width - vectorEnd, scratch, out + vectorEnd);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(ColorPyramidSanitizeRow);
HWY_EXPORT(ColorPyramidHorizontalRow);
HWY_EXPORT(ColorPyramidVerticalRow);

void ColorPyramidSanitizeRowSimd(const float* radiance, size_t width, float* level0) {
  HWY_DYNAMIC_DISPATCH(ColorPyramidSanitizeRow)(radiance, width, level0);
}

void ColorPyramidHorizontalRowSimd(const float* level, size_t width, float* blurred) {
  HWY_DYNAMIC_DISPATCH(ColorPyramidHorizontalRow)(level, width, blurred);
}

void ColorPyramidVerticalRowSimd(const float* const* horizontalRows, size_t footprintRows,
                                 const float* rowCoverage, const float* columnCoverage, size_t sourceWidth,
                                 size_t width, float* scratch, float* out) {
  HWY_DYNAMIC_DISPATCH(ColorPyramidVerticalRow)(horizontalRows, footprintRows, rowCoverage, columnCoverage,
                                                sourceWidth, width, scratch, out);
}

}  // namespace ssgi
#endif
