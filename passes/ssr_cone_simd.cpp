// The Highway twin of SsrConeRowScalar (ssr_cone.cpp): lanes are the pixels of a row, each walking
// its own cone's circles; a lane stops where the scalar loop does and keeps its sums while the others
// go on. The same operations in the same order as TraceCone, SampleCircle and SampleLevel, no fused
// multiply-add, no approximate division, std::min / std::max semantics, frexp from the float's bits,
// so every target gives the scalar bytes (tests/passes/ssr_cone_test.cpp).
#ifndef SSGI_PASSES_SSR_CONE_SIMD_FRAME_
#define SSGI_PASSES_SSR_CONE_SIMD_FRAME_
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ssgi {

// What the row kernel reads of SsrConeContext, flattened so that only plain values and pointers
// cross the dispatch boundary.
inline constexpr int kMaxConeLevels = 15;  // a 16384-pixel side: levels 0 .. 14
struct SsrConeFrame {
  int width, height;  // level 0
  int levels;         // colour pyramid levels; level k is max(1, width >> k) x max(1, height >> k)
  const float* texels[kMaxConeLevels][3];  // level k's R, G, B planes at texel (0, 0)
  int32_t stride[kMaxConeLevels];          // texels from one row to the next
  const float* coneTan;                    // ConeTanTable, 256 entries
  int maxSamples;
};

}  // namespace ssgi
#endif  // SSGI_PASSES_SSR_CONE_SIMD_FRAME_

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/ssr_cone_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/math-inl.h"
#include "core/row-inl.h"
#include "passes/ssr_cone.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Where SampleLevel reads for each lane: level k at (x, y) for the lanes of `mask`.
struct TapLanes {
  MF mask;
  VF fu, fv;  // the bilinear weights
  HWY_ALIGN int32_t k[hn::MaxLanes(DI())];
  HWY_ALIGN int32_t x0[hn::MaxLanes(DI())], x1[hn::MaxLanes(DI())], y0[hn::MaxLanes(DI())], y1[hn::MaxLanes(DI())];
  // Per channel: (x0, y0), (x1, y0), (x0, y1), (x1, y1); lanes out of the mask stay 0.
  HWY_ALIGN float texels[3][4][hn::MaxLanes(DF())] = {};
};

// Level k is max(1, size >> k) texels along each axis (PyramidLevelSizes); lanes out of `mask` read
// texel (0, 0) of level 0.
void FindTaps(const SsrConeFrame& frame, VI level, VF x, VF y, MF mask, TapLanes& taps) {
  const DF df;
  const DI di;
  const VI zero = hn::Zero(di);
  const VI one = hn::Set(di, 1);
  const VI width = hn::Max(hn::Set(di, frame.width) >> level, one);
  const VI height = hn::Max(hn::Set(di, frame.height) >> level, one);
  const VF half = hn::Set(df, 0.5f);
  const VF u = hn::Sub(hn::Mul(x, hn::Div(hn::ConvertTo(df, width), hn::Set(df, float(frame.width)))), half);
  const VF v = hn::Sub(hn::Mul(y, hn::Div(hn::ConvertTo(df, height), hn::Set(df, float(frame.height)))), half);
  const VF uFloor = hn::Floor(u);
  const VF vFloor = hn::Floor(v);
  taps.mask = mask;
  taps.fu = hn::Sub(u, uFloor);
  taps.fv = hn::Sub(v, vFloor);
  const auto lanes = hn::RebindMask(di, mask);
  const VI column = hn::IfThenElseZero(lanes, hn::ConvertTo(di, uFloor));
  const VI row = hn::IfThenElseZero(lanes, hn::ConvertTo(di, vFloor));
  const VI lastX = hn::Sub(width, one);
  const VI lastY = hn::Sub(height, one);
  hn::Store(hn::IfThenElseZero(lanes, level), di, taps.k);
  hn::Store(hn::Min(hn::Max(column, zero), lastX), di, taps.x0);
  hn::Store(hn::Min(hn::Max(hn::Add(column, one), zero), lastX), di, taps.x1);
  hn::Store(hn::Min(hn::Max(row, zero), lastY), di, taps.y0);
  hn::Store(hn::Min(hn::Max(hn::Add(row, one), zero), lastY), di, taps.y1);
}

// Loads lane i's 12 texels. Each level is a plane of its own and a gather reads from one base; lane
// by lane beat one gather per distinct level among the lanes (2 to 3 levels a vector on the default
// scene, where a 16-lane gather costs more than 16 loads).
HWY_INLINE void LoadTaps(const SsrConeFrame& frame, size_t i, TapLanes& taps) {
  const int32_t k = taps.k[i];
  const ptrdiff_t row0 = ptrdiff_t(taps.y0[i]) * frame.stride[k];
  const ptrdiff_t row1 = ptrdiff_t(taps.y1[i]) * frame.stride[k];
  for (int c = 0; c < 3; ++c) {
    const float* texels = frame.texels[k][c];
    taps.texels[c][0][i] = texels[row0 + taps.x0[i]];
    taps.texels[c][1][i] = texels[row0 + taps.x1[i]];
    taps.texels[c][2][i] = texels[row1 + taps.x0[i]];
    taps.texels[c][3][i] = texels[row1 + taps.x1[i]];
  }
}

// Calls load(i) for each lane i of mask.
template <class Load>
void ForEachLane(MF mask, const Load& load) {
  for (uint64_t bits = LaneBits(DF(), mask); bits != 0; bits &= bits - 1)
    load(size_t(hwy::Num0BitsBelowLS1Bit_Nonzero64(bits)));
}

// SampleLevel from the loaded taps; lanes out of the mask are 0.
Vec3V<DF> Bilinear(const TapLanes& taps) {
  const DF df;
  VF out[3];
  for (int c = 0; c < 3; ++c) {
    const VF t00 = hn::Load(df, taps.texels[c][0]);
    const VF t01 = hn::Load(df, taps.texels[c][1]);
    const VF t10 = hn::Load(df, taps.texels[c][2]);
    const VF t11 = hn::Load(df, taps.texels[c][3]);
    const VF top = hn::Add(t00, hn::Mul(hn::Sub(t01, t00), taps.fu));
    const VF bottom = hn::Add(t10, hn::Mul(hn::Sub(t11, t10), taps.fu));
    out[c] = hn::IfThenElseZero(taps.mask, hn::Add(top, hn::Mul(hn::Sub(bottom, top), taps.fv)));
  }
  return {out[0], out[1], out[2]};
}

// SampleLevel of level 0 at (x, y) for the lanes of `mask`.
Vec3V<DF> SampleLevel0(const SsrConeFrame& frame, VF x, VF y, MF mask) {
  TapLanes taps;
  FindTaps(frame, hn::Zero(DI()), x, y, mask, taps);
  ForEachLane(mask, [&](size_t i) { LoadTaps(frame, i, taps); });
  return Bilinear(taps);
}

// SampleCircle for the lanes of `mask`: the trilinear fetch at level log2(diameter), diameter >= 1.
// frexp from the bits: diameter = 1.f * 2^(e - 127) = (1.f / 2) * 2^(e - 126), so frexp's exponent
// minus 1 is e - 127 and its mantissa is the float with the exponent field of 0.5.
Vec3V<DF> SampleCircleLanes(const SsrConeFrame& frame, VF x, VF y, VF diameter, MF mask) {
  const DF df;
  const DI di;
  const DU du;
  const auto bits = hn::BitCast(du, diameter);
  const VI level = hn::Sub(hn::BitCast(di, hn::ShiftRight<23>(bits)), hn::Set(di, 127));
  const VF mantissa = hn::BitCast(df, hn::Or(hn::And(bits, hn::Set(du, 0x807FFFFFu)), hn::Set(du, 0x3F000000u)));
  const VI lastLevel = hn::Set(di, frame.levels - 1);
  const MF beyond = hn::RebindMask(df, hn::Not(hn::Lt(level, lastLevel)));
  const MF both = hn::AndNot(beyond, mask);
  TapLanes fine, coarse;
  FindTaps(frame, hn::Min(level, lastLevel), x, y, mask, fine);
  FindTaps(frame, hn::Add(level, hn::Set(di, 1)), x, y, both, coarse);
  ForEachLane(mask, [&](size_t i) { LoadTaps(frame, i, fine); });
  ForEachLane(both, [&](size_t i) { LoadTaps(frame, i, coarse); });
  const Vec3V<DF> f = Bilinear(fine);
  const Vec3V<DF> c = Bilinear(coarse);
  const VF t = hn::Sub(hn::Mul(hn::Set(df, 2.0f), mantissa), hn::Set(df, 1.0f));
  const auto blend = [&](VF a, VF b) { return hn::IfThenElse(beyond, a, hn::Add(a, hn::Mul(hn::Sub(b, a), t))); };
  return {blend(f.x, c.x), blend(f.y, c.y), blend(f.z, c.z)};
}

// SsrConeRowScalar for the pixels x0, x0 + 1, ... of row y, short of `width` (the run's end); red,
// green, blue are its output rows.
void ConeLanes(const SsrConeFrame& frame, const uint32_t* word1, const float* hitX, const float* hitY,
               const float* confidence, size_t y, size_t x0, size_t width, float* const rgb[3],
               SsrConeCounts& counts) {
  const DF df;
  const DI di;
  const DU du;
  const VF zero = hn::Zero(df);
  const MF active = hn::Gt(LoadRow(df, confidence, x0, width, 0.0f), zero);
  Vec3V<DF> radiance{zero, zero, zero};
  if (hn::AllFalse(df, active)) return StoreRow3(radiance, df, rgb, x0, width);
  counts.pixels += hn::CountTrue(df, active);
  const VI code = hn::BitCast(di, hn::ShiftRight<24>(LoadRow(du, word1, x0, width, 0u)));
  // Lanes without a hit sample (0, 0), whatever their trace outputs hold.
  const VF hx = hn::IfThenElseZero(active, LoadRow(df, hitX, x0, width, 0.0f));
  const VF hy = hn::IfThenElseZero(active, LoadRow(df, hitY, x0, width, 0.0f));
  const VF originX = hn::Add(hn::Add(hn::Iota(df, 0.0f), hn::Set(df, float(x0))), hn::Set(df, 0.5f));
  const VF originY = hn::Set(df, float(y) + 0.5f);
  const VF deltaX = hn::Sub(hx, originX);
  const VF deltaY = hn::Sub(hy, originY);
  const VF h = hn::Sqrt(hn::Add(hn::Mul(deltaX, deltaX), hn::Mul(deltaY, deltaY)));
  // Code 0 (the mirror) and cones too short to walk: the level-0 sample at the hit.
  const MF mirror = hn::RebindMask(df, hn::Eq(code, hn::Zero(di)));
  const MF walks = hn::AndNot(mirror, hn::And(active, hn::Ge(h, hn::Set(df, kConeMinHeight))));
  const MF atHit = hn::AndNot(walks, active);
  if (!hn::AllFalse(df, atHit)) {
    radiance = SampleLevel0(frame, hx, hy, atHit);
    counts.samples += hn::CountTrue(df, atHit);
  }

  if (!hn::AllFalse(df, walks)) {
    // TraceCone; lanes that do not walk compute along on a harmless cone (h = 1) and are not used.
    const VF one = hn::Set(df, 1.0f);
    const VF two = hn::Set(df, 2.0f);
    const VF height = hn::IfThenElse(walks, h, one);
    const VF tanTheta = hn::GatherIndex(df, frame.coneTan, hn::IfThenElseZero(hn::RebindMask(di, walks), code));
    const VF directionX = hn::Div(deltaX, height);
    const VF directionY = hn::Div(deltaY, height);
    const VF inRadiusPerHeight =
        hn::Mul(tanTheta, hn::Sub(hn::Sqrt(hn::Add(one, hn::Mul(tanTheta, tanTheta))), tanTheta));
    const VF footprintRadius = hn::Mul(height, tanTheta);
    Vec3V<DF> sum{zero, zero, zero};
    VF coverage = zero;
    VF adjacent = height;
    MF live = walks;
    for (int sample = 0; sample < frame.maxSamples && !hn::AllFalse(df, live); ++sample) {
      counts.samples += hn::CountTrue(df, live);
      const VF radius = hn::Mul(adjacent, inRadiusPerHeight);
      const VF ratio = hn::Div(radius, footprintRadius);
      const VF weight = MinStd(hn::Mul(ratio, ratio), hn::Sub(one, coverage));
      const VF along = hn::Sub(adjacent, radius);
      const VF centreX = hn::Add(originX, hn::Mul(directionX, along));
      const VF centreY = hn::Add(originY, hn::Mul(directionY, along));
      const VF diameter = MaxStd(hn::Mul(two, radius), one);
      const Vec3V<DF> circle = SampleCircleLanes(frame, centreX, centreY, diameter, live);
      sum = IfThenElse3(live, Add3(sum, Scale3(circle, weight)), sum);
      coverage = hn::IfThenElse(live, hn::Add(coverage, weight), coverage);
      adjacent = hn::IfThenElse(live, hn::Sub(adjacent, hn::Mul(two, radius)), adjacent);
      live = hn::And(live, hn::Lt(coverage, one));
    }
    radiance = IfThenElse3(walks, Div3(sum, coverage), radiance);
  }
  StoreRow3(radiance, df, rgb, x0, width);
}

SsrConeCounts ConeRow(const SsrConeFrame& frame, const uint32_t* word1, const float* hitX, const float* hitY,
                      const float* confidence, size_t y, size_t xBegin, size_t xEnd, float* red, float* green,
                      float* blue) {
  float* const rgb[3] = {red, green, blue};
  SsrConeCounts counts;
  for (size_t x0 = xBegin; x0 < xEnd; x0 += hn::Lanes(DF())) {
    ConeLanes(frame, word1, hitX, hitY, confidence, y, x0, xEnd, rgb, counts);
  }
  return counts;
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "core/check.h"

namespace ssgi {

HWY_EXPORT(ConeRow);

namespace {

SsrConeFrame FlattenContext(const SsrConeContext& context) {
  const std::vector<Plane3<float>>& levels = context.pyramid.levels;
  SsrConeFrame frame;
  frame.width = int(levels[0].c[0].xsize());
  frame.height = int(levels[0].c[0].ysize());
  frame.levels = int(levels.size());
  SSGI_CHECK_LE(frame.levels, kMaxConeLevels);
  for (int k = 0; k < frame.levels; ++k) {
    const Plane3<float>& level = levels[size_t(k)];
    for (int c = 0; c < 3; ++c) {
      SSGI_CHECK_EQ(level.c[c].xsize(), size_t(std::max(1, frame.width >> k)));
      SSGI_CHECK_EQ(level.c[c].ysize(), size_t(std::max(1, frame.height >> k)));
      SSGI_CHECK_EQ(level.c[c].PixelsPerRow(), level.c[0].PixelsPerRow());
      frame.texels[k][c] = level.c[c].ConstRow(0);
    }
    frame.stride[k] = int32_t(level.c[0].PixelsPerRow());
  }
  frame.coneTan = context.coneTan.data();
  frame.maxSamples = context.maxSamples;
  return frame;
}

}  // namespace

SsrConeCounts SsrConeRowSimd(const SsrConeContext& context, const uint32_t* word1, const float* hitX,
                             const float* hitY, const float* confidence, size_t y, size_t xBegin, size_t xEnd,
                             float* red, float* green, float* blue) {
  return HWY_DYNAMIC_DISPATCH(ConeRow)(FlattenContext(context), word1, hitX, hitY, confidence, y, xBegin, xEnd, red,
                                       green, blue);
}

void SsrConeRowsSimd(const SsrConeContext& context, const SsrConeInputs& in, size_t yBegin, size_t yEnd,
                     SsrConeOutputs& out, SsrConeCounts* rowCounts) {
  const SsrConeFrame frame = FlattenContext(context);
  for (size_t y = yBegin; y < yEnd; ++y) {
    ForEachConeRun(in, y, out, [&](size_t xBegin, size_t xEnd) {
      const SsrConeCounts counts = HWY_DYNAMIC_DISPATCH(ConeRow)(
          frame, in.gbuffer.word[GBufferWord::kNormalRoughness].ConstRow(y), in.hitX.ConstRow(y), in.hitY.ConstRow(y),
          in.confidence.ConstRow(y), y, xBegin, xEnd, out.reflected.c[0].MutableRow(y),
          out.reflected.c[1].MutableRow(y), out.reflected.c[2].MutableRow(y));
      rowCounts[y].samples += counts.samples;
      rowCounts[y].pixels += counts.pixels;
    });
  }
}

}  // namespace ssgi
#endif
