// The Highway twin of TonemapRowScalar (tonemap.cpp): the same operations in the same order, no
// fused multiply-add and no approximate division, so every target gives the scalar bytes
// (tests/passes/tonemap_test.cpp checks each compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/tonemap_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/color-inl.h"
#include "passes/tonemap.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The sRGB codes of one channel of a vector of pixels, as 8-bit lanes.
HWY_INLINE hn::Vec<hn::Rebind<uint8_t, DF>> TonemapCodes(VF x, VF scale, bool aces, const int32_t* encodeTable) {
  const DF df;
  const auto zero = hn::Zero(df);
  x = hn::Mul(x, scale);
  x = hn::IfThenElse(hn::Eq(x, x), x, zero);  // NaN -> 0
  x = hn::Min(hn::Max(x, zero), hn::Set(df, kTonemapMaxInput));
  if (aces) {
    const auto numerator = hn::Mul(x, hn::Add(hn::Mul(hn::Set(df, 2.51f), x), hn::Set(df, 0.03f)));
    const auto denominator =
        hn::Add(hn::Mul(x, hn::Add(hn::Mul(hn::Set(df, 2.43f), x), hn::Set(df, 0.59f))), hn::Set(df, 0.14f));
    x = hn::Div(numerator, denominator);
  }
  return hn::DemoteTo(hn::Rebind<uint8_t, DF>(), LinearToSrgbCodeV(x, encodeTable));  // of min(x, 1)
}

void TonemapRow(const float* const radiance[3], size_t count, float scale, bool aces, uint8_t* rgb) {
  const DF df;
  const hn::Rebind<uint8_t, DF> du8;
  const int32_t* encodeTable = SrgbEncodeTableForKernels();
  const size_t lanes = hn::Lanes(df);
  const auto scaleV = hn::Set(df, scale);
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    const auto r = TonemapCodes(hn::LoadU(df, radiance[0] + i), scaleV, aces, encodeTable);
    const auto g = TonemapCodes(hn::LoadU(df, radiance[1] + i), scaleV, aces, encodeTable);
    const auto b = TonemapCodes(hn::LoadU(df, radiance[2] + i), scaleV, aces, encodeTable);
    hn::StoreInterleaved3(r, g, b, du8, rgb + 3 * i);
  }
  const float* const tail[3] = {radiance[0] + i, radiance[1] + i, radiance[2] + i};
  TonemapRowScalar(tail, count - i, scale, aces ? Tonemap::kAces : Tonemap::kClamp, rgb + 3 * i);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(TonemapRow);

void TonemapRowSimd(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  HWY_DYNAMIC_DISPATCH(TonemapRow)(radiance, count, scale, curve == Tonemap::kAces, rgb);
}

}  // namespace ssgi
#endif
