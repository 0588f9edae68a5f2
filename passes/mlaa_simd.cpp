// The Highway twins of MlaaLumaRowScalar, MlaaEdgeRowScalar and MlaaCoverageRowScalar (mlaa.cpp): the
// same products, sums, divisions and square roots in the same order (Mul then Add, never a fused
// MulAdd; Div and Sqrt are correctly rounded on every target), and the same integer operations, on
// vectors of pixels. The pixels whose neighbours the vectors cannot load (the edge row's first two,
// each row's tail) go to the scalar definition.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/mlaa_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep

#include "hwy/highway.h"

#include "core/math-inl.h"
#include "passes/mlaa.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void MlaaLumaRow(const float* const rgb[3], size_t width, float exposureScale, float* luma) {
  const DF df;
  const size_t lanes = hn::Lanes(df);
  const VF kr = hn::Set(df, 0.2126f), kg = hn::Set(df, 0.7152f), kb = hn::Set(df, 0.0722f);
  const VF scale = hn::Set(df, exposureScale), one = hn::Set(df, 1.0f);
  size_t x = 0;
  for (; x + lanes <= width; x += lanes) {
    const VF r = hn::LoadU(df, rgb[0] + x), g = hn::LoadU(df, rgb[1] + x), b = hn::LoadU(df, rgb[2] + x);
    const VF y = hn::Add(hn::Add(hn::Mul(kr, r), hn::Mul(kg, g)), hn::Mul(kb, b));
    const VF t = SanitizeRadianceV(hn::Mul(y, scale));
    hn::StoreU(hn::Sqrt(hn::Div(t, hn::Add(one, t))), df, luma + x);
  }
  if (x < width) {
    const float* const tail[3] = {rgb[0] + x, rgb[1] + x, rgb[2] + x};
    MlaaLumaRowScalar(tail, width - x, exposureScale, luma + x);
  }
}

void MlaaEdgeRow(const float* const rows[4], size_t width, float threshold, uint32_t* edges) {
  const DF df;
  const DU du;
  const size_t lanes = hn::Lanes(df);
  const size_t head = width < 2 ? width : 2;
  MlaaEdgePixelsScalar(rows, width, threshold, 0, head, edges);
  const VF limit = hn::Set(df, threshold), two = hn::Set(df, 2.0f);
  const auto leftBit = hn::Set(du, kMlaaLeftEdge), topBit = hn::Set(du, kMlaaTopEdge);
  size_t x = head;
  for (; x + lanes < width; x += lanes) {
    const VF l = hn::LoadU(df, rows[2] + x), left = hn::LoadU(df, rows[2] + x - 1);
    const VF up = hn::LoadU(df, rows[1] + x);
    const VF toLeft = hn::Abs(hn::Sub(l, left)), toUp = hn::Abs(hn::Sub(l, up));
    const VF toRight = hn::Abs(hn::Sub(l, hn::LoadU(df, rows[2] + x + 1)));
    const VF toDown = hn::Abs(hn::Sub(l, hn::LoadU(df, rows[3] + x)));
    const VF leftToLeft = hn::Abs(hn::Sub(left, hn::LoadU(df, rows[2] + x - 2)));
    const VF upToUp = hn::Abs(hn::Sub(up, hn::LoadU(df, rows[0] + x)));
    // Differences of finite luma are finite and >= 0: Max is the scalar's std::max.
    const VF largest = hn::Max(hn::Max(hn::Max(toLeft, toUp), hn::Max(toRight, toDown)), hn::Max(leftToLeft, upToUp));
    const auto leftEdge = hn::And(hn::Ge(toLeft, limit), hn::Le(largest, hn::Mul(two, toLeft)));
    const auto topEdge = hn::And(hn::Ge(toUp, limit), hn::Le(largest, hn::Mul(two, toUp)));
    const auto bits = hn::Or(hn::IfThenElseZero(hn::RebindMask(du, leftEdge), leftBit),
                             hn::IfThenElseZero(hn::RebindMask(du, topEdge), topBit));
    hn::StoreU(bits, du, edges + x);
  }
  MlaaEdgePixelsScalar(rows, width, threshold, x, width, edges);
}

size_t MlaaCoverageRow(const uint32_t* weights, const uint32_t* below, size_t width, uint32_t* coverage) {
  const DU du;
  const DI di;
  const size_t lanes = hn::Lanes(du);
  const auto byte = hn::Set(du, 255u);
  size_t x = 0, blended = 0;
  for (; x + lanes < width; x += lanes) {
    const auto own = hn::LoadU(du, weights + x);
    const auto left = hn::And(hn::ShiftRight<8>(own), byte), right = hn::And(hn::LoadU(du, weights + x + 1), byte);
    const auto up = hn::ShiftRight<24>(own), down = hn::And(hn::ShiftRight<16>(hn::LoadU(du, below + x)), byte);
    // Shares are at most 255: signed comparisons of them are the scalar's unsigned ones.
    const auto horizontal = hn::Gt(hn::BitCast(di, hn::Max(left, right)), hn::BitCast(di, hn::Max(up, down)));
    const auto word = hn::IfThenElse(hn::RebindMask(du, horizontal), hn::Or(left, hn::ShiftLeft<8>(right)),
                                     hn::Or(hn::ShiftLeft<16>(up), hn::ShiftLeft<24>(down)));
    hn::StoreU(word, du, coverage + x);
    blended += hn::CountTrue(du, hn::Ne(word, hn::Zero(du)));
  }
  return blended + MlaaCoveragePixelsScalar(weights, below, width, x, width, coverage);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(MlaaLumaRow);
HWY_EXPORT(MlaaEdgeRow);
HWY_EXPORT(MlaaCoverageRow);

void MlaaLumaRowSimd(const float* const rgb[3], size_t width, float exposureScale, float* luma) {
  HWY_DYNAMIC_DISPATCH(MlaaLumaRow)(rgb, width, exposureScale, luma);
}

void MlaaEdgeRowSimd(const float* const rows[4], size_t width, float threshold, uint32_t* edges) {
  HWY_DYNAMIC_DISPATCH(MlaaEdgeRow)(rows, width, threshold, edges);
}

size_t MlaaCoverageRowSimd(const uint32_t* weights, const uint32_t* below, size_t width, uint32_t* coverage) {
  return HWY_DYNAMIC_DISPATCH(MlaaCoverageRow)(weights, below, width, coverage);
}

}  // namespace ssgi
#endif
