// The Highway twins of the shadow filter's row kernels (shadow_filter.cpp). Lanes are pixels; each
// lane does the scalar definition's operations in the same order: no fused multiply-add, exact
// division and square root, std::min / std::max as MinStd / MaxStd (core/math-inl.h), the taps'
// sums in the scalar order, a lane whose kernel has fewer taps masked off where its scalar loop
// ends. So every target gives the scalar bytes (tests/passes/shadow_filter_test.cpp checks each
// compiled target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/shadow_filter_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include <algorithm>

#include "core/gbuffer-inl.h"
#include "core/math-inl.h"
#include "passes/shadow_filter.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace {

// Background: !(depth > 0 && depth < inf).
MF Geometry(DF d, VF depth) {
  return hn::And(hn::Gt(depth, hn::Zero(d)), hn::Lt(depth, hn::Set(d, kBackgroundDepth)));
}

// ViewPosition of the pixels x .. x + Lanes - 1 of row y.
Vec3V<DF> ViewPositionV(DF d, const ShadowFilterSetupContext& context, int x, int y, VF depth) {
  return {hn::Mul(depth, hn::LoadU(d, context.rayX + x)), hn::Mul(depth, hn::Set(d, context.rayY[y])),
          hn::Mul(depth, hn::Set(d, -1.0f))};
}

// PenumbraRadiusPixels.
VF PenumbraRadiusV(DF d, const ShadowFilterSetupContext& context, const Vec3V<DF>& position, VF depth, VF blocker) {
  const PreparedLight& light = context.light;
  const VF blocker2 = hn::Mul(blocker, hn::Set(d, 2.0f));
  VF width;
  if (light.isSpot) {
    const VF distance = Length3(Sub3(Set3(d, light.position), position));
    width = hn::Div(hn::Mul(blocker2, hn::Set(d, light.radius)),
                    MaxStd(hn::Sub(distance, blocker), hn::Set(d, kShadowFilterMinLightToBlocker)));
  } else {
    width = hn::Mul(blocker2, hn::Set(d, light.tanAngularRadius));
  }
  const VF radius =
      hn::Mul(hn::Mul(hn::Set(d, 0.5f), width), hn::Div(hn::Set(d, context.pixelsPerMetreAtUnitDepth), depth));
  return hn::IfThenElseZero(hn::Gt(radius, hn::Zero(d)), MinStd(radius, hn::Set(d, context.maxRadius)));
}

// The hard value of word 3 for geometry: flag ? 0 : 1.
VF HardV(DF d, hn::Vec<DU> word3) {
  return hn::IfThenZeroElse(UnpackHardShadowV(d, word3), hn::Set(d, 1.0f));
}

struct KernelV {
  VF majorX, majorY, majorLength, minorLength;
};

// MakeKernel.
KernelV MakeKernelV(DF d, ShadowFilter filter, const Vec3V<DF>& p, const Vec3V<DF>& n, VF radius) {
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const KernelV none{one, zero, zero, zero};
  if (filter == ShadowFilter::kHard) return none;
  const MF blurs = hn::Not(hn::Lt(radius, hn::Set(d, kShadowFilterMinBlurRadius)));
  if (hn::AllFalse(d, blurs)) return none;
  KernelV k{one, zero, radius, radius};
  if (filter == ShadowFilter::kSsabss) {
    const VF depth = hn::Neg(p.z);
    const VF projectedX = hn::Add(n.x, hn::Mul(hn::Div(p.x, depth), n.z));
    const VF projectedY = hn::Neg(hn::Add(n.y, hn::Mul(hn::Div(p.y, depth), n.z)));
    const VF length = hn::Sqrt(hn::Add(hn::Mul(projectedX, projectedX), hn::Mul(projectedY, projectedY)));
    const MF facesCamera = hn::Lt(length, hn::Set(d, kShadowFilterMinProjectedNormal));
    const VF mx = hn::Div(projectedX, length), my = hn::Div(projectedY, length);
    const VF facing = hn::Div(hn::Abs(Dot3(n, Neg3(p))), hn::Sqrt(Dot3(p, p)));
    k.majorX = hn::IfThenElse(facesCamera, one, my);
    k.majorY = hn::IfThenElse(facesCamera, zero, hn::Neg(mx));
    k.minorLength = hn::IfThenElse(facesCamera, radius, hn::Mul(radius, facing));
  }
  return {hn::IfThenElse(blurs, k.majorX, one), hn::IfThenElse(blurs, k.majorY, zero),
          hn::IfThenElseZero(blurs, k.majorLength), hn::IfThenElseZero(blurs, k.minorLength)};
}

// ShadowFilterImage::Index of the pixels (x, y), lane by lane.
VI IndexV(DI di, const ShadowFilterImage& image, VI x, VI y) {
  static_assert(kShadowFilterTileSize == 16, "the shifts below divide by the tile size");
  const VI tile = hn::Add(hn::Mul(hn::ShiftRight<4>(y), hn::Set(di, image.tilesX)), hn::ShiftRight<4>(x));
  const VI slot = hn::GatherIndex(di, image.tileSlots, tile);
  const VI fifteen = hn::Set(di, 15);
  return hn::Add(hn::ShiftLeft<8>(slot), hn::Add(hn::ShiftLeft<4>(hn::And(y, fifteen)), hn::And(x, fifteen)));
}

// What a vector of taps reads: each tap pixel's texel and value.
struct TapsV {
  Vec3V<DF> position, normal;
  VF value;
};

// The taps at pixels (tapX, tapY): where every taken lane's tap lies at one offset from its centre
// (nearly always: neighbouring pixels' kernels share a direction), the taps are one run of a row
// within at most two tiles' rows, read with a load per tile; otherwise gathered lane by lane. Lanes
// not taken read pixels near their centres (set up, or the arrays' margins, ShadowFilterImage): values
// never used.
HWY_INLINE TapsV LoadTaps(const ShadowFilterImage& image, const float* values, VI tapX, VI tapY,
                          hn::Mask<DI> taken) {
  const DF d;
  const DI di;
  const ShadowFilterTexels& p = image.texels;
  const intptr_t first = hn::FindFirstTrue(di, taken);
  const int runX = hn::ExtractLane(tapX, size_t(first)) - int(first), runY = hn::ExtractLane(tapY, size_t(first));
  const int lanes = int(hn::Lanes(d));
  const bool run = hn::AllTrue(
      di, hn::Or(hn::Not(taken), hn::And(hn::Eq(tapX, hn::Iota(di, runX)), hn::Eq(tapY, hn::Set(di, runY)))));
  if (run && runX >= 0 && runX + lanes <= image.width) {
    const int tileRow = runY / kShadowFilterTileSize * image.tilesX;
    const int tileA = tileRow + runX / kShadowFilterTileSize;
    const int tileB = tileRow + (runX + lanes - 1) / kShadowFilterTileSize;
    const int32_t slotA = image.tileSlots[tileA], slotB = image.tileSlots[tileB];
    if (slotA >= 0 && slotB >= 0) {
      const ptrdiff_t column = runX % kShadowFilterTileSize;
      const ptrdiff_t row = ptrdiff_t(runY % kShadowFilterTileSize * kShadowFilterTileSize);
      const ptrdiff_t a = ptrdiff_t(slotA) * kShadowFilterTileSize * kShadowFilterTileSize + row + column;
      const ptrdiff_t b = ptrdiff_t(slotB) * kShadowFilterTileSize * kShadowFilterTileSize + row + column -
                          kShadowFilterTileSize;
      const MF inA = hn::FirstN(d, size_t(kShadowFilterTileSize - column));
      const auto load = [&](const float* array) {
        const VF fromA = hn::LoadU(d, array + a);
        return tileA == tileB ? fromA : hn::IfThenElse(inA, fromA, hn::LoadU(d, array + b));
      };
      return {{load(p.positionX), load(p.positionY), load(p.positionZ)},
              {load(p.normalX), load(p.normalY), load(p.normalZ)},
              load(values)};
    }
  }
  const VI index = IndexV(di, image, tapX, tapY);
  const auto gather = [&](const float* array) { return hn::GatherIndex(d, array, index); };
  return {{gather(p.positionX), gather(p.positionY), gather(p.positionZ)},
          {gather(p.normalX), gather(p.normalY), gather(p.normalZ)},
          gather(values)};
}

// Blur1D for the Lanes pixels from (x, y), all in one tile, along the major axis or the minor.
template <bool kMinor>
void BlurVector(const ShadowFilterImage& image, const float* values, int taps, int x, int y, float* out) {
  const DF d;
  const DI di;
  const ShadowFilterTexels& p = image.texels;
  const ShadowFilterKernels& kernels = image.kernels;
  const size_t centre = image.Index(x, y);
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const VF value = hn::LoadU(d, values + centre);
  const Vec3V<DF> cp{hn::LoadU(d, p.positionX + centre), hn::LoadU(d, p.positionY + centre),
                     hn::LoadU(d, p.positionZ + centre)};
  const VF length = hn::LoadU(d, (kMinor ? kernels.minorLength : kernels.majorLength) + centre);
  const MF blurs = hn::And(hn::Lt(cp.z, zero), hn::Ge(length, hn::Set(d, kShadowFilterMinBlurRadius)));
  if (hn::AllFalse(d, blurs)) {
    hn::StoreU(value, d, out);
    return;
  }
  const Vec3V<DF> cn{hn::LoadU(d, p.normalX + centre), hn::LoadU(d, p.normalY + centre),
                     hn::LoadU(d, p.normalZ + centre)};
  const VF majorX = hn::LoadU(d, kernels.majorX + centre), majorY = hn::LoadU(d, kernels.majorY + centre);
  const VF directionX = kMinor ? hn::Neg(majorY) : majorX;
  const VF directionY = kMinor ? majorX : majorY;
  const VI count = hn::IfThenElseZero(
      hn::RebindMask(di, blurs),
      taps > 0 ? hn::Set(di, taps) : hn::ConvertTo(di, hn::Ceil(hn::Sub(length, hn::Set(d, 0.5f)))));
  const VF spacing = taps > 0 ? hn::Div(length, hn::Set(d, float(taps) + 0.5f)) : one;
  const int maxCount = hn::GetLane(hn::MaxOfLanes(di, count));
  const VF centreX = hn::Add(hn::Iota(d, float(x)), hn::Set(d, 0.5f));
  const VF centreY = hn::Set(d, float(y) + 0.5f);
  const VI pixelX = hn::Iota(di, x), pixelY = hn::Set(di, y);
  const VF width = hn::Set(d, float(image.width)), height = hn::Set(d, float(image.height));
  const VF maxPlaneDistance = hn::Mul(hn::Set(d, kShadowFilterMaxPlaneDistance), hn::Neg(cp.z));
  VF sum = value, weightSum = one;
  for (int k = 1; k <= maxCount; ++k) {
    const MF active = hn::RebindMask(d, hn::Lt(hn::Set(di, k - 1), count));
    const VF t = hn::Mul(hn::Set(d, float(k)), spacing);
    const VF weight = taps > 0 ? one : MinStd(one, hn::Sub(length, hn::Sub(t, hn::Set(d, 0.5f))));
    for (const float side : {-1.0f, 1.0f}) {
      const VF offset = hn::Mul(hn::Set(d, side), t);
      const VF sx = hn::Floor(hn::Add(centreX, hn::Mul(offset, directionX)));
      const VF sy = hn::Floor(hn::Add(centreY, hn::Mul(offset, directionY)));
      const MF inside =
          hn::And(hn::And(hn::Ge(sx, zero), hn::Ge(sy, zero)), hn::And(hn::Lt(sx, width), hn::Lt(sy, height)));
      const MF taken = hn::And(active, inside);
      if (hn::AllFalse(d, taken)) continue;
      // Lanes not taken tap their own centre, which is set up.
      const auto takenI = hn::RebindMask(di, taken);
      const TapsV tap = LoadTaps(image, values, hn::IfThenElse(takenI, hn::ConvertTo(di, sx), pixelX),
                                 hn::IfThenElse(takenI, hn::ConvertTo(di, sy), pixelY), takenI);
      const MF accepted = hn::And(hn::And(taken, hn::Lt(tap.position.z, zero)),
                                  hn::And(hn::Gt(Dot3(tap.normal, cn), hn::Set(d, kShadowFilterMinNormalDot)),
                                          hn::Lt(hn::Abs(Dot3(cn, Sub3(tap.position, cp))), maxPlaneDistance)));
      sum = hn::IfThenElse(accepted, hn::Add(sum, hn::Mul(weight, tap.value)), sum);
      weightSum = hn::IfThenElse(accepted, hn::Add(weightSum, weight), weightSum);
    }
  }
  hn::StoreU(hn::IfThenElse(blurs, hn::Div(sum, weightSum), value), d, out);
}

// Whole vectors within each tile's part of the run; the rest of a tile's part by the scalar kernel.
template <bool kMinor>
void BlurRow(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin, int xEnd, float* out) {
  const int lanes = int(hn::Lanes(DF()));
  int x = xBegin;
  while (x < xEnd) {
    const int tileEnd = std::min(xEnd, (x / kShadowFilterTileSize + 1) * kShadowFilterTileSize);
    for (; x + lanes <= tileEnd; x += lanes) BlurVector<kMinor>(image, values, taps, x, y, out + (x - xBegin));
    if (x == tileEnd) continue;
    if (kMinor) {
      ShadowFilterMinorRowScalar(image, values, taps, y, x, tileEnd, out + (x - xBegin));
    } else {
      ShadowFilterMajorRowScalar(image, values, taps, y, x, tileEnd, out + (x - xBegin));
    }
    x = tileEnd;
  }
}

}  // namespace

void ShadowPenumbraRow(const ShadowFilterSetupContext& context, const uint32_t* word2, const uint32_t* word3, int x,
                       int y, int count, float* hard, ShadowFilterTileSummary* tiles) {
  const DF d;
  const DU du;
  const int lanes = int(hn::Lanes(d));
  int i = 0;
  while (i < count) {
    // Vectors within one tile, so that each adds to one summary.
    const int tileEnd = std::min(count, ((x + i) / kShadowFilterTileSize + 1) * kShadowFilterTileSize - x);
    ShadowFilterTileSummary& tile = tiles[(x + i) / kShadowFilterTileSize];
    for (; i + lanes <= tileEnd; i += lanes) {
      const VF depth = UnpackDepthV(d, hn::LoadU(du, word2 + i));
      const auto w3 = hn::LoadU(du, word3 + i);
      const MF geometry = Geometry(d, depth);
      const VF hardV = HardV(d, w3);
      const VF radius = PenumbraRadiusV(d, context, ViewPositionV(d, context, x + i, y, depth), depth,
                                        UnpackBlockerDistanceV(d, w3));
      hn::StoreU(hn::IfThenElse(geometry, hardV, hn::Set(d, 1.0f)), d, hard + i);
      // The radii are never NaN, so the maximum does not depend on the order of comparison.
      const VF tileRadius =
          hn::MaxOfLanes(d, hn::IfThenElse(geometry, radius, hn::Set(d, kShadowFilterNoRadius)));
      tile.maxRadius = std::max(tile.maxRadius, hn::GetLane(tileRadius));
      tile.geometryPixels += int32_t(hn::CountTrue(d, geometry));
      tile.litPixels += int32_t(hn::CountTrue(d, hn::And(geometry, hn::Ne(hardV, hn::Zero(d)))));
    }
    ShadowFilterPenumbraRowScalar(context, word2 + i, word3 + i, x + i, y, tileEnd - i, hard + i, tiles);
    i = tileEnd;
  }
}

void ShadowSetupRow(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                    const uint32_t* word3, int x, int y, int count, const ShadowFilterTexels& texels,
                    const ShadowFilterKernels* kernels) {
  const DF d;
  const DU du;
  const int lanes = int(hn::Lanes(d));
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  int i = 0;
  for (; i + lanes <= count; i += lanes) {
    const VF depth = UnpackDepthV(d, hn::LoadU(du, word2 + i));
    const auto w3 = hn::LoadU(du, word3 + i);
    const MF geometry = Geometry(d, depth);
    const Vec3V<DF> p = ViewPositionV(d, context, x + i, y, depth);
    const Vec3V<DF> n = UnpackNormalV(d, hn::LoadU(du, word1 + i), context.normalEncoding);
    hn::StoreU(hn::IfThenElseZero(geometry, p.x), d, texels.positionX + i);
    hn::StoreU(hn::IfThenElseZero(geometry, p.y), d, texels.positionY + i);
    hn::StoreU(hn::IfThenElseZero(geometry, p.z), d, texels.positionZ + i);
    hn::StoreU(hn::IfThenElseZero(geometry, n.x), d, texels.normalX + i);
    hn::StoreU(hn::IfThenElseZero(geometry, n.y), d, texels.normalY + i);
    hn::StoreU(hn::IfThenElseZero(geometry, n.z), d, texels.normalZ + i);
    hn::StoreU(hn::IfThenElse(geometry, HardV(d, w3), one), d, texels.hard + i);
    if (!kernels) continue;
    const VF radius = PenumbraRadiusV(d, context, p, depth, UnpackBlockerDistanceV(d, w3));
    const KernelV k = MakeKernelV(d, context.filter, p, n, hn::IfThenElseZero(geometry, radius));
    hn::StoreU(hn::IfThenElse(geometry, k.majorX, one), d, kernels->majorX + i);
    hn::StoreU(hn::IfThenElse(geometry, k.majorY, zero), d, kernels->majorY + i);
    hn::StoreU(hn::IfThenElseZero(geometry, k.majorLength), d, kernels->majorLength + i);
    hn::StoreU(hn::IfThenElseZero(geometry, k.minorLength), d, kernels->minorLength + i);
  }
  if (i == count) return;
  const ShadowFilterKernels tailKernels = kernels ? *kernels + size_t(i) : ShadowFilterKernels{};
  ShadowFilterSetupRowScalar(context, word1 + i, word2 + i, word3 + i, x + i, y, count - i, texels + size_t(i),
                             kernels ? &tailKernels : nullptr);
}

void ShadowMajorRow(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin, int xEnd,
                    float* out) {
  BlurRow<false>(image, values, taps, y, xBegin, xEnd, out);
}

void ShadowMinorRow(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin, int xEnd,
                    float* out) {
  BlurRow<true>(image, values, taps, y, xBegin, xEnd, out);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(ShadowPenumbraRow);
HWY_EXPORT(ShadowSetupRow);
HWY_EXPORT(ShadowMajorRow);
HWY_EXPORT(ShadowMinorRow);

void ShadowFilterPenumbraRowSimd(const ShadowFilterSetupContext& context, const uint32_t* word2, const uint32_t* word3,
                                 int x, int y, int count, float* hard, ShadowFilterTileSummary* tiles) {
  HWY_DYNAMIC_DISPATCH(ShadowPenumbraRow)(context, word2, word3, x, y, count, hard, tiles);
}

void ShadowFilterSetupRowSimd(const ShadowFilterSetupContext& context, const uint32_t* word1, const uint32_t* word2,
                              const uint32_t* word3, int x, int y, int count, const ShadowFilterTexels& texels,
                              const ShadowFilterKernels* kernels) {
  HWY_DYNAMIC_DISPATCH(ShadowSetupRow)(context, word1, word2, word3, x, y, count, texels, kernels);
}

void ShadowFilterMajorRowSimd(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                              int xEnd, float* out) {
  HWY_DYNAMIC_DISPATCH(ShadowMajorRow)(image, values, taps, y, xBegin, xEnd, out);
}

void ShadowFilterMinorRowSimd(const ShadowFilterImage& image, const float* values, int taps, int y, int xBegin,
                              int xEnd, float* out) {
  HWY_DYNAMIC_DISPATCH(ShadowMinorRow)(image, values, taps, y, xBegin, xEnd, out);
}

}  // namespace ssgi
#endif
