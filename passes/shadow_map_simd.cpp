// The Highway twin of BlockerSearchRowScalar (shadow_map.cpp): lanes are the pixels of the row, each
// tap a gather of the depth keys. Each lane runs the scalar definition's operations in its order:
// std::min / std::max as the same compare and select (so a NaN goes where it goes there, whatever a
// target's min instruction does), Mul then Add (never fused), exact division and square root, the
// blocker distances summed tap by tap. A receiver the scalar code returns early for stays in the
// vector under a mask: its lanes compute values that are never stored and gather only key 0. So every
// target gives the scalar bytes (tests/passes/shadow_map_test.cpp checks each compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/shadow_map_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/cache_control.h"
#include "hwy/highway.h"

#include "core/gbuffer-inl.h"
#include "passes/shadow_map.h"

#ifndef SSGI_PASSES_SHADOW_MAP_SIMD_ROW_INPUTS
#define SSGI_PASSES_SHADOW_MAP_SIMD_ROW_INPUTS
namespace ssgi {
namespace {

// A row's taps cover a band of the shadow map that moves a little from row to row; the texels it
// newly reaches would come from memory at the gathers. So each tap also prefetches, for one lane in
// kPrefetchLaneStep, roughly where the same pixel kPrefetchRows rows below will tap (same view depth,
// no normal offset): a hint only, which changes no result.
constexpr int kPrefetchRows = 16;
constexpr size_t kPrefetchLaneStep = 8;

// What the search of one row reads, flattened into plain values for the dispatch boundary: the
// row's receiver rays, BlockerSearchContext's constants, and the per-pixel subexpressions of the
// scalar kernel that do not depend on the pixel (computed once, by the same float expressions).
struct BlockerSearchRowInputs {
  const float* depthKey;  // the shadow map's depth keys, row ty at depthKey + ty * depthKeyStride
  size_t depthKeyStride;
  uint32_t lastKeyIndex;  // (resolution - 1) * depthKeyStride + resolution - 1
  const glm::vec2* pattern;
  size_t taps;
  float origin[3], first[3], step[3];  // ReceiverPositions: At(row, x, d) = origin + (first + step x) d
  float aheadFirst[3], aheadStep[3];   // the same for kPrefetchRows rows below, minus this row's
  float normalToLight[3][3];           // [column][row], as glm::mat3
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

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;

// std::min(a, b) and std::max(a, b), NaN included: (b < a) ? b : a and (a < b) ? b : a. glm::min of
// vectors is std::min per component.
VF StdMin(VF a, VF b) { return hn::IfThenElse(hn::Lt(b, a), b, a); }
VF StdMax(VF a, VF b) { return hn::IfThenElse(hn::Lt(a, b), b, a); }

// How far, as an index into the map, the pixel kPrefetchRows rows below taps from where this one
// does, roughly: from the receivers at light-view positions p and view depths `depth` of the pixels
// at x = fx, with no normal offset.
template <bool kOrthographic>
hn::Vec<DI> PrefetchShift(const BlockerSearchRowInputs& in, const VF (&p)[3], VF fx, VF depth) {
  const DF df;
  const DI di;
  VF below[3];
  for (int c = 0; c < 3; ++c) {
    const VF change = hn::Add(hn::Set(df, in.aheadFirst[c]), hn::Mul(hn::Set(df, in.aheadStep[c]), fx));
    below[c] = hn::Add(p[c], hn::Mul(change, depth));
  }
  VF shiftX, shiftY;
  if constexpr (kOrthographic) {
    shiftX = hn::Sub(below[0], p[0]);
    shiftY = hn::Sub(p[1], below[1]);
  } else {
    shiftX = hn::Sub(hn::Div(below[0], hn::Neg(below[2])), hn::Div(p[0], hn::Neg(p[2])));
    shiftY = hn::Sub(hn::Div(p[1], hn::Neg(p[2])), hn::Div(below[1], hn::Neg(below[2])));
  }
  const auto texelsX = hn::ConvertTo(di, hn::Mul(shiftX, hn::Set(df, in.invTexelX)));
  const auto texelsY = hn::ConvertTo(di, hn::Mul(shiftY, hn::Set(df, in.invTexelY)));
  return hn::Add(hn::Mul(texelsY, hn::Set(di, int32_t(in.depthKeyStride))), texelsX);
}

// SearchBlockers (shadow_map.cpp) for the Lanes(df) pixels from x of one row: words 1 and 2 in, word 3 out.
template <bool kOrthographic>
void SearchBlockersV(const BlockerSearchRowInputs& in, const uint32_t* word1, const uint32_t* word2, int x,
                     uint32_t* shadowTerm) {
  const DF df;
  const DI di;
  const DU du;
  const VF zero = hn::Zero(df);
  const VF one = hn::Set(df, 1.0f);
  const VF nearPlane = hn::Set(df, in.nearPlane);
  const VF resolution = hn::Set(df, in.resolution);

  const VF depth = UnpackDepthV(df, hn::LoadU(du, word2));
  auto receiver = hn::Lt(depth, hn::Set(df, kBackgroundDepth));
  if (hn::AllFalse(df, receiver)) {
    hn::StoreU(hn::Zero(du), du, shadowTerm);
    return;
  }

  // ReceiverPositions::At and the normal rotated into the light view (glm's mat3 * vec3).
  const VF fx = hn::ConvertTo(df, hn::Iota(di, x));
  VF p[3];
  for (int c = 0; c < 3; ++c) {
    const VF direction = hn::Add(hn::Set(df, in.first[c]), hn::Mul(hn::Set(df, in.step[c]), fx));
    p[c] = hn::Add(hn::Set(df, in.origin[c]), hn::Mul(direction, depth));
  }
  const Vec3V<DF> cameraNormal = UnpackNormalV(df, hn::LoadU(du, word1), in.encoding);
  VF n[3];
  for (int r = 0; r < 3; ++r) {
    n[r] = hn::Add(hn::Add(hn::Mul(hn::Set(df, in.normalToLight[0][r]), cameraNormal.x),
                           hn::Mul(hn::Set(df, in.normalToLight[1][r]), cameraNormal.y)),
                   hn::Mul(hn::Set(df, in.normalToLight[2][r]), cameraNormal.z));
  }

  const VF lightDepth = hn::Neg(p[2]);
  receiver = hn::And(receiver, hn::Gt(lightDepth, nearPlane));
  VF distance, cosAngle;
  if constexpr (kOrthographic) {
    distance = lightDepth;
    // dot(n, (0, 0, 1)), with its products by 0.
    cosAngle = hn::Add(hn::Add(hn::Mul(n[0], zero), hn::Mul(n[1], zero)), hn::Mul(n[2], one));
  } else {
    distance = hn::Sqrt(hn::Add(hn::Add(hn::Mul(p[0], p[0]), hn::Mul(p[1], p[1])), hn::Mul(p[2], p[2])));
    cosAngle = hn::Add(hn::Add(hn::Mul(n[0], hn::Div(hn::Neg(p[0]), distance)),
                               hn::Mul(n[1], hn::Div(hn::Neg(p[1]), distance))),
                       hn::Mul(n[2], hn::Div(hn::Neg(p[2]), distance)));
  }
  const VF sinAngle = hn::Sqrt(StdMax(zero, hn::Sub(one, hn::Mul(cosAngle, cosAngle))));
  const VF maxSlope = hn::Set(df, kMaxSlope);
  const VF slope = hn::IfThenElse(hn::Gt(hn::Mul(cosAngle, maxSlope), sinAngle), hn::Div(sinAngle, cosAngle), maxSlope);
  const VF texel = kOrthographic ? hn::Set(df, in.maxTexel) : hn::Mul(hn::Set(df, in.maxTexel), lightDepth);
  const VF offset = hn::Mul(hn::Mul(hn::Set(df, kNormalOffsetTexels), texel), sinAngle);
  const VF biasedX = hn::Add(p[0], hn::Mul(n[0], offset));
  const VF biasedY = hn::Add(p[1], hn::Mul(n[1], offset));
  const VF biasedDepth = hn::Neg(hn::Add(p[2], hn::Mul(n[2], offset)));
  receiver = hn::And(receiver, hn::Gt(biasedDepth, nearPlane));
  const VF toUnitDepth = kOrthographic ? one : hn::Div(one, biasedDepth);
  const VF centreX =
      hn::Mul(hn::Add(hn::Mul(biasedX, toUnitDepth), hn::Set(df, in.halfX)), hn::Set(df, in.invTexelX));
  const VF centreY =
      hn::Mul(hn::Sub(hn::Set(df, in.halfY), hn::Mul(biasedY, toUnitDepth)), hn::Set(df, in.invTexelY));
  receiver = hn::And(receiver, hn::And(hn::And(hn::Ge(centreX, zero), hn::Lt(centreX, resolution)),
                                       hn::And(hn::Ge(centreY, zero), hn::Lt(centreY, resolution))));
  if (hn::AllFalse(df, receiver)) {
    hn::StoreU(hn::Zero(du), du, shadowTerm);
    return;
  }
  const VF bias = hn::Mul(
      texel, hn::Add(hn::Set(df, kConstantBiasTexels), hn::Mul(hn::Set(df, kSlopeBiasTexels), slope)));

  VF radiusX, radiusY;
  if constexpr (kOrthographic) {
    const VF world = hn::Mul(StdMin(hn::Sub(lightDepth, nearPlane), hn::Set(df, in.maxBlockerDistance)),
                             hn::Set(df, in.tanAngularRadius));
    radiusX = hn::Mul(world, hn::Set(df, in.invTexelX));
    radiusY = hn::Mul(world, hn::Set(df, in.invTexelY));
  } else {
    const VF nearest = StdMax(nearPlane, hn::Sub(lightDepth, hn::Set(df, in.maxBlockerDistance)));
    radiusX = hn::Mul(hn::Div(hn::Mul(hn::Set(df, in.lightRadius), hn::Sub(lightDepth, nearest)),
                              hn::Mul(lightDepth, nearest)),
                      hn::Set(df, in.invTexelX));
    radiusY = radiusX;
  }
  radiusX = StdMin(radiusX, resolution);
  radiusY = StdMin(radiusY, resolution);

  // The receiver plane along texel (tx, ty)'s ray: m = m0 + mx tx + my ty.
  const VF m0 = hn::Add(hn::Mul(n[0], hn::Set(df, in.planeX0)), hn::Mul(n[1], hn::Set(df, in.planeY0)));
  const VF mx = hn::Mul(n[0], hn::Set(df, in.texelX));
  const VF my = hn::Mul(hn::Neg(n[1]), hn::Set(df, in.texelY));
  const VF c = hn::Add(hn::Mul(n[0], biasedX), hn::Mul(n[1], biasedY));
  const VF minFacing =
      StdMax(hn::Div(hn::Sqrt(hn::Add(hn::Mul(n[0], n[0]), hn::Mul(n[1], n[1]))), maxSlope), hn::Set(df, kMinFacing));
  const VF invFacing = kOrthographic ? hn::Div(one, StdMax(n[2], minFacing)) : zero;

  const auto stride = hn::Set(di, int32_t(in.depthKeyStride));
  const auto prefetchShift = PrefetchShift<kOrthographic>(in, p, fx, depth);
  const auto lastKeyIndex = hn::Set(du, in.lastKeyIndex);
  HWY_ALIGN uint32_t prefetchIndex[HWY_MAX_BYTES / 4];

  const auto receiverI = hn::RebindMask(di, receiver);
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
    const auto searched = hn::And(receiverI, hn::RebindMask(di, inMap));
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
                                                StdMax(hn::Sub(n[2], m), minFacing)));
      tapDepth = hn::Div(nearPlane, key);
    }
    const auto blocker =
        hn::And(searched, hn::RebindMask(di, hn::And(hn::Ne(key, zero), hn::Lt(tapDepth, hn::Sub(planeDepth, bias)))));
    if (i == 0) hardShadow = blocker;
    blockers = hn::IfThenElse(blocker, hn::Add(blockers, oneI), blockers);
    VF blockerDistance = tapDepth;
    if constexpr (!kOrthographic) {
      const VF rayX = hn::Sub(hn::Mul(hn::Add(ftx, half), hn::Set(df, in.texelX)), hn::Set(df, in.halfX));
      const VF rayY = hn::Sub(hn::Set(df, in.halfY), hn::Mul(hn::Add(fty, half), hn::Set(df, in.texelY)));
      const VF rayLength = hn::Sqrt(hn::Add(hn::Add(hn::Mul(rayX, rayX), hn::Mul(rayY, rayY)), hn::Mul(one, one)));
      blockerDistance = hn::Mul(tapDepth, rayLength);
    }
    blockerDistanceSum =
        hn::IfThenElse(hn::RebindMask(df, blocker), hn::Add(blockerDistanceSum, blockerDistance), blockerDistanceSum);
  }
  const auto found = hn::Gt(blockers, hn::Zero(di));
  const VF average = hn::Sub(distance, hn::Div(blockerDistanceSum, hn::ConvertTo(df, blockers)));
  // PackShadowTerm(hardShadow, max(0, average)).
  const auto packed = hn::Or(hn::BitCast(du, StdMax(zero, average)),
                             hn::IfThenElseZero(hn::RebindMask(du, hardShadow), hn::Set(du, 0x80000000u)));
  hn::StoreU(hn::IfThenElseZero(hn::RebindMask(du, found), packed), du, shadowTerm);
}

template <bool kOrthographic>
void SearchBlockersRowV(const BlockerSearchRowInputs& in, const uint32_t* word1, const uint32_t* word2, int width,
                        uint32_t* shadowTerm) {
  const DF df;
  const int lanes = int(hn::Lanes(df));
  int x = 0;
  for (; x + lanes <= width; x += lanes) SearchBlockersV<kOrthographic>(in, word1 + x, word2 + x, x, shadowTerm + x);
  if (x == width) return;
  // The tail through one vector of copies, padded with background, so no load or store passes the row.
  HWY_ALIGN uint32_t w1[HWY_MAX_BYTES / 4], w2[HWY_MAX_BYTES / 4], out[HWY_MAX_BYTES / 4];
  for (int i = 0; i < lanes; ++i) {
    w1[i] = x + i < width ? word1[x + i] : 0u;
    w2[i] = x + i < width ? word2[x + i] : PackDepth(kBackgroundDepth);
  }
  SearchBlockersV<kOrthographic>(in, w1, w2, x, out);
  for (int i = 0; x + i < width; ++i) shadowTerm[x + i] = out[i];
}

}  // namespace

void BlockerSearchRow(const BlockerSearchRowInputs* in, const uint32_t* word1, const uint32_t* word2, int width,
                      uint32_t* shadowTerm) {
  if (in->orthographic) {
    SearchBlockersRowV<true>(*in, word1, word2, width, shadowTerm);
  } else {
    SearchBlockersRowV<false>(*in, word1, word2, width, shadowTerm);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>

namespace ssgi {

HWY_EXPORT(BlockerSearchRow);

void BlockerSearchRowSimd(const BlockerSearchContext& context, const uint32_t* word1, const uint32_t* word2, int y,
                          int width, uint32_t* shadowTerm) {
  const ViewProjection& light = context.light;
  const ReceiverPositions::Row row = context.receivers.AtRow(y);
  const ReceiverPositions::Row ahead = context.receivers.AtRow(y + kPrefetchRows);
  BlockerSearchRowInputs in;
  in.depthKey = context.depthKey.ConstRow(0);
  in.depthKeyStride = context.depthKey.bytes_per_row() / sizeof(float);
  in.lastKeyIndex = uint32_t((light.width - 1) * in.depthKeyStride + size_t(light.width) - 1);
  in.pattern = context.pattern;
  in.taps = context.taps;
  for (int c = 0; c < 3; ++c) {
    in.origin[c] = context.receivers.Origin()[c];
    in.first[c] = row.first[c];
    in.step[c] = row.step[c];
    in.aheadFirst[c] = ahead.first[c] - row.first[c];
    in.aheadStep[c] = ahead.step[c] - row.step[c];
    for (int r = 0; r < 3; ++r) in.normalToLight[c][r] = context.normalToLight[c][r];
  }
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
  HWY_DYNAMIC_DISPATCH(BlockerSearchRow)(&in, word1, word2, width, shadowTerm);
}

}  // namespace ssgi
#endif
