// The Highway twins of the bounce pass's row kernels (bounce.cpp): lanes are neighbouring pixels of a
// row. The same operations in the same order as the scalar definitions (no fused multiply-add, no
// approximate division or square root, std::min / std::max / std::clamp semantics, the acos of
// core/fast_math.h), so every target gives the scalar bytes (tests/passes/bounce_test.cpp checks
// each compiled target). Where a lane's pixel skips a step (no geometry, a tap off the image or on
// the background, no newly covered sector), the vector computes along and adds a selected zero: the
// sums hold only values >= +0, to which adding +0 changes no bit.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/bounce_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include <algorithm>
#include <cstring>

#include "core/color.h"
#include "core/gbuffer-inl.h"
#include "core/math-inl.h"
#include "core/row-inl.h"
#include "passes/bounce.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using MI = hn::Mask<DI>;
using VU = hn::Vec<DU>;

constexpr float kHalfPi = 1.57079633f;

HWY_INLINE MF HasGeometryV(VF d) {
  const DF df;
  return hn::And(hn::Ge(d, hn::Set(df, kBounceMinDepth)), hn::Le(d, hn::Set(df, kBounceMaxDepth)));
}

// Ray (bounce.cpp) at full-resolution positions (x, y) per lane.
HWY_INLINE Vec3V<DF> RayV(const BounceSetup& setup, VF x, VF y) {
  const DF df;
  const VF half = hn::Set(df, 0.5f);
  return {hn::Add(hn::Mul(hn::Add(x, half), hn::Set(df, setup.rayScaleX)), hn::Set(df, setup.rayOffsetX)),
          hn::Add(hn::Mul(hn::Add(y, half), hn::Set(df, setup.rayScaleY)), hn::Set(df, setup.rayOffsetY)),
          hn::Set(df, -1.0f)};
}

// ViewPosition (bounce.cpp) of full-resolution columns x (per lane, as exact floats) on row y.
HWY_INLINE Vec3V<DF> ViewPositionV(const BounceSetup& setup, VF x, VF y, VF d) {
  const Vec3V<DF> ray = RayV(setup, x, y);
  return {hn::Mul(d, ray.x), hn::Mul(d, ray.y), hn::Neg(d)};
}

// Values start, start + 1, ... of a row of `count` values, for any start (negative too); lanes
// outside the row hold `fill`.
template <class D>
HWY_INLINE hn::Vec<D> LoadShifted(D d, const hn::TFromD<D>* row, ptrdiff_t start, size_t count, hn::TFromD<D> fill) {
  const ptrdiff_t lanes = ptrdiff_t(hn::Lanes(d));
  if (start >= 0 && start + lanes <= ptrdiff_t(count)) return hn::LoadU(d, row + start);
  HWY_ALIGN hn::TFromD<D> buffer[hn::MaxLanes(D())];
  for (ptrdiff_t l = 0; l < lanes; ++l) {
    const ptrdiff_t at = start + l;
    buffer[l] = at >= 0 && at < ptrdiff_t(count) ? row[at] : fill;
  }
  return hn::Load(d, buffer);
}

// Full-resolution values 2i of a row of `fullCount` for the half-resolution lanes i = half0, half0
// + 1, ...: the even ones.
template <class D>
HWY_INLINE hn::Vec<D> LoadEven(D d, const hn::TFromD<D>* row, size_t half0, size_t fullCount, hn::TFromD<D> fill) {
  const size_t lanes = hn::Lanes(d);
  HWY_ALIGN hn::TFromD<D> buffer[2 * hn::MaxLanes(D())];
  const hn::TFromD<D>* source = row + 2 * half0;
  if (2 * (half0 + lanes) > fullCount) {
    for (size_t l = 0; l < 2 * lanes; ++l) buffer[l] = 2 * half0 + l < fullCount ? source[l] : fill;
    source = buffer;
  }
  hn::Vec<D> even, odd;
  hn::LoadInterleaved2(d, source, even, odd);
  return even;
}

// ---------------------------------------------------------------------------------------------
// Prepare.

void PrepareRow(const BounceSetup& setup, const uint32_t* word1Row, const uint32_t* word2Row,
                const float* const litRow[3], float* depth, float* const normal[3], uint32_t* normalCode,
                float* const lit[3]) {
  const DF df;
  const DU du;
  const size_t count = size_t(setup.halfWidth), fullCount = size_t(setup.width);
  for (size_t i = 0; i < count; i += hn::Lanes(df)) {
    const VF d = UnpackDepthV(df, LoadEven(du, word2Row, i, fullCount, PackDepth(kBackgroundDepth)));
    const MF geometry = HasGeometryV(d);
    StoreRow(hn::IfThenElse(geometry, d, hn::Set(df, kBackgroundDepth)), df, depth, i, count);
    const VU word1 = LoadEven(du, word1Row, i, fullCount, 0u);
    const Vec3V<DF> n = UnpackNormalV(df, word1, setup.encoding);
    StoreRow(hn::IfThenElseZero(geometry, n.x), df, normal[0], i, count);
    StoreRow(hn::IfThenElseZero(geometry, n.y), df, normal[1], i, count);
    StoreRow(hn::IfThenElseZero(geometry, n.z), df, normal[2], i, count);
    StoreRow(hn::IfThenElseZero(hn::RebindMask(du, geometry), hn::And(word1, hn::Set(du, 0xFFFFFFu))), du, normalCode,
             i, count);
    for (int c = 0; c < 3; ++c)
      StoreRow(SanitizeRadianceV(LoadEven(df, litRow[c], i, fullCount, 0.0f)), df, lit[c], i, count);
  }
}

// ---------------------------------------------------------------------------------------------
// March.

// Slice (bounce.cpp) per lane.
struct SliceV {
  Vec3V<DF> o;
  VF halfCos, halfSin, cosGamma, sinGamma, q0, invI, weight;
};

HWY_INLINE SliceV MakeSliceV(const Vec3V<DF>& v, const Vec3V<DF>& n, VF cx, VF cy) {
  const DF df;
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f);
  SliceV s;
  const VF dv = hn::Sub(hn::Mul(cx, v.x), hn::Mul(cy, v.y));
  const Vec3V<DF> along{hn::Sub(cx, hn::Mul(dv, v.x)), hn::Sub(hn::Neg(cy), hn::Mul(dv, v.y)),
                        hn::Neg(hn::Mul(dv, v.z))};
  const VF invAlong = hn::Div(one, hn::Sqrt(Dot3(along, along)));
  s.o = Scale3(along, invAlong);
  const VF no = Dot3(n, s.o), nv = Dot3(n, v);
  const VF projected = hn::Sqrt(hn::Add(hn::Mul(no, no), hn::Mul(nv, nv)));
  const MF facing = hn::And(hn::Gt(nv, zero), hn::Gt(projected, zero));
  s.cosGamma = hn::IfThenElseZero(facing, hn::Div(nv, projected));
  s.sinGamma = hn::IfThenElse(facing, hn::Div(no, projected), hn::IfThenElse(hn::Lt(no, zero), hn::Neg(one), one));
  const VF absGamma = AcosPolyV(s.cosGamma);
  const VF gamma = hn::IfThenElse(hn::Lt(s.sinGamma, zero), hn::Neg(absGamma), absGamma);
  s.halfCos = hn::Mul(half, s.cosGamma);
  s.halfSin = hn::Mul(half, s.sinGamma);
  const VF measure = hn::Add(s.cosGamma, hn::Mul(gamma, s.sinGamma));
  s.invI = hn::Div(one, measure);
  s.q0 = hn::Mul(hn::Add(s.cosGamma, hn::Mul(hn::Sub(gamma, hn::Set(df, kHalfPi)), s.sinGamma)), hn::Set(df, -0.5f));
  s.weight = hn::IfThenElseZero(hn::Gt(projected, zero), hn::Mul(projected, measure));
  return s;
}

// SectorPosition (bounce.cpp) per lane; (x, y) != (0, 0).
template <bool kPositive>
HWY_INLINE VF SectorPositionV(const SliceV& s, VF x, VF y) {
  const DF df;
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
  const VF length = hn::Sqrt(hn::Add(hn::Mul(x, x), hn::Mul(y, y)));
  const VF inv = hn::Div(one, length);
  const VF c = ClampStd(hn::Mul(y, inv), hn::Neg(one), one);
  const VF a = hn::Mul(hn::Abs(x), inv);
  const VF theta = AcosPolyV(c);
  const VF sideCos = hn::Mul(s.halfCos, hn::Mul(a, a));
  const VF q = hn::Add(kPositive ? sideCos : hn::Neg(sideCos), hn::Mul(s.halfSin, hn::Sub(theta, hn::Mul(c, a))));
  const VF sideSin = kPositive ? a : hn::Neg(a);
  const MF below = hn::Lt(hn::Add(hn::Mul(c, s.cosGamma), hn::Mul(sideSin, s.sinGamma)), zero);
  const VF u = ClampStd(hn::Mul(hn::Sub(q, s.q0), s.invI), zero, one);
  return hn::IfThenElse(below, kPositive ? one : zero, u);
}

// Below(k) (bounce.cpp) for k in [0, 32].
HWY_INLINE VU BelowV(VI k) {
  const DI di;
  const DU du;
  const VU shifted = hn::Shl(hn::Set(du, 1u), hn::BitCast(du, hn::Min(k, hn::Set(di, 31))));
  return hn::IfThenElse(hn::RebindMask(du, hn::Gt(k, hn::Set(di, 31))), hn::Set(du, 0xFFFFFFFFu),
                        hn::Sub(shifted, hn::Set(du, 1u)));
}

// SectorMask (bounce.cpp): lo and hi in [0, 1].
HWY_INLINE VU SectorMaskV(VF lo, VF hi, float sectors) {
  const DF df;
  const DI di;
  const VF n = hn::Set(df, sectors), half = hn::Set(df, 0.5f);
  const VI start = hn::ConvertTo(di, hn::Add(hn::Mul(lo, n), half));
  const VI end = hn::ConvertTo(di, hn::Add(hn::Mul(hi, n), half));
  return hn::AndNot(BelowV(start), BelowV(end));
}

// The state of one vector of pixels through the march.
struct MarchLanes {
  MF geometry;
  VF i, j;  // half-resolution coordinates, exact floats
  VF d;     // the depth (1 where there is none, so that no lane computes with infinity)
  Vec3V<DF> n, p, v;
  VF radius;
};

// RawNormal (bounce.cpp) per lane.
HWY_INLINE Vec3V<DF> RawNormalV(VU code, NormalEncoding encoding) {
  const DF df;
  const DI di;
  const DU du;
  const VF one = hn::Set(df, 1.0f);
  const auto dequantize = [&](VU bits, float scale) {
    return hn::Sub(hn::Mul(hn::ConvertTo(df, hn::BitCast(di, bits)), hn::Set(df, scale)), one);
  };
  if (encoding == NormalEncoding::kXyz8) {
    const VU byte = hn::Set(du, 0xFFu);
    return {dequantize(hn::And(code, byte), kBounceXyz8Scale),
            dequantize(hn::And(hn::ShiftRight<8>(code), byte), kBounceXyz8Scale),
            dequantize(hn::And(hn::ShiftRight<16>(code), byte), kBounceXyz8Scale)};
  }
  const VU twelveBits = hn::Set(du, 0xFFFu);
  VF x = dequantize(hn::And(code, twelveBits), kBounceOct24Scale);
  VF y = dequantize(hn::And(hn::ShiftRight<12>(code), twelveBits), kBounceOct24Scale);
  const VF z = hn::Sub(hn::Sub(one, hn::Abs(x)), hn::Abs(y));
  const VF zero = hn::Zero(df);
  const VF fold = MaxStd(hn::Neg(z), zero);
  x = hn::IfThenElse(hn::Ge(x, zero), hn::Sub(x, fold), hn::Add(x, fold));
  y = hn::IfThenElse(hn::Ge(y, zero), hn::Sub(y, fold), hn::Add(y, fold));
  return {x, y, z};
}

// One sample of a slice for a vector of pixels: where it lies and what it read, gathered before
// the slice's samples are folded in, so that the gathers' latencies overlap.
struct TapLanes {
  MF inside;        // live, and the sample's pixel is in the image
  VI index;         // the sample's pixel in the half-resolution planes (0 outside `inside`)
  VF tx, ty;        // the sample's pixel
  VF lineX, lineY;  // the sample on the slice's screen line
  VF depth;
};

HWY_INLINE TapLanes PlaceTap(const BounceSetup& setup, const BounceHalfView& half, const MarchLanes& m, MF live,
                             VF signedX, VF signedY) {
  const DF df;
  const DI di;
  const VF zero = hn::Zero(df), half5 = hn::Set(df, 0.5f);
  TapLanes t;
  t.lineX = hn::Add(m.i, signedX);
  t.lineY = hn::Add(m.j, signedY);
  t.tx = hn::Add(m.i, hn::Floor(hn::Add(signedX, half5)));
  t.ty = hn::Add(m.j, hn::Floor(hn::Add(signedY, half5)));
  const MF inside = hn::And(hn::And(hn::Ge(t.tx, zero), hn::Lt(t.tx, hn::Set(df, float(setup.halfWidth)))),
                            hn::And(hn::Ge(t.ty, zero), hn::Lt(t.ty, hn::Set(df, float(setup.halfHeight)))));
  t.inside = hn::And(live, inside);
  t.index = hn::IfThenElseZero(
      hn::RebindMask(di, t.inside),
      hn::Add(hn::Mul(hn::ConvertTo(di, t.ty), hn::Set(di, int32_t(half.stride))), hn::ConvertTo(di, t.tx)));
  t.depth = hn::AllFalse(df, t.inside) ? hn::Set(df, kBackgroundDepth) : hn::GatherIndex(df, half.depth, t.index);
  return t;
}

// Folds one placed sample of side kPositive into occluded and sliceBounce (MarchPixel's loop body).
template <bool kPositive>
HWY_INLINE void FoldTap(const BounceSetup& setup, const BounceHalfView& half, const MarchLanes& m, const SliceV& s,
                        const TapLanes& t, VU& occluded, Vec3V<DF>& sliceBounce) {
  const DF df;
  const DI di;
  const DU du;
  const VF zero = hn::Zero(df), half5 = hn::Set(df, 0.5f), two = hn::Set(df, 2.0f);
  MF occluding = hn::And(t.inside, HasGeometryV(t.depth));
  if (hn::AllFalse(df, occluding)) return;
  const VF depthUsed = hn::IfThenElse(occluding, t.depth, m.d);
  // Samples that barely rise above the pixel's tangent plane cover nothing (bounce.cpp).
  const Vec3V<DF> pixelRay = RayV(setup, hn::Mul(two, t.tx), hn::Mul(two, t.ty));
  const Vec3V<DF> own = Sub3(Scale3(pixelRay, depthUsed), m.p);
  const VF rise = Dot3(m.n, own);
  occluding = hn::And(occluding, hn::Gt(rise, zero));
  occluding = hn::AndNot(hn::Le(hn::Mul(hn::Mul(rise, rise), hn::Set(df, kBounceMinRiseInverseSquare)), Dot3(own, own)),
                         occluding);
  if (hn::AllFalse(df, occluding)) return;
  const Vec3V<DF> tapNormal = RawNormalV(hn::GatherIndex(du, half.normalCode, t.index), setup.encoding);
  // The line's ray meets the pixel's tangent plane (bounce.cpp).
  const Vec3V<DF> lineRay = RayV(setup, hn::Mul(two, t.lineX), hn::Mul(two, t.lineY));
  const VF ratio = hn::Div(Dot3(tapNormal, pixelRay), Dot3(tapNormal, lineRay));
  const MF onPlane = hn::And(hn::Ge(ratio, half5), hn::Le(ratio, two));
  const Vec3V<DF> point = IfThenElse3(onPlane, Scale3(lineRay, hn::Mul(depthUsed, ratio)), Scale3(pixelRay, depthUsed));
  const Vec3V<DF> delta = Sub3(point, m.p);
  VF x = Dot3(delta, s.o), y = Dot3(delta, m.v);
  occluding = hn::AndNot(hn::And(hn::Eq(x, zero), hn::Eq(y, zero)), occluding);
  // Lanes that do not occlude take a harmless direction, so no NaN reaches a conversion.
  x = hn::IfThenElse(occluding, x, hn::Set(df, 1.0f));
  y = hn::IfThenElseZero(occluding, y);
  const VF front = SectorPositionV<kPositive>(s, x, y);
  const VF back = SectorPositionV<kPositive>(s, x, hn::Sub(y, hn::Set(df, setup.thickness)));
  const VU mask = hn::IfThenElseZero(hn::RebindMask(du, occluding),
                                     SectorMaskV(MinStd(front, back), MaxStd(front, back), float(setup.sectors)));
  const VU fresh = hn::AndNot(occluded, mask);
  occluded = hn::Or(occluded, mask);
  const MF anyFresh = hn::RebindMask(df, hn::Ne(fresh, hn::Zero(du)));
  if (hn::AllFalse(df, anyFresh)) return;
  const MF lights = hn::And(anyFresh, hn::Lt(Dot3(tapNormal, delta), zero));
  if (hn::AllFalse(df, lights)) return;
  const VF count = hn::ConvertTo(df, hn::BitCast(di, hn::PopulationCount(fresh)));
  sliceBounce.x =
      hn::Add(sliceBounce.x, hn::IfThenElseZero(lights, hn::Mul(count, hn::GatherIndex(df, half.lit[0], t.index))));
  sliceBounce.y =
      hn::Add(sliceBounce.y, hn::IfThenElseZero(lights, hn::Mul(count, hn::GatherIndex(df, half.lit[1], t.index))));
  sliceBounce.z =
      hn::Add(sliceBounce.z, hn::IfThenElseZero(lights, hn::Mul(count, hn::GatherIndex(df, half.lit[2], t.index))));
}

HWY_ALIGN constexpr int32_t kBayerFlat[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};

// Each slice's direction and each step's spread for a vector of pixels of row j, from their
// per-pixel rotation (bounce.cpp).
struct SamplePattern {
  VF cx[kBounceMaxSlices], cy[kBounceMaxSlices], spread[kBounceMaxSteps];
};

HWY_INLINE void GatherSamplePattern(const BounceSetup& setup, int j, VI iv, SamplePattern& pattern) {
  const DF df;
  const DI di;
  const VI rotation = hn::GatherIndex(di, kBayerFlat, hn::Add(hn::Set(di, (j & 3) * 4), hn::And(iv, hn::Set(di, 3))));
  const VI jitter = hn::And(hn::Mul(rotation, hn::Set(di, 5)), hn::Set(di, 15));
  for (int k = 0; k < setup.slices; ++k) {
    pattern.cx[k] = hn::GatherIndex(df, setup.directionX + 16 * k, rotation);
    pattern.cy[k] = hn::GatherIndex(df, setup.directionY + 16 * k, rotation);
  }
  for (int step = 0; step < setup.steps; ++step)
    pattern.spread[step] = hn::GatherIndex(df, setup.stepSpread + 16 * step, jitter);
}

uint64_t MarchRow(const BounceSetup& setup, const BounceHalfView& half, int j, float* visibility,
                  float* const bounce[3]) {
  const DF df;
  const DI di;
  const DU du;
  const size_t lanes = hn::Lanes(df), count = size_t(setup.halfWidth);
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
  const size_t rowStart = size_t(j) * half.stride;
  const float sectors = float(setup.sectors);
  uint64_t taps = 0;
  // The rotation repeats every four pixels along the row: where a vector holds whole groups of four,
  // every vector of the row has the pattern of the first, gathered once.
  const bool periodic = lanes % 4 == 0;
  SamplePattern rowPattern, vectorPattern;
  if (periodic) GatherSamplePattern(setup, j, hn::Iota(di, 0), rowPattern);
  for (size_t i0 = 0; i0 < count; i0 += lanes) {
    MarchLanes m;
    const VI iv = hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(i0)));
    const VF depth = LoadRow(df, half.depth + rowStart, i0, count, kBackgroundDepth);
    m.geometry = HasGeometryV(depth);
    if (hn::AllFalse(df, m.geometry)) {
      StoreRow(one, df, visibility, i0, count);
      for (int c = 0; c < 3; ++c) StoreRow(zero, df, bounce[c], i0, count);
      continue;
    }
    m.i = hn::ConvertTo(df, iv);
    m.j = hn::Set(df, float(j));
    m.d = hn::IfThenElse(m.geometry, depth, one);
    m.n = {LoadRow(df, half.normal[0] + rowStart, i0, count, 0.0f),
           LoadRow(df, half.normal[1] + rowStart, i0, count, 0.0f),
           LoadRow(df, half.normal[2] + rowStart, i0, count, 0.0f)};
    const VF two = hn::Set(df, 2.0f);
    m.p = ViewPositionV(setup, hn::Mul(two, m.i), hn::Set(df, 2.0f * float(j)), m.d);
    const VF invLength = hn::Div(one, hn::Sqrt(Dot3(m.p, m.p)));
    m.v = Neg3(Scale3(m.p, invLength));
    m.radius =
        hn::Mul(MinStd(hn::Div(hn::Set(df, setup.radiusPixelsAtUnitDepth), m.d), hn::Set(df, setup.maxRadiusPixels)),
                hn::Set(df, 0.5f));
    if (!periodic) GatherSamplePattern(setup, j, iv, vectorPattern);
    const SamplePattern& pattern = periodic ? rowPattern : vectorPattern;

    VF weightSum = zero, visibilitySum = zero;
    Vec3V<DF> bounceSum{zero, zero, zero};
    for (int k = 0; k < setup.slices; ++k) {
      const VF cx = pattern.cx[k], cy = pattern.cy[k];
      const SliceV slice = MakeSliceV(m.v, m.n, cx, cy);
      const MF live = hn::And(m.geometry, hn::Gt(slice.weight, zero));
      if (hn::AllFalse(df, live)) continue;
      VU occluded = hn::Zero(du);
      Vec3V<DF> sliceBounce{zero, zero, zero};
      TapLanes placed[2 * kBounceMaxSteps];
      for (int step = 0; step < setup.steps; ++step) {
        const VF distance = hn::Add(hn::Set(df, kBounceMinTapDistance), hn::Mul(pattern.spread[step], m.radius));
        const VF offsetX = hn::Mul(distance, cx), offsetY = hn::Mul(distance, cy);
        placed[2 * step] = PlaceTap(setup, half, m, live, offsetX, offsetY);
        placed[2 * step + 1] = PlaceTap(setup, half, m, live, hn::Neg(offsetX), hn::Neg(offsetY));
        taps += hn::CountTrue(df, placed[2 * step].inside) + hn::CountTrue(df, placed[2 * step + 1].inside);
      }
      for (int step = 0; step < setup.steps; ++step) {
        FoldTap<true>(setup, half, m, slice, placed[2 * step], occluded, sliceBounce);
        FoldTap<false>(setup, half, m, slice, placed[2 * step + 1], occluded, sliceBounce);
      }
      const VF visible = hn::Sub(
          one, hn::Div(hn::ConvertTo(df, hn::BitCast(di, hn::PopulationCount(occluded))), hn::Set(df, sectors)));
      weightSum = hn::Add(weightSum, hn::IfThenElseZero(live, slice.weight));
      visibilitySum = hn::Add(visibilitySum, hn::IfThenElseZero(live, hn::Mul(slice.weight, visible)));
      bounceSum = Add3(bounceSum, IfThenElse3(live, Scale3(sliceBounce, slice.weight), Vec3V<DF>{zero, zero, zero}));
    }
    const MF any = hn::Gt(weightSum, zero);
    StoreRow(hn::IfThenElse(any, hn::Div(visibilitySum, weightSum), one), df, visibility, i0, count);
    const VF norm = hn::Mul(weightSum, hn::Set(df, sectors));
    StoreRow(hn::IfThenElseZero(any, hn::Div(bounceSum.x, norm)), df, bounce[0], i0, count);
    StoreRow(hn::IfThenElseZero(any, hn::Div(bounceSum.y, norm)), df, bounce[1], i0, count);
    StoreRow(hn::IfThenElseZero(any, hn::Div(bounceSum.z, norm)), df, bounce[2], i0, count);
  }
  return taps;
}

// ---------------------------------------------------------------------------------------------
// Filter and upsample.

// MatchWeight (bounce.cpp) per lane.
HWY_INLINE VF MatchWeightV(const Vec3V<DF>& p, const Vec3V<DF>& n, VF invTolerance, const Vec3V<DF>& c,
                           const Vec3V<DF>& m) {
  const DF df;
  const VF zero = hn::Zero(df);
  const VF plane = MaxStd(zero, hn::Sub(hn::Set(df, 1.0f), hn::Mul(hn::Abs(Dot3(n, Sub3(c, p))), invTolerance)));
  const VF facing = MaxStd(zero, Dot3(n, m));
  const VF f2 = hn::Mul(facing, facing), f4 = hn::Mul(f2, f2);
  return hn::Mul(plane, hn::Mul(f4, f4));
}

void FilterRow(const BounceSetup& setup, const BounceHalfView& half, int j, bool vertical,
               const float* sourceVisibility, const float* const sourceBounce[3], float* visibility,
               float* const bounce[3]) {
  const DF df;
  const DI di;
  const size_t lanes = hn::Lanes(df), count = size_t(setup.halfWidth);
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), two = hn::Set(df, 2.0f);
  const size_t centreRow = size_t(j) * half.stride;
  for (size_t i0 = 0; i0 < count; i0 += lanes) {
    const VF depth = LoadRow(df, half.depth + centreRow, i0, count, kBackgroundDepth);
    const MF geometry = HasGeometryV(depth);
    if (hn::AllFalse(df, geometry)) {
      StoreRow(one, df, visibility, i0, count);
      for (int c = 0; c < 3; ++c) StoreRow(zero, df, bounce[c], i0, count);
      continue;
    }
    const VF d = hn::IfThenElse(geometry, depth, one);
    const VF i = hn::ConvertTo(df, hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(i0))));
    const Vec3V<DF> p = ViewPositionV(setup, hn::Mul(two, i), hn::Set(df, 2.0f * float(j)), d);
    const Vec3V<DF> n{LoadRow(df, half.normal[0] + centreRow, i0, count, 0.0f),
                      LoadRow(df, half.normal[1] + centreRow, i0, count, 0.0f),
                      LoadRow(df, half.normal[2] + centreRow, i0, count, 0.0f)};
    const VF invTolerance = hn::Div(one, hn::Mul(hn::Set(df, setup.depthTolerance), d));
    VF weightSum = zero, visibilitySum = zero;
    Vec3V<DF> bounceSum{zero, zero, zero};
    for (int t = -kBounceFilterRadius; t <= kBounceFilterRadius; ++t) {
      const int jj = vertical ? j + t : j;
      // A row outside the image adds weight 0 and value 0 at every lane: nothing.
      if (jj < 0 || jj >= setup.halfHeight) continue;
      const size_t row = size_t(jj) * half.stride;
      // Along a row the neighbours are the lanes shifted by t (LoadShifted fills those past either end
      // as background); along a column, the same lanes of another row.
      const ptrdiff_t start = vertical ? ptrdiff_t(i0) : ptrdiff_t(i0) + t;
      const VF neighbourDepth = LoadShifted(df, half.depth + row, start, count, kBackgroundDepth);
      const MF live = hn::And(geometry, HasGeometryV(neighbourDepth));
      const VF column = vertical ? i : hn::Add(i, hn::Set(df, float(t)));
      const Vec3V<DF> c = ViewPositionV(setup, hn::Mul(two, column), hn::Set(df, 2.0f * float(jj)),
                                        hn::IfThenElse(live, neighbourDepth, d));
      const Vec3V<DF> m{LoadShifted(df, half.normal[0] + row, start, count, 0.0f),
                        LoadShifted(df, half.normal[1] + row, start, count, 0.0f),
                        LoadShifted(df, half.normal[2] + row, start, count, 0.0f)};
      const VF weight = hn::IfThenElseZero(live, hn::Mul(hn::Set(df, kBounceFilterSpatial[t + kBounceFilterRadius]),
                                                         MatchWeightV(p, n, invTolerance, c, m)));
      const VF v = hn::IfThenElseZero(live, LoadShifted(df, sourceVisibility + row, start, count, 0.0f));
      const Vec3V<DF> b{hn::IfThenElseZero(live, LoadShifted(df, sourceBounce[0] + row, start, count, 0.0f)),
                        hn::IfThenElseZero(live, LoadShifted(df, sourceBounce[1] + row, start, count, 0.0f)),
                        hn::IfThenElseZero(live, LoadShifted(df, sourceBounce[2] + row, start, count, 0.0f))};
      weightSum = hn::Add(weightSum, weight);
      visibilitySum = hn::Add(visibilitySum, hn::Mul(weight, v));
      bounceSum = Add3(bounceSum, Scale3(b, weight));
    }
    StoreRow(hn::IfThenElse(geometry, hn::Div(visibilitySum, weightSum), one), df, visibility, i0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.x, weightSum)), df, bounce[0], i0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.y, weightSum)), df, bounce[1], i0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.z, weightSum)), df, bounce[2], i0, count);
  }
}

// The half-resolution values of row `row` at columns base + index (per lane; index in [0, Lanes)
// where there are two lanes or more).
struct CandidateRow {
  VF depth, visibility;
  Vec3V<DF> normal, bounce;
};

HWY_INLINE VF Pick(VF values, VI index, const float* row, size_t base) {
  const DF df;
  if (hn::Lanes(df) >= 2) return hn::TableLookupLanes(values, hn::IndicesFromVec(df, index));
  return hn::GatherIndex(df, row + base, index);
}

void UpsampleRow(const BounceSetup& setup, const BounceHalfView& half, int y, const uint32_t* word1Row,
                 const uint32_t* word2Row, float* visibility, float* const bounce[3]) {
  const DF df;
  const DI di;
  const DU du;
  const size_t lanes = hn::Lanes(df), count = size_t(setup.width), halfCount = size_t(setup.halfWidth);
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half5 = hn::Set(df, 0.5f);
  const int j0 = y >> 1, j1 = std::min(j0 + (y & 1), setup.halfHeight - 1);
  const float by0 = (y & 1) ? 0.5f : 1.0f, by1 = 1.0f - by0;
  for (size_t x0 = 0; x0 < count; x0 += lanes) {
    const VF depth = UnpackDepthV(df, LoadRow(du, word2Row, x0, count, PackDepth(kBackgroundDepth)));
    const MF geometry = HasGeometryV(depth);
    if (hn::AllFalse(df, geometry)) {
      StoreRow(one, df, visibility, x0, count);
      for (int c = 0; c < 3; ++c) StoreRow(zero, df, bounce[c], x0, count);
      continue;
    }
    const VF d = hn::IfThenElse(geometry, depth, one);
    const VI xi = hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(x0)));
    const Vec3V<DF> p = ViewPositionV(setup, hn::ConvertTo(df, xi), hn::Set(df, float(y)), d);
    const Vec3V<DF> n = UnpackNormalV(df, LoadRow(du, word1Row, x0, count, 0u), setup.encoding);
    const VF invTolerance = hn::Div(one, hn::Mul(hn::Set(df, setup.depthTolerance), d));
    const VI odd = hn::And(xi, hn::Set(di, 1));
    const VI i0 = hn::ShiftRight<1>(xi);
    const VI i1 = hn::Min(hn::Add(i0, odd), hn::Set(di, setup.halfWidth - 1));
    const VF bx0 = hn::IfThenElse(hn::RebindMask(df, hn::Eq(odd, hn::Set(di, 1))), half5, one);
    const VF bx1 = hn::Sub(one, bx0);
    const size_t base = x0 >> 1;
    const VI index[2] = {hn::Sub(i0, hn::Set(di, int32_t(base))), hn::Sub(i1, hn::Set(di, int32_t(base)))};
    const VF bx[2] = {bx0, bx1};
    const VF columns[2] = {hn::ConvertTo(df, hn::Add(i0, i0)), hn::ConvertTo(df, hn::Add(i1, i1))};
    VF weightSum = zero, visibilitySum = zero;
    Vec3V<DF> bounceSum{zero, zero, zero};
    const int rows[2] = {j0, j1};
    const float by[2] = {by0, by1};
    for (int r = 0; r < 2; ++r) {
      if (by[r] == 0.0f) continue;  // an even row's second row: weight 0, which adds nothing
      const size_t row = size_t(rows[r]) * half.stride;
      const VF rowDepth = LoadRow(df, half.depth + row, base, halfCount, kBackgroundDepth);
      const VF rowVisibility = LoadRow(df, half.filteredVisibility + row, base, halfCount, 1.0f);
      VF rowNormal[3], rowBounce[3];
      for (int c = 0; c < 3; ++c) {
        rowNormal[c] = LoadRow(df, half.normal[c] + row, base, halfCount, 0.0f);
        rowBounce[c] = LoadRow(df, half.filteredBounce[c] + row, base, halfCount, 0.0f);
      }
      for (int column = 0; column < 2; ++column) {
        const VI at = index[column];
        const VF candidateDepth = Pick(rowDepth, at, half.depth + row, base);
        const MF live = hn::And(geometry, HasGeometryV(candidateDepth));
        const Vec3V<DF> c = ViewPositionV(setup, columns[column], hn::Set(df, 2.0f * float(rows[r])),
                                          hn::IfThenElse(live, candidateDepth, d));
        const Vec3V<DF> m{Pick(rowNormal[0], at, half.normal[0] + row, base),
                          Pick(rowNormal[1], at, half.normal[1] + row, base),
                          Pick(rowNormal[2], at, half.normal[2] + row, base)};
        const VF match = hn::IfThenElseZero(live, MatchWeightV(p, n, invTolerance, c, m));
        const VF weight =
            hn::Mul(hn::Mul(bx[column], hn::Set(df, by[r])), hn::Add(match, hn::Set(df, kBounceUpsampleFloor)));
        weightSum = hn::Add(weightSum, weight);
        visibilitySum =
            hn::Add(visibilitySum, hn::Mul(weight, Pick(rowVisibility, at, half.filteredVisibility + row, base)));
        bounceSum.x = hn::Add(bounceSum.x, hn::Mul(weight, Pick(rowBounce[0], at, half.filteredBounce[0] + row, base)));
        bounceSum.y = hn::Add(bounceSum.y, hn::Mul(weight, Pick(rowBounce[1], at, half.filteredBounce[1] + row, base)));
        bounceSum.z = hn::Add(bounceSum.z, hn::Mul(weight, Pick(rowBounce[2], at, half.filteredBounce[2] + row, base)));
      }
    }
    StoreRow(hn::IfThenElse(geometry, hn::Div(visibilitySum, weightSum), one), df, visibility, x0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.x, weightSum)), df, bounce[0], x0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.y, weightSum)), df, bounce[1], x0, count);
    StoreRow(hn::IfThenElseZero(geometry, hn::Div(bounceSum.z, weightSum)), df, bounce[2], x0, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(PrepareRow);
HWY_EXPORT(MarchRow);
HWY_EXPORT(FilterRow);
HWY_EXPORT(UpsampleRow);

void BouncePrepareRowSimd(const BounceSetup& setup, const uint32_t* word1Row, const uint32_t* word2Row,
                          const float* const litRow[3], float* depth, float* const normal[3], uint32_t* normalCode,
                          float* const lit[3]) {
  HWY_DYNAMIC_DISPATCH(PrepareRow)(setup, word1Row, word2Row, litRow, depth, normal, normalCode, lit);
}

uint64_t BounceMarchRowSimd(const BounceSetup& setup, const BounceHalfView& half, int j, float* visibility,
                            float* const bounce[3]) {
  return HWY_DYNAMIC_DISPATCH(MarchRow)(setup, half, j, visibility, bounce);
}

void BounceFilterRowSimd(const BounceSetup& setup, const BounceHalfView& half, int j, bool vertical,
                         const float* sourceVisibility, const float* const sourceBounce[3], float* visibility,
                         float* const bounce[3]) {
  HWY_DYNAMIC_DISPATCH(FilterRow)(setup, half, j, vertical, sourceVisibility, sourceBounce, visibility, bounce);
}

void BounceUpsampleRowSimd(const BounceSetup& setup, const BounceHalfView& half, int y, const uint32_t* word1Row,
                           const uint32_t* word2Row, float* visibility, float* const bounce[3]) {
  HWY_DYNAMIC_DISPATCH(UpsampleRow)(setup, half, y, word1Row, word2Row, visibility, bounce);
}

}  // namespace ssgi
#endif
