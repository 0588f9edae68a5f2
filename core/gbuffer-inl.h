// Highway twins of the G-buffer's normal encoding and unpacking (core/gbuffer.h) for the passes' SIMD kernels: the same
// operations in the same order as the scalar functions, so every target gives their bits (docs/design.md
// §11; tests/core/gbuffer_simd_test.cpp checks every code). Lanes are pixels.
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_GBUFFER_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_GBUFFER_INL_H_
#undef SSGI_CORE_GBUFFER_INL_H_
#else
#define SSGI_CORE_GBUFFER_INL_H_
#endif

#include "core/gbuffer.h"
#include "core/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// DequantizeSigned: float(code) / maxCode * 2 - 1, for codes below 2^24 (exact as floats).
template <class D>
hn::Vec<D> DequantizeSignedV(D d, hn::Vec<hn::RebindToUnsigned<D>> code, float maxCode) {
  const hn::RebindToSigned<D> di;
  const auto value = hn::ConvertTo(d, hn::BitCast(di, code));
  return hn::Sub(hn::Mul(hn::Div(value, hn::Set(d, maxCode)), hn::Set(d, 2.0f)), hn::Set(d, 1.0f));
}

// UnpackNormal(word1, encoding): the unit view-space normal of word 1's low 24 bits.
template <class D>
Vec3V<D> UnpackNormalV(D d, hn::Vec<hn::RebindToUnsigned<D>> word1, NormalEncoding encoding) {
  const hn::RebindToUnsigned<D> du;
  Vec3V<D> n;
  if (encoding == NormalEncoding::kXyz8) {
    const auto byte = hn::Set(du, 0xFFu);
    n.x = DequantizeSignedV(d, hn::And(word1, byte), 255.0f);
    n.y = DequantizeSignedV(d, hn::And(hn::ShiftRight<8>(word1), byte), 255.0f);
    n.z = DequantizeSignedV(d, hn::And(hn::ShiftRight<16>(word1), byte), 255.0f);
  } else {
    const auto twelveBits = hn::Set(du, 0xFFFu);
    const auto zero = hn::Zero(d);
    n.x = DequantizeSignedV(d, hn::And(word1, twelveBits), 4095.0f);
    n.y = DequantizeSignedV(d, hn::And(hn::ShiftRight<12>(word1), twelveBits), 4095.0f);
    n.z = hn::Sub(hn::Sub(hn::Set(d, 1.0f), hn::Abs(n.x)), hn::Abs(n.y));
    const auto t = hn::Max(hn::Neg(n.z), zero);
    n.x = hn::IfThenElse(hn::Ge(n.x, zero), hn::Sub(n.x, t), hn::Add(n.x, t));
    n.y = hn::IfThenElse(hn::Ge(n.y, zero), hn::Sub(n.y, t), hn::Add(n.y, t));
  }
  const auto length = hn::Sqrt(hn::Add(hn::Add(hn::Mul(n.x, n.x), hn::Mul(n.y, n.y)), hn::Mul(n.z, n.z)));
  return {hn::Div(n.x, length), hn::Div(n.y, length), hn::Div(n.z, length)};
}

// QuantizeSigned (core/gbuffer.cpp): value clamped to [-1, 1] (NaN to -1), then
// uint((clamped * 0.5 + 0.5) * maxCode + 0.5).
template <class D>
hn::Vec<hn::RebindToUnsigned<D>> QuantizeSignedV(D d, hn::Vec<D> value, float maxCode) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto one = hn::Set(d, 1.0f), minusOne = hn::Set(d, -1.0f), half = hn::Set(d, 0.5f);
  const auto clamped =
      hn::IfThenElse(hn::Gt(value, minusOne), hn::IfThenElse(hn::Gt(value, one), one, value), minusOne);
  const auto scaled = hn::Add(hn::Mul(hn::Add(hn::Mul(clamped, half), half), hn::Set(d, maxCode)), half);
  return hn::BitCast(du, hn::ConvertTo(di, scaled));
}

// EncodeNormal(n, encoding): the 24-bit code of a unit normal.
template <class D>
hn::Vec<hn::RebindToUnsigned<D>> EncodeNormalV(D d, const Vec3V<D>& n, NormalEncoding encoding) {
  if (encoding == NormalEncoding::kXyz8) {
    return hn::Or(hn::Or(QuantizeSignedV(d, n.x, 255.0f), hn::ShiftLeft<8>(QuantizeSignedV(d, n.y, 255.0f))),
                  hn::ShiftLeft<16>(QuantizeSignedV(d, n.z, 255.0f)));
  }
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const auto l1 = hn::Add(hn::Add(hn::Abs(n.x), hn::Abs(n.y)), hn::Abs(n.z));
  auto u = hn::Div(n.x, l1);
  auto v = hn::Div(n.y, l1);
  // The lower hemisphere folds over the diagonals; SignNotZero(t) = t >= 0 ? 1 : -1.
  const auto foldedU = hn::Mul(hn::Sub(one, hn::Abs(v)), hn::IfThenElse(hn::Ge(u, zero), one, hn::Neg(one)));
  const auto foldedV = hn::Mul(hn::Sub(one, hn::Abs(u)), hn::IfThenElse(hn::Ge(v, zero), one, hn::Neg(one)));
  const auto lower = hn::Lt(n.z, zero);
  u = hn::IfThenElse(lower, foldedU, u);
  v = hn::IfThenElse(lower, foldedV, v);
  return hn::Or(QuantizeSignedV(d, u, 4095.0f), hn::ShiftLeft<12>(QuantizeSignedV(d, v, 4095.0f)));
}

// UnpackAlbedo: the linear value of each 8-bit sRGB code, gathered from `srgbDecodeTable`
// (SrgbDecodeTableForKernels(), core/color.h), the table SrgbCodeToLinear reads.
template <class D>
Vec3V<D> UnpackAlbedoV(D d, hn::Vec<hn::RebindToUnsigned<D>> word0, const float* srgbDecodeTable) {
  const hn::RebindToSigned<D> di;
  const auto byte = hn::Set(di, 0xFF);
  const auto codes = hn::BitCast(di, word0);
  hn::Vec<D> albedo[3];
  const auto r = hn::And(codes, byte), g = hn::And(hn::ShiftRight<8>(codes), byte);
  GatherNearIndex3(d, srgbDecodeTable, 256, {r, g, hn::And(hn::ShiftRight<16>(codes), byte)}, albedo);
  return {albedo[0], albedo[1], albedo[2]};
}

// UnpackMetallic: float(word0 >> 24) / 255.
template <class D>
hn::Vec<D> UnpackMetallicV(D d, hn::Vec<hn::RebindToUnsigned<D>> word0) {
  const hn::RebindToSigned<D> di;
  return hn::Div(hn::ConvertTo(d, hn::BitCast(di, hn::ShiftRight<24>(word0))), hn::Set(d, 255.0f));
}

// UnpackRoughness: float(word1 >> 24) / 255.
template <class D>
hn::Vec<D> UnpackRoughnessV(D d, hn::Vec<hn::RebindToUnsigned<D>> word1) {
  const hn::RebindToSigned<D> di;
  return hn::Div(hn::ConvertTo(d, hn::BitCast(di, hn::ShiftRight<24>(word1))), hn::Set(d, 255.0f));
}

// UnpackDepth: word 2's bits as the view depth.
template <class D>
hn::Vec<D> UnpackDepthV(D d, hn::Vec<hn::RebindToUnsigned<D>> word2) {
  return hn::BitCast(d, word2);
}

// UnpackHardShadow(word3): bit 31, as a mask.
template <class D>
hn::Mask<D> UnpackHardShadowV(D d, hn::Vec<hn::RebindToUnsigned<D>> word3) {
  const hn::RebindToSigned<D> di;
  return hn::RebindMask(d, hn::Lt(hn::BitCast(di, word3), hn::Zero(di)));
}

// UnpackBlockerDistance(word3): bits 0-30 as a float.
template <class D>
hn::Vec<D> UnpackBlockerDistanceV(D d, hn::Vec<hn::RebindToUnsigned<D>> word3) {
  const hn::RebindToUnsigned<D> du;
  return hn::BitCast(d, hn::And(word3, hn::Set(du, 0x7FFFFFFFu)));
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_GBUFFER_INL_H_
