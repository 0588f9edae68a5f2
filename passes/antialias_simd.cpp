// The Highway twin of AntialiasRowScalar (antialias.cpp): the same products and sums in the same
// order, Mul then Add (never a fused MulAdd), on vectors of pixels; a vector without an edge pixel
// is skipped. The first pixel and the tail, whose neighbours the vectors cannot load, go to the
// scalar definition.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/antialias_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep

#include "hwy/highway.h"

#include "core/math-inl.h"
#include "passes/antialias.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void AntialiasRow(const uint32_t* coverage, const float* const rows[3][3], size_t width, float* const blended[3]) {
  const DF df;
  const DU du;
  const DI di;
  const size_t lanes = hn::Lanes(df);
  AntialiasPixelsScalar(coverage, rows, width, 0, width < 1 ? width : 1, blended);
  size_t x = 1;
  const auto byte = hn::Set(du, 255u);
  const auto scale = hn::Set(df, 1.0f / 256.0f);
  for (; x + lanes < width; x += lanes) {
    const auto word = hn::LoadU(du, coverage + x);
    const auto edge = hn::Ne(word, hn::Zero(du));
    if (hn::AllFalse(du, edge)) continue;
    const auto l = hn::And(word, byte), r = hn::And(hn::ShiftRight<8>(word), byte),
               u = hn::And(hn::ShiftRight<16>(word), byte), d = hn::ShiftRight<24>(word);
    const auto own = hn::Sub(hn::Sub(hn::Sub(hn::Sub(hn::Set(du, 256u), l), r), u), d);
    const auto toFloat = [&](hn::Vec<DU> v) { return hn::ConvertTo(df, hn::BitCast(di, v)); };
    const VF w0 = toFloat(own), wl = toFloat(l), wr = toFloat(r), wu = toFloat(u), wd = toFloat(d);
    const auto store = hn::RebindMask(df, edge);
    for (int c = 0; c < 3; ++c) {
      const float* row = rows[c][1];
      VF sum = hn::Mul(hn::LoadU(df, row + x), w0);
      sum = hn::Add(sum, hn::Mul(hn::LoadU(df, row + x - 1), wl));
      sum = hn::Add(sum, hn::Mul(hn::LoadU(df, row + x + 1), wr));
      sum = hn::Add(sum, hn::Mul(hn::LoadU(df, rows[c][0] + x), wu));
      sum = hn::Add(sum, hn::Mul(hn::LoadU(df, rows[c][2] + x), wd));
      hn::BlendedStore(hn::Mul(sum, scale), store, df, blended[c] + x);
    }
  }
  AntialiasPixelsScalar(coverage, rows, width, x < width ? x : width, width, blended);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(AntialiasRow);

void AntialiasRowSimd(const uint32_t* coverage, const float* const rows[3][3], size_t width, float* const blended[3]) {
  HWY_DYNAMIC_DISPATCH(AntialiasRow)(coverage, rows, width, blended);
}

}  // namespace ssgi
#endif
