// The Highway twin of BlockerSearchRowScalar (shadow_map.cpp): the same operations in the same order
// through the core twins (core/*-inl.h), so every target gives the scalar bits
// (tests/passes/shadow_map_test.cpp checks each compiled target). Lanes are the pixels of the row,
// each tap a gather of the depth keys, the blocker distances summed tap by tap in every lane. A
// receiver the scalar code returns early for stays in the vector under a mask: its lanes compute
// values that are never stored and gather only key 0; a vector with no receiver left skips the taps.
#include <limits>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/shadow_map_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/cache_control.h"
#include "hwy/highway.h"

#include "core/gbuffer-inl.h"
#include "core/math-inl.h"
#include "core/row-inl.h"
#include "passes/shadow_map.h"

#ifndef SSGI_PASSES_SHADOW_MAP_SIMD_ONCE
#define SSGI_PASSES_SHADOW_MAP_SIMD_ONCE
namespace ssgi {
namespace {

// A row's taps cover a band of the shadow map that moves a little from row to row; the texels it
// newly reaches would come from memory at the gathers. So each tap also prefetches, for one lane in
// kPrefetchLaneStep, roughly where the same pixel kPrefetchRows rows below will tap (same view depth,
// no normal offset): a hint only, which changes no result.
constexpr int kPrefetchRows = 16;
constexpr size_t kPrefetchLaneStep = 4;

// What the search of one row reads, flattened into plain values for the dispatch boundary: the
// row's receiver rays, BlockerSearchContext's constants, and the subexpressions of the scalar kernel
// that do not depend on the pixel (computed once, by the same float expressions).
struct BlockerSearchRowInputs {
  const float* depthKey;  // the shadow map's depth keys, row ty at depthKey + ty * depthKeyStride
  size_t depthKeyStride;
  uint32_t lastKeyIndex;  // (resolution - 1) * depthKeyStride + resolution - 1
  const glm::vec2* pattern;
  size_t taps;
  glm::vec3 origin, first, step;   // ReceiverPositions: At(row, x, d) = origin + (first + step x) d
  glm::vec3 aheadFirst, aheadStep;  // first and step kPrefetchRows rows below, minus this row's
  glm::mat3 normalToLight;
  NormalEncoding encoding;
  bool orthographic;
  float nearPlane, farMinusNear;  // ViewProjection::DepthFromKey
  float halfX, halfY, resolution;
  float texelX, texelY, invTexelX, invTexelY;
  float maxTexel;          // max(texelX, texelY)
  float planeX0, planeY0;  // the receiver plane's ray at texel (0, 0): 0.5 texelX - halfX, halfY - 0.5 texelY
  float tanAngularRadius, lightRadius, maxBlockerDistance;
};

}  // namespace
}  // namespace ssgi
#endif

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace {

// How far, as an index into the map, the pixel kPrefetchRows rows below taps from where this one
// does, roughly: from the receiver at light-view position p, at x = fx and view depth `depth`,
// without the normal offset.
template <bool kOrthographic>
hn::Vec<DI> PrefetchShift(const BlockerSearchRowInputs& in, const Vec3V<DF>& p, VF fx, VF depth) {
  const DF df;
  const DI di;
  const Vec3V<DF> below =
      Add3(p, Scale3(Add3(Set3(df, in.aheadFirst), Scale3(Set3(df, in.aheadStep), fx)), depth));
  VF shiftX, shiftY;
  if constexpr (kOrthographic) {
    shiftX = hn::Sub(below.x, p.x);
    shiftY = hn::Sub(p.y, below.y);
  } else {
    shiftX = hn::Sub(hn::Div(below.x, hn::Neg(below.z)), hn::Div(p.x, hn::Neg(p.z)));
    shiftY = hn::Sub(hn::Div(p.y, hn::Neg(p.z)), hn::Div(below.y, hn::Neg(below.z)));
  }
  const auto texelsX = hn::ConvertTo(di, hn::Mul(shiftX, hn::Set(df, in.invTexelX)));
  const auto texelsY = hn::ConvertTo(di, hn::Mul(shiftY, hn::Set(df, in.invTexelY)));
  return hn::Add(hn::Mul(texelsY, hn::Set(di, int32_t(in.depthKeyStride))), texelsX);
}

// SearchBlockersRow's body (shadow_map.cpp) for the pixels at x = fx of one row: words 1 and 2 in,
// word 3 out.
template <bool kOrthographic>
hn::Vec<DU> SearchBlockersV(const BlockerSearchRowInputs& in, hn::Vec<DU> word1, hn::Vec<DU> word2, VF fx) {
  const DF df;
  const DI di;
  const DU du;
  const VF zero = hn::Zero(df);
  const VF one = hn::Set(df, 1.0f);
  const VF nearPlane = hn::Set(df, in.nearPlane);
  const VF resolution = hn::Set(df, in.resolution);

  const VF depth = UnpackDepthV(df, word2);
  auto receiver = hn::Lt(depth, hn::Set(df, kBackgroundDepth));
  if (hn::AllFalse(df, receiver)) return hn::Zero(du);
  const Vec3V<DF> p =
      Add3(Set3(df, in.origin), Scale3(Add3(Set3(df, in.first), Scale3(Set3(df, in.step), fx)), depth));
  const Vec3V<DF> n = MulMat3(df, in.normalToLight, UnpackNormalV(df, word1, in.encoding));

  const VF lightDepth = hn::Neg(p.z);
  receiver = hn::And(receiver, hn::Gt(lightDepth, nearPlane));
  const VF distance = kOrthographic ? lightDepth : Length3(p);
  const Vec3V<DF> toLight = kOrthographic ? Set3(df, glm::vec3(0.0f, 0.0f, 1.0f)) : Div3(Neg3(p), distance);
  const VF cosAngle = Dot3(n, toLight);
  const VF sinAngle = hn::Sqrt(MaxStd(zero, hn::Sub(one, hn::Mul(cosAngle, cosAngle))));
  const VF maxSlope = hn::Set(df, kMaxSlope);
  const VF slope = hn::IfThenElse(hn::Gt(hn::Mul(cosAngle, maxSlope), sinAngle), hn::Div(sinAngle, cosAngle), maxSlope);
  const VF texel = kOrthographic ? hn::Set(df, in.maxTexel) : hn::Mul(hn::Set(df, in.maxTexel), lightDepth);
  const Vec3V<DF> biased = Add3(p, Scale3(n, hn::Mul(hn::Mul(hn::Set(df, kNormalOffsetTexels), texel), sinAngle)));
  const VF biasedDepth = hn::Neg(biased.z);
  receiver = hn::And(receiver, hn::Gt(biasedDepth, nearPlane));
  const VF toUnitDepth = kOrthographic ? one : hn::Div(one, biasedDepth);
  const VF centreX =
      hn::Mul(hn::Add(hn::Mul(biased.x, toUnitDepth), hn::Set(df, in.halfX)), hn::Set(df, in.invTexelX));
  const VF centreY =
      hn::Mul(hn::Sub(hn::Set(df, in.halfY), hn::Mul(biased.y, toUnitDepth)), hn::Set(df, in.invTexelY));
  receiver = hn::And(receiver, hn::And(hn::And(hn::Ge(centreX, zero), hn::Lt(centreX, resolution)),
                                       hn::And(hn::Ge(centreY, zero), hn::Lt(centreY, resolution))));
  if (hn::AllFalse(df, receiver)) return hn::Zero(du);
  const VF bias = hn::Mul(
      texel, hn::Add(hn::Set(df, kConstantBiasTexels), hn::Mul(hn::Set(df, kSlopeBiasTexels), slope)));

  VF radiusX, radiusY;
  if constexpr (kOrthographic) {
    const VF world = hn::Mul(MinStd(hn::Sub(lightDepth, nearPlane), hn::Set(df, in.maxBlockerDistance)),
                             hn::Set(df, in.tanAngularRadius));
    radiusX = hn::Mul(world, hn::Set(df, in.invTexelX));
    radiusY = hn::Mul(world, hn::Set(df, in.invTexelY));
  } else {
    const VF nearest = MaxStd(nearPlane, hn::Sub(lightDepth, hn::Set(df, in.maxBlockerDistance)));
    radiusX = hn::Mul(hn::Div(hn::Mul(hn::Set(df, in.lightRadius), hn::Sub(lightDepth, nearest)),
                              hn::Mul(lightDepth, nearest)),
                      hn::Set(df, in.invTexelX));
    radiusY = radiusX;
  }
  radiusX = MinStd(radiusX, resolution);
  radiusY = MinStd(radiusY, resolution);

  // The receiver plane along texel (tx, ty)'s ray: m = m0 + mx tx + my ty.
  const VF m0 = hn::Add(hn::Mul(n.x, hn::Set(df, in.planeX0)), hn::Mul(n.y, hn::Set(df, in.planeY0)));
  const VF mx = hn::Mul(n.x, hn::Set(df, in.texelX));
  const VF my = hn::Mul(hn::Neg(n.y), hn::Set(df, in.texelY));
  const VF c = hn::Add(hn::Mul(n.x, biased.x), hn::Mul(n.y, biased.y));
  const VF minFacing =
      MaxStd(hn::Div(hn::Sqrt(hn::Add(hn::Mul(n.x, n.x), hn::Mul(n.y, n.y))), maxSlope), hn::Set(df, kMinFacing));
  const VF invFacing = kOrthographic ? hn::Div(one, MaxStd(n.z, minFacing)) : zero;

  const auto stride = hn::Set(di, int32_t(in.depthKeyStride));
  const auto prefetchShift = PrefetchShift<kOrthographic>(in, p, fx, depth);
  const auto lastKeyIndex = hn::Set(du, in.lastKeyIndex);
  HWY_ALIGN uint32_t prefetchIndex[HWY_MAX_BYTES / 4];
  const auto searchedReceiver = hn::RebindMask(di, receiver);
  const auto mapSize = hn::Set(du, uint32_t(in.resolution));
  // A tap's texel in one step instead of the saturating float -> int conversion and back: Floor(t) + 2^23
  // is exact for 0 <= Floor(t) < 2^23 and its bits are 0x4B000000 + int(t); for any other t (negative, at
  // least 2^23 > resolution, infinite, NaN) those bits minus 0x4B000000, as unsigned, are at least 2^23.
  // So the difference is int(tap) and, compared with the resolution, the scalar 0 <= tap < resolution;
  // Floor(tap) itself is float(int(tap)) there (a tap is never -0: the centre is never -0, being halfX plus
  // or halfY minus a value, scaled).
  const VF twoPow23 = hn::Set(df, 8388608.0f);
  const auto twoPow23Bits = hn::Set(di, 0x4B000000);
  const auto oneI = hn::Set(di, 1);
  const VF farMinusNear = hn::Set(df, in.farMinusNear);
  const VF half = hn::Set(df, 0.5f);
  auto hardShadow = hn::FirstN(di, 0);
  auto blockers = hn::Zero(di);
  VF blockerDistanceSum = zero;
  for (size_t i = 0; i < in.taps; ++i) {
    const VF ftx = hn::Floor(hn::Add(centreX, hn::Mul(hn::Set(df, in.pattern[i].x), radiusX)));
    const VF fty = hn::Floor(hn::Add(centreY, hn::Mul(hn::Set(df, in.pattern[i].y), radiusY)));
    const auto tx = hn::Sub(hn::BitCast(di, hn::Add(ftx, twoPow23)), twoPow23Bits);
    const auto ty = hn::Sub(hn::BitCast(di, hn::Add(fty, twoPow23)), twoPow23Bits);
    const auto inMap = hn::And(hn::Lt(hn::BitCast(du, tx), mapSize), hn::Lt(hn::BitCast(du, ty), mapSize));
    const auto searched = hn::And(searchedReceiver, hn::RebindMask(di, inMap));
    // The lanes that are not searched read key 0.
    const auto index = hn::IfThenElseZero(searched, hn::Add(hn::Mul(ty, stride), tx));
    const VF key = hn::GatherIndex(df, in.depthKey, index);
    hn::Store(hn::Min(hn::BitCast(du, hn::Add(index, prefetchShift)), lastKeyIndex), du, prefetchIndex);
    for (size_t lane = 0; lane < hn::Lanes(du); lane += kPrefetchLaneStep) {
      hwy::Prefetch(in.depthKey + prefetchIndex[lane]);
    }
    const VF m = hn::Add(hn::Add(m0, hn::Mul(mx, ftx)), hn::Mul(my, fty));
    VF planeDepth, tapDepth;
    if constexpr (kOrthographic) {
      planeDepth = hn::Add(biasedDepth, hn::Mul(hn::Sub(m, c), invFacing));
      tapDepth = hn::Add(nearPlane, hn::Mul(hn::Sub(one, key), farMinusNear));
    } else {
      planeDepth = hn::Add(biasedDepth, hn::Div(hn::Sub(hn::Mul(biasedDepth, m), c),
                                                MaxStd(hn::Sub(n.z, m), minFacing)));
      tapDepth = hn::Div(nearPlane, key);
    }
    const auto blocker =
        hn::And(searched, hn::RebindMask(di, hn::And(hn::Ne(key, zero), hn::Lt(tapDepth, hn::Sub(planeDepth, bias)))));
    if (i == 0) hardShadow = blocker;
    blockers = hn::IfThenElse(blocker, hn::Add(blockers, oneI), blockers);
    VF blockerDistance = tapDepth;
    if constexpr (!kOrthographic) {
      const Vec3V<DF> ray{hn::Sub(hn::Mul(hn::Add(ftx, half), hn::Set(df, in.texelX)), hn::Set(df, in.halfX)),
                          hn::Sub(hn::Set(df, in.halfY), hn::Mul(hn::Add(fty, half), hn::Set(df, in.texelY))), one};
      blockerDistance = hn::Mul(tapDepth, Length3(ray));
    }
    blockerDistanceSum =
        hn::IfThenElse(hn::RebindMask(df, blocker), hn::Add(blockerDistanceSum, blockerDistance), blockerDistanceSum);
  }
  const auto found = hn::Gt(blockers, hn::Zero(di));
  const VF average = hn::Sub(distance, hn::Div(blockerDistanceSum, hn::ConvertTo(df, blockers)));
  // PackShadowTerm(hardShadow, max(0, average)).
  const auto packed = hn::Or(hn::BitCast(du, MaxStd(zero, average)),
                             hn::IfThenElseZero(hn::RebindMask(du, hardShadow), hn::Set(du, 0x80000000u)));
  return hn::IfThenElseZero(hn::RebindMask(du, found), packed);
}

template <bool kOrthographic>
void SearchBlockersRowV(const BlockerSearchRowInputs& in, const uint32_t* word1, const uint32_t* word2, size_t width,
                        uint32_t* shadowTerm) {
  const DF df;
  const DU du;
  const VF lane = hn::Iota(df, 0.0f);
  for (size_t x = 0; x < width; x += hn::Lanes(df)) {
    const hn::Vec<DU> term =
        SearchBlockersV<kOrthographic>(in, LoadRow(du, word1, x, width, 0u),
                                       LoadRow(du, word2, x, width, PackDepth(kBackgroundDepth)),
                                       hn::Add(lane, hn::Set(df, float(x))));
    StoreRow(term, du, shadowTerm, x, width);
  }
}

}  // namespace

void BlockerSearchRow(const BlockerSearchRowInputs& in, const uint32_t* word1, const uint32_t* word2, int width,
                      uint32_t* shadowTerm) {
  if (in.orthographic) {
    SearchBlockersRowV<true>(in, word1, word2, size_t(width), shadowTerm);
  } else {
    SearchBlockersRowV<false>(in, word1, word2, size_t(width), shadowTerm);
  }
}

// ReceiverBoundsRowScalar's twin: each lane keeps its own bounds over the pixels x = lane (mod the
// lane count), then the lanes' bounds are folded in lane order. With -0 made +0 and NaN never
// taken (the comparisons are glm::min's and glm::max's), a minimum or maximum does not depend on
// the order it is taken in: the scalar bounds, exactly.
size_t ReceiverBoundsRow(const uint32_t* word2, int width, glm::vec3 origin, glm::vec3 first, glm::vec3 step,
                         glm::vec3& lo, glm::vec3& hi) {
  const DF df;
  const DI di;
  const DU du;
  const size_t count = size_t(width);
  const VF zero = hn::Zero(df);
  const VF inf = hn::Set(df, std::numeric_limits<float>::infinity());
  const VF minusInf = hn::Neg(inf);
  VF lanesLo[3] = {inf, inf, inf}, lanesHi[3] = {minusInf, minusInf, minusInf};
  const Vec3V<DF> o = Set3(df, origin), f = Set3(df, first), s = Set3(df, step);
  size_t receivers = 0;
  for (size_t x = 0; x < count; x += hn::Lanes(df)) {
    const VF depth = UnpackDepthV(df, LoadRow(du, word2, x, count, PackDepth(kBackgroundDepth)));
    const MF receiver = hn::Lt(depth, hn::Set(df, kBackgroundDepth));
    if (hn::AllFalse(df, receiver)) continue;
    receivers += hn::CountTrue(df, receiver);
    const VF px = hn::ConvertTo(df, hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(x))));
    const Vec3V<DF> p = Add3(o, Scale3(Add3(f, Scale3(s, px)), depth));  // ReceiverPositions::At
    const VF q[3] = {hn::Add(p.x, zero), hn::Add(p.y, zero), hn::Add(hn::Neg(p.z), zero)};
    for (int c = 0; c < 3; ++c) {
      lanesLo[c] = MinStd(lanesLo[c], hn::IfThenElse(receiver, q[c], inf));
      lanesHi[c] = MaxStd(lanesHi[c], hn::IfThenElse(receiver, q[c], minusInf));
    }
  }
  HWY_ALIGN float laneValues[hn::MaxLanes(DF())];
  for (int c = 0; c < 3; ++c) {
    hn::Store(lanesLo[c], df, laneValues);
    for (size_t i = 0; i < hn::Lanes(df); ++i) lo[c] = glm::min(lo[c], laneValues[i]);
    hn::Store(lanesHi[c], df, laneValues);
    for (size_t i = 0; i < hn::Lanes(df); ++i) hi[c] = glm::max(hi[c], laneValues[i]);
  }
  return receivers;
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>

namespace ssgi {

HWY_EXPORT(BlockerSearchRow);
HWY_EXPORT(ReceiverBoundsRow);

size_t ReceiverBoundsRowSimd(const uint32_t* word2, int width, const ReceiverPositions& positions,
                             const ReceiverPositions::Row& row, glm::vec3& lo, glm::vec3& hi) {
  return HWY_DYNAMIC_DISPATCH(ReceiverBoundsRow)(word2, width, positions.Origin(), row.first, row.step, lo, hi);
}

void BlockerSearchRowSimd(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                          int width, uint32_t* shadowTerm) {
  const ViewProjection& light = context.light;
  const ReceiverPositions::Row row = context.receivers.AtRow(y);
  const ReceiverPositions::Row below = context.receivers.AtRow(y + kPrefetchRows);
  BlockerSearchRowInputs in;
  in.depthKey = context.depthKey.ConstRow(0);
  in.depthKeyStride = context.depthKey.bytes_per_row() / sizeof(float);
  in.lastKeyIndex = uint32_t(size_t(light.width - 1) * in.depthKeyStride + size_t(light.width - 1));
  in.pattern = context.pattern;
  in.taps = context.taps;
  in.origin = context.receivers.Origin();
  in.first = row.first;
  in.step = row.step;
  in.aheadFirst = below.first - row.first;
  in.aheadStep = below.step - row.step;
  in.normalToLight = context.normalToLight;
  in.encoding = context.encoding;
  in.orthographic = light.orthographic;
  in.nearPlane = light.nearPlane;
  in.farMinusNear = light.farPlane - light.nearPlane;
  in.halfX = light.halfX;
  in.halfY = light.halfY;
  in.resolution = float(light.width);
  in.texelX = context.texelX;
  in.texelY = context.texelY;
  in.invTexelX = context.invTexelX;
  in.invTexelY = context.invTexelY;
  in.maxTexel = std::max(context.texelX, context.texelY);
  in.planeX0 = 0.5f * context.texelX - light.halfX;
  in.planeY0 = light.halfY - 0.5f * context.texelY;
  in.tanAngularRadius = context.tanAngularRadius;
  in.lightRadius = context.lightRadius;
  in.maxBlockerDistance = context.maxBlockerDistance;
  HWY_DYNAMIC_DISPATCH(BlockerSearchRow)(in, word1, word2, width, shadowTerm);
}

}  // namespace ssgi
#endif
