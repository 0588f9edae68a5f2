// Highway twin of SampleTexture (core/texture.h) for the passes' SIMD kernels: lanes are lookups into
// one texture, each at its own UV, footprint and so mip level; the same operations in the same order
// as the scalar sampler (core/texture.cpp), so every target gives its bits (tests/core/
// texture_simd_test.cpp).
//
// A per-target header in Highway's "-inl.h" convention: a *_simd.cpp includes it after
// hwy/highway.h, once per target through hwy/foreach_target.h, outside any namespace.
#if defined(SSGI_CORE_TEXTURE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SSGI_CORE_TEXTURE_INL_H_
#undef SSGI_CORE_TEXTURE_INL_H_
#else
#define SSGI_CORE_TEXTURE_INL_H_
#endif

#include "core/math-inl.h"
#include "core/texture.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// RGBA per lane.
struct Vec4V {
  VF r, g, b, a;
};

// texture.cpp's Log2 for x > 1 (normal, finite): exponent and mantissa from the bits, then the
// atanh series of ln. Other lanes compute along, unused.
HWY_INLINE VF Log2V(VF x) {
  const DF df;
  const DI di;
  const VI bits = hn::BitCast(di, x);
  const VI exponentMinusOne = hn::Sub(hn::And(hn::ShiftRight<23>(bits), hn::Set(di, 0xFF)), hn::Set(di, 127));
  const VF mantissa = hn::BitCast(df, hn::Or(hn::And(bits, hn::Set(di, 0x7FFFFF)), hn::Set(di, 0x3F800000)));
  const VF one = hn::Set(df, 1.0f);
  const VF s = hn::Div(hn::Sub(mantissa, one), hn::Add(mantissa, one));
  const VF s2 = hn::Mul(s, s);
  VF series = hn::Mul(s2, hn::Set(df, 1.0f / 11.0f));
  series = hn::Mul(s2, hn::Add(hn::Set(df, 1.0f / 9.0f), series));
  series = hn::Mul(s2, hn::Add(hn::Set(df, 1.0f / 7.0f), series));
  series = hn::Mul(s2, hn::Add(hn::Set(df, 1.0f / 5.0f), series));
  series = hn::Mul(s2, hn::Add(hn::Set(df, 1.0f / 3.0f), series));
  series = hn::Add(one, series);
  constexpr float kInvLn2 = 1.44269504f;
  return hn::Add(hn::ConvertTo(df, exponentMinusOne),
                 hn::Mul(hn::Mul(hn::Mul(hn::Set(df, 2.0f), s), series), hn::Set(df, kInvLn2)));
}

// WrapIndex: i + size below 0, i - size from size on.
HWY_INLINE VI WrapIndexV(VI i, VI size) {
  const DI di;
  return hn::IfThenElse(hn::Lt(i, hn::Zero(di)), hn::Add(i, size),
                        hn::IfThenElse(hn::Lt(i, size), i, hn::Sub(i, size)));
}

// EdgeIndex (texture.cpp): WrapIndexV for kRepeat, else clamped to [0, size - 1].
HWY_INLINE VI EdgeIndexV(VI i, VI size, TextureWrap wrap) {
  const DI di;
  if (wrap == TextureWrap::kRepeat) return WrapIndexV(i, size);
  return hn::Max(hn::Min(i, hn::Sub(size, hn::Set(di, 1))), hn::Zero(di));
}

// WrapCoordinate (texture.cpp): the coordinate in [0, 1] under `wrap`, 0 where it is not finite.
HWY_INLINE VF WrapCoordinateV(VF x, TextureWrap wrap) {
  const DF df;
  const VF one = hn::Set(df, 1.0f);
  VF wrapped;
  if (wrap == TextureWrap::kClamp) {
    wrapped = hn::Min(hn::Max(x, hn::Zero(df)), one);
  } else if (wrap == TextureWrap::kMirror) {
    const VF t = hn::Sub(x, hn::Mul(hn::Set(df, 2.0f), hn::Floor(hn::Mul(x, hn::Set(df, 0.5f)))));
    wrapped = hn::IfThenElse(hn::Gt(t, one), hn::Sub(hn::Set(df, 2.0f), t), t);
  } else {
    wrapped = hn::Sub(x, hn::Floor(x));
  }
  return hn::IfThenElseZero(hn::IsFinite(x), wrapped);
}

// The decoded texel of each lane's 32-bit word.
HWY_INLINE Vec4V DecodeTexelV(const TextureView& view, hn::Vec<DU> word) {
  const DF df;
  const DI di;
  const auto byte = hn::Set(DU(), 0xFFu);
  const auto code = [&](auto shifted) { return hn::BitCast(di, hn::And(shifted, byte)); };
  return {LookupTable256(df, view.colour, code(word)), LookupTable256(df, view.colour, code(hn::ShiftRight<8>(word))),
          LookupTable256(df, view.colour, code(hn::ShiftRight<16>(word))),
          LookupTable256(df, view.alpha, hn::BitCast(di, hn::ShiftRight<24>(word)))};
}

// The words of the texels (x0, y) and (x1, y) of each lane, `rowStart` the index of its (0, y). Where
// every lane's x1 is x0 + 1 (not wrapped), the two are neighbours in memory: one 64-bit gather of
// half the lanes reads both, half the elements of two 32-bit gathers (a gather's time goes with its
// elements).
HWY_INLINE void TexelWordPairV(const TextureView& view, VI rowStart, VI x0, VI x1, bool neighbours,
                               hn::Vec<DU>& word0, hn::Vec<DU>& word1) {
  const DU du;
#if HWY_TARGET != HWY_SCALAR  // one lane: no halves
  if (neighbours) {
    const hn::Half<DI> dh;
    const hn::Repartition<int64_t, DI> dl;
    const hn::Repartition<uint64_t, DI> dw;
    const VI first = hn::Add(rowStart, x0);
    const auto bytes = [&](auto half) { return hn::ShiftLeft<2>(hn::PromoteTo(dl, half)); };
    const uint64_t* texels = reinterpret_cast<const uint64_t*>(view.texels);
    const auto lower = hn::BitCast(du, hn::GatherOffset(dw, texels, bytes(hn::LowerHalf(dh, first))));
    const auto upper = hn::BitCast(du, hn::GatherOffset(dw, texels, bytes(hn::UpperHalf(dh, first))));
    word0 = hn::ConcatEven(du, upper, lower);
    word1 = hn::ConcatOdd(du, upper, lower);
    return;
  }
#else
  (void)neighbours;
#endif
  word0 = hn::GatherIndex(du, view.texels, hn::Add(rowStart, x0));
  word1 = hn::GatherIndex(du, view.texels, hn::Add(rowStart, x1));
}

// a * (1 - f) + b * f per channel, as glm's vec4 arithmetic.
HWY_INLINE Vec4V LerpV(const Vec4V& a, const Vec4V& b, VF f) {
  const VF keep = hn::Sub(hn::Set(DF(), 1.0f), f);
  const auto lerp = [&](VF x, VF y) { return hn::Add(hn::Mul(x, keep), hn::Mul(y, f)); };
  return {lerp(a.r, b.r), lerp(a.g, b.g), lerp(a.b, b.b), lerp(a.a, b.a)};
}

// SampleBilinear at each lane's level (u, v in [0, 1]).
HWY_INLINE Vec4V SampleBilinearV(const TextureView& view, VI level, VF u, VF v) {
  const DF df;
  const DI di;
  const VI width = LookupSmallTable<kMaxTextureLevels>(di, view.width, level);
  const VI height = LookupSmallTable<kMaxTextureLevels>(di, view.height, level);
  const VI offset = LookupSmallTable<kMaxTextureLevels>(di, view.offset, level);
  const VF half = hn::Set(df, 0.5f);
  const VF x = hn::Sub(hn::Mul(u, hn::ConvertTo(df, width)), half);
  const VF y = hn::Sub(hn::Mul(hn::Sub(hn::Set(df, 1.0f), v), hn::ConvertTo(df, height)), half);
  const VF x0 = hn::Floor(x), y0 = hn::Floor(y);
  const VF fx = hn::Sub(x, x0), fy = hn::Sub(y, y0);
  const VI one = hn::Set(di, 1);
  const VI ix = hn::ConvertTo(di, x0), iy = hn::ConvertTo(di, y0);
  const VI ix0 = EdgeIndexV(ix, width, view.wrapU), ix1 = EdgeIndexV(hn::Add(ix, one), width, view.wrapU);
  const VI iy0 = EdgeIndexV(iy, height, view.wrapV), iy1 = EdgeIndexV(hn::Add(iy, one), height, view.wrapV);
  const bool neighbours = hn::AllTrue(di, hn::Eq(ix1, hn::Add(ix0, one)));
  hn::Vec<DU> word[4];  // (ix0, iy0), (ix1, iy0), (ix0, iy1), (ix1, iy1)
  TexelWordPairV(view, hn::Add(offset, hn::Mul(iy0, width)), ix0, ix1, neighbours, word[0], word[1]);
  TexelWordPairV(view, hn::Add(offset, hn::Mul(iy1, width)), ix0, ix1, neighbours, word[2], word[3]);
  const Vec4V top = LerpV(DecodeTexelV(view, word[0]), DecodeTexelV(view, word[1]), fx);
  const Vec4V bottom = LerpV(DecodeTexelV(view, word[2]), DecodeTexelV(view, word[3]), fx);
  return LerpV(top, bottom, fy);
}

// SampleTexture(texture, (u, v), footprint) per lane, every lane of `view`'s texture.
HWY_INLINE Vec4V SampleTextureV(const TextureView& view, VF u, VF v, VF footprint) {
  const DF df;
  const DI di;
  const VF zero = hn::Zero(df);
  const VF scaled = hn::Mul(footprint, hn::Set(df, view.baseSide));
  // A zero or NaN footprint fails both tests: level 0.
  VF lambda = hn::IfThenElse(hn::Gt(scaled, hn::Set(df, 1.0f)), Log2V(scaled), zero);
  lambda = hn::IfThenElse(hn::Ge(scaled, hn::Set(df, float(1 << view.lastLevel))), hn::Set(df, float(view.lastLevel)),
                          lambda);
  u = WrapCoordinateV(u, view.wrapU);
  v = WrapCoordinateV(v, view.wrapV);
  const VI level = hn::ConvertTo(di, lambda);
  const VF blend = hn::Sub(lambda, hn::ConvertTo(df, level));
  const Vec4V fine = SampleBilinearV(view, level, u, v);
  const auto exact = hn::Eq(blend, zero);
  if (hn::AllTrue(df, exact)) return fine;
  // Lanes on an exact level take it alone; the others' next level exists (lambda < lastLevel).
  const VI next = hn::Min(hn::Add(level, hn::Set(di, 1)), hn::Set(di, view.lastLevel));
  const Vec4V mixed = LerpV(fine, SampleBilinearV(view, next, u, v), blend);
  return {hn::IfThenElse(exact, fine.r, mixed.r), hn::IfThenElse(exact, fine.g, mixed.g),
          hn::IfThenElse(exact, fine.b, mixed.b), hn::IfThenElse(exact, fine.a, mixed.a)};
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#endif  // SSGI_CORE_TEXTURE_INL_H_
