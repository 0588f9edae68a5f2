// The Highway twin of TonemapRowScalar (tonemap.cpp): the exposure product as the scalar kernel
// rounds it, then each channel's code from the curve's bucket table (TonemapCodeBuckets) with one
// gather, so every target gives the scalar bytes (tests/passes/tonemap_test.cpp checks each compiled
// target and every float).
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

// The codes of one channel of a vector of pixels, as 8-bit lanes: the bucket lookup of
// TonemapCodeBuckets, which is TonemapCode for every x >= 0 that is not NaN (NaN is 0 there).
HWY_INLINE hn::Vec<hn::Rebind<uint8_t, DF>> TonemapCodes(VF x, VF scale, const CodeBuckets& buckets) {
  x = hn::Mul(x, scale);
  x = hn::IfThenElseZero(hn::Eq(x, x), x);  // NaN -> 0
  const VI codes = BucketCodeV(hn::BitCast(DI(), x), buckets);
  return hn::DemoteTo(hn::Rebind<uint8_t, DF>(), codes);
}

void TonemapRow(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  const DF df;
  const hn::Rebind<uint8_t, DF> du8;
  const CodeBuckets& buckets = TonemapCodeBuckets(curve);
  const size_t lanes = hn::Lanes(df);
  const auto scaleV = hn::Set(df, scale);
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    const auto r = TonemapCodes(hn::LoadU(df, radiance[0] + i), scaleV, buckets);
    const auto g = TonemapCodes(hn::LoadU(df, radiance[1] + i), scaleV, buckets);
    const auto b = TonemapCodes(hn::LoadU(df, radiance[2] + i), scaleV, buckets);
    hn::StoreInterleaved3(r, g, b, du8, rgb + 3 * i);
  }
  const float* const tail[3] = {radiance[0] + i, radiance[1] + i, radiance[2] + i};
  TonemapRowScalar(tail, count - i, scale, curve, rgb + 3 * i);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(TonemapRow);

void TonemapRowSimd(const float* const radiance[3], size_t count, float scale, Tonemap curve, uint8_t* rgb) {
  HWY_DYNAMIC_DISPATCH(TonemapRow)(radiance, count, scale, curve, rgb);
}

}  // namespace ssgi
#endif
