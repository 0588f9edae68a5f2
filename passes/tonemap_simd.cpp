// The Highway twin of TonemapRowScalar (tonemap.cpp): the same operations in the same order, no
// fused multiply-add and no approximate division, so every target gives the scalar bytes
// (tests/passes/tonemap_test.cpp checks each compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/tonemap_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/color.h"
#include "passes/tonemap.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void TonemapRow(const float* radiance, size_t count, float scale, bool aces, uint8_t* codes) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<uint8_t, decltype(df)> du8;
  const SrgbEncodeTables& tables = SrgbEncodeTablesForKernels();
  const size_t lanes = hn::Lanes(df);
  const auto zero = hn::Zero(df);
  const auto one = hn::Set(df, 1.0f);
  const auto largestBelowOne = hn::Set(df, 0.99999994f);
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    auto x = hn::Mul(hn::LoadU(df, radiance + i), hn::Set(df, scale));
    x = hn::IfThenElse(hn::Eq(x, x), x, zero);  // NaN -> 0
    x = hn::Min(hn::Max(x, zero), hn::Set(df, kTonemapMaxInput));
    if (aces) {
      const auto numerator = hn::Mul(x, hn::Add(hn::Mul(hn::Set(df, 2.51f), x), hn::Set(df, 0.03f)));
      const auto denominator =
          hn::Add(hn::Mul(x, hn::Add(hn::Mul(hn::Set(df, 2.43f), x), hn::Set(df, 0.59f))), hn::Set(df, 0.14f));
      x = hn::Div(numerator, denominator);
    }
    // LinearToSrgbCode: the bucket of x (clamped below 1 so the index stays in the table), two
    // threshold steps, then 0 for x <= 0 and 255 for x >= 1.
    const auto inTable = hn::Min(x, largestBelowOne);
    const auto bucket = hn::ShiftRight<kSrgbBucketShift>(hn::BitCast(di, inTable));
    auto code = hn::GatherIndex(di, tables.bucketCode, bucket);
    for (int step = 0; step < 2; ++step) {
      const auto threshold = hn::GatherIndex(df, tables.thresholds, code);
      code = hn::Sub(code, hn::VecFromMask(di, hn::RebindMask(di, hn::Ge(x, threshold))));
    }
    code = hn::IfThenElseZero(hn::RebindMask(di, hn::Gt(x, zero)), code);
    code = hn::IfThenElse(hn::RebindMask(di, hn::Ge(x, one)), hn::Set(di, 255), code);
    hn::StoreU(hn::DemoteTo(du8, code), du8, codes + i);
  }
  TonemapRowScalar(radiance + i, count - i, scale, aces ? Tonemap::kAces : Tonemap::kClamp, codes + i);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(TonemapRow);

void TonemapRowSimd(const float* radiance, size_t count, float scale, Tonemap curve, uint8_t* codes) {
  HWY_DYNAMIC_DISPATCH(TonemapRow)(radiance, count, scale, curve == Tonemap::kAces, codes);
}

}  // namespace ssgi
#endif
