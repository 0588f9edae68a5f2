// The Highway twin of SsrTraceTileScalar (ssr_trace.cpp): the tile's pixels that trace their own ray
// are listed in row order, each lane one of them, and the lanes march through the Hi-Z together. A lane stops where
// MarchHiZ returns and keeps its state while the others go on: neighbouring rays are coherent, so the lanes mostly
// finish within a few steps of each other. The same operations in the same order as the scalar tracer and MarchHiZ, no
// fused multiply-add, no approximate division, std::min / std::clamp semantics, so every target gives the scalar bytes
// (tests/passes/ssr_trace_test.cpp).
#ifndef SSGI_PASSES_SSR_TRACE_SIMD_FRAME_
#define SSGI_PASSES_SSR_TRACE_SIMD_FRAME_
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/camera.h"
#include "core/render_modes.h"

namespace ssgi {

// What the row kernel reads of SsrTraceInputs, flattened so that only plain values and pointers
// cross the dispatch boundary.
inline constexpr int kMaxHiZLevels = 15;  // a 16384-pixel side: levels 0 .. 14
struct SsrTraceFrame {
  int width, height;
  const uint32_t* word1;  // G-buffer words 1 and 2 at pixel (0, 0), rows gbufferStride apart
  const uint32_t* word2;
  int32_t gbufferStride;
  NormalEncoding encoding;
  const ViewProjection* view;  // the perspective camera
  int levels;                  // Hi-Z levels; level k is max(1, width >> k) x max(1, height >> k)
  const float* hiz[kMaxHiZLevels];
  // Padded to 16 so that a 16-lane vector holds the whole table (unused entries 0).
  int32_t hizStride[kMaxHiZLevels + 1];
  // Every level addressed from one base: level k's texel (x, y) is hizBase[hizOffset[k] + y *
  // hizStride[k] + x], so a gather whose lanes are at different levels is still one gather.
  // hizOffsetsFit is false where the levels lie too far apart in memory for 32-bit indices.
  const float* hizBase;
  int32_t hizOffset[kMaxHiZLevels + 1];
  bool hizOffsetsFit;
};

}  // namespace ssgi
#endif  // SSGI_PASSES_SSR_TRACE_SIMD_FRAME_

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/ssr_trace_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep

#include "hwy/highway.h"

#include "core/camera-inl.h"
#include "core/gbuffer-inl.h"
#include "core/math-inl.h"
#include "core/row-inl.h"
#include "passes/ssr_trace.h"

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

VF SafeReciprocalV(VF v) {
  const DF df;
  return hn::IfThenElse(hn::Lt(hn::Abs(v), hn::Set(df, kHiZTinyComponent)), hn::Set(df, kHiZNever),
                        hn::Div(hn::Set(df, 1.0f), v));
}

MF InsideImageV(VF x, VF y, float width, float height) {
  const DF df;
  const VF zero = hn::Zero(df);
  return hn::And(hn::And(hn::Ge(x, zero), hn::Lt(x, hn::Set(df, width))),
                 hn::And(hn::Ge(y, zero), hn::Lt(y, hn::Set(df, height))));
}

// MarchHiZ's state for a vector of rays.
struct MarchLanes {
  MF live;  // still marching
  MF hit;
  VI steps;  // HiZMarch::iterations
  VF posX, posY, posZ;  // HiZMarch::position
  VF t;
  VI level;
  VF dirX, dirY, dirZ, invX, invY, invZ;
  MF positiveX, positiveY;
  VF nudgeX, nudgeY;  // the boundary nudge, signed along the direction
  VF tEnd;
};

// MarchHiZ's set-up for the lanes of `live`, whose origins are pixel centres: already strictly
// inside their level-0 cells, where MarchHiZ's snap leaves them.
HWY_INLINE MarchLanes StartMarch(const SsrTraceFrame& frame, MF live, VF originX, VF originY, VF originZ,
                                  const Vec3V<DF>& end) {
  const DF df;
  const DI di;
  MarchLanes m;
  m.live = hn::And(live, hn::And(hn::IsFinite(originZ),
                                 hn::And(hn::IsFinite(end.x), hn::And(hn::IsFinite(end.y), hn::IsFinite(end.z)))));
  m.hit = hn::FirstN(df, 0);
  // Lanes that do not march start at 0 and never move, so no NaN or out-of-range value reaches a
  // float -> int conversion or a gather index.
  m.posX = hn::IfThenElseZero(m.live, originX);
  m.posY = hn::IfThenElseZero(m.live, originY);
  m.posZ = hn::IfThenElseZero(m.live, originZ);
  m.t = hn::Zero(df);
  m.level = hn::Zero(di);
  m.steps = hn::Zero(di);
  m.dirX = hn::Sub(hn::IfThenElseZero(m.live, end.x), m.posX);
  m.dirY = hn::Sub(hn::IfThenElseZero(m.live, end.y), m.posY);
  m.dirZ = hn::Sub(hn::IfThenElseZero(m.live, end.z), m.posZ);
  m.invX = SafeReciprocalV(m.dirX);
  m.invY = SafeReciprocalV(m.dirY);
  m.invZ = SafeReciprocalV(m.dirZ);
  const VF minusTiny = hn::Set(df, -kHiZTinyComponent);
  m.positiveX = hn::Not(hn::Le(m.dirX, minusTiny));
  m.positiveY = hn::Not(hn::Le(m.dirY, minusTiny));
  const VF nudge = hn::Set(df, kHiZBoundaryNudge);
  const VF minusNudge = hn::Set(df, -kHiZBoundaryNudge);
  m.nudgeX = hn::IfThenElse(m.positiveX, nudge, minusNudge);
  m.nudgeY = hn::IfThenElse(m.positiveY, nudge, minusNudge);
  const VF borderX = hn::IfThenElseZero(m.positiveX, hn::Set(df, float(frame.width)));
  const VF borderY = hn::IfThenElseZero(m.positiveY, hn::Set(df, float(frame.height)));
  const VF exitX = hn::Mul(hn::Sub(borderX, m.posX), m.invX);
  const VF exitY = hn::Mul(hn::Sub(borderY, m.posY), m.invY);
  m.tEnd = MinStd(MinStd(hn::Set(df, 1.0f), exitX), exitY);
  return m;
}

// int(v) for v in [0, 2^23): floor(v) + 2^23 holds that integer in its mantissa bits. hn::ConvertTo
// gives the same integers but pays for fixing up out-of-range inputs on every call.
HWY_INLINE VI TruncateSmall(VF v) {
  const DF df;
  const DI di;
  constexpr float kTwoTo23 = 8388608.0f;
  return hn::Sub(hn::BitCast(di, hn::Add(hn::Floor(v), hn::Set(df, kTwoTo23))), hn::BitCast(di, hn::Set(df, kTwoTo23)));
}

// Targets whose gathers are the hardware's, which reads any address the indices give: there the
// levels, separate planes, are read through one base (SsrTraceFrame::hizOffset).
constexpr bool kHardwareGather = HWY_TARGET == HWY_AVX2 || HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL;

// The Hi-Z texel (cellX, cellY) of each live lane's level, 0 in the other lanes. Neighbouring rays
// march alike, but at any step about half the vectors have live lanes at two or more levels: with
// hardware gathers one GatherIndex from the common base serves every mix of levels. Elsewhere (and
// where the levels lie too far apart), one GatherIndex when the live lanes share their level, else a
// load per lane.
HWY_INLINE VF ClosestInverseDepth(const SsrTraceFrame& frame, const MarchLanes& m, VI cellX, VI cellY) {
  const DF df;
  const DI di;
  const auto live = hn::RebindMask(di, m.live);
  const VI level = hn::IfThenElseZero(live, m.level);
  if (kHardwareGather && frame.hizOffsetsFit) {
    const VI index =
        hn::Add(LookupSmallTable<kMaxHiZLevels + 1>(di, frame.hizOffset, level),
                hn::Add(hn::Mul(cellY, LookupSmallTable<kMaxHiZLevels + 1>(di, frame.hizStride, level)), cellX));
    return hn::GatherIndex(df, frame.hizBase, hn::IfThenElseZero(live, index));
  }
  HWY_ALIGN int32_t laneLevel[hn::MaxLanes(DI())];
  hn::Store(level, di, laneLevel);
  const int32_t first = laneLevel[hn::FindFirstTrue(di, live)];
  if (hn::AllTrue(di, hn::Or(hn::Not(live), hn::Eq(level, hn::Set(di, first))))) {
    const VI index = hn::Add(hn::Mul(cellY, hn::Set(di, frame.hizStride[first])), cellX);
    return hn::GatherIndex(df, frame.hiz[first], hn::IfThenElseZero(live, index));
  }
  // Lanes out of `live` read texel (0, 0) of level 0.
  HWY_ALIGN int32_t laneIndex[hn::MaxLanes(DI())];
  hn::Store(hn::IfThenElseZero(live, hn::Add(hn::Mul(cellY, hn::GatherIndex(di, frame.hizStride, level)), cellX)), di,
            laneIndex);
  HWY_ALIGN float closest[hn::MaxLanes(DF())];
  for (size_t i = 0; i < hn::Lanes(df); ++i) closest[i] = frame.hiz[laneLevel[i]][laneIndex[i]];
  return hn::Load(df, closest);
}

// Step `step` (1-based) of MarchHiZ's loop for the live lanes of m: a lane stops where MarchHiZ
// returns; the lanes that step count it in m.steps.
HWY_INLINE void StepMarch(const SsrTraceFrame& frame, const SsrTraceParams& params, int step, MarchLanes& m) {
  const DF df;
  const DI di;
  const VF zero = hn::Zero(df);
  const VI one = hn::Set(di, 1);
  const VI imageWidth = hn::Set(di, frame.width);
  const VI imageHeight = hn::Set(di, frame.height);
  const VF never = hn::Set(df, kHiZNever);
  m.steps = hn::Add(m.steps, hn::IfThenElseZero(hn::RebindMask(di, m.live), one));
  // CellIndex. Positions are never NaN (StartMarch), so hn::Min / hn::Max clamp as std::clamp does;
  // level k has max(1, size >> k) cells (PyramidHalvedSize).
  const VF maxCoordinate = hn::Set(df, kHiZMaxCoordinate);
  const VI sizeX = hn::Max(imageWidth >> m.level, one);
  const VI sizeY = hn::Max(imageHeight >> m.level, one);
  const VI pixelX = TruncateSmall(hn::Min(hn::Max(m.posX, zero), maxCoordinate));
  const VI pixelY = TruncateSmall(hn::Min(hn::Max(m.posY, zero), maxCoordinate));
  const VI cellX = hn::Min(pixelX >> m.level, hn::Sub(sizeX, one));
  const VI cellY = hn::Min(pixelY >> m.level, hn::Sub(sizeY, one));
  // The first step only leaves the origin's cell: its depth is not needed.
  VF tDepth = never;
  if (step > 1) {
    const VF closest = ClosestInverseDepth(frame, m, cellX, cellY);
    tDepth = hn::IfThenElse(hn::Le(m.posZ, closest), zero,
                            hn::IfThenElse(hn::Le(m.dirZ, hn::Set(df, -kHiZTinyComponent)),
                                           hn::Mul(hn::Sub(closest, m.posZ), m.invZ), never));
  }
  const VI nextX = hn::Add(cellX, one);
  const VI nextY = hn::Add(cellY, one);
  const auto positiveXi = hn::RebindMask(di, m.positiveX);
  const auto positiveYi = hn::RebindMask(di, m.positiveY);
  // CellBoundary: the last cell's upper boundary is the image border.
  const VI upperX = hn::IfThenElse(hn::Eq(nextX, sizeX), imageWidth, nextX << m.level);
  const VI upperY = hn::IfThenElse(hn::Eq(nextY, sizeY), imageHeight, nextY << m.level);
  const VF boundaryX = hn::ConvertTo(df, hn::IfThenElse(positiveXi, upperX, cellX << m.level));
  const VF boundaryY = hn::ConvertTo(df, hn::IfThenElse(positiveYi, upperY, cellY << m.level));
  const VF tX = hn::Mul(hn::Sub(boundaryX, m.posX), m.invX);
  const VF tY = hn::Mul(hn::Sub(boundaryY, m.posY), m.invY);
  const VF tCell = MinStd(tX, tY);

  const MF depthStep = hn::Lt(tDepth, tCell);
  const VF tStep = hn::IfThenElse(depthStep, tDepth, tCell);
  const VF tNext = hn::Add(m.t, tStep);
  // A depth step past the segment's end and a cell step reaching it end the march where it is.
  const MF ends =
      hn::Or(hn::And(depthStep, hn::Gt(tNext, m.tEnd)), hn::AndNot(depthStep, hn::Ge(tNext, m.tEnd)));
  const MF moving = hn::AndNot(ends, m.live);
  const MF depthMove = hn::And(depthStep, moving);
  const MF cellMove = hn::AndNot(depthStep, moving);
  const MF xWins = hn::Le(tX, tY);
  VF x = hn::Add(m.posX, hn::Mul(m.dirX, tStep));
  VF y = hn::Add(m.posY, hn::Mul(m.dirY, tStep));
  x = hn::IfThenElse(hn::And(cellMove, xWins), hn::Add(boundaryX, m.nudgeX), x);
  y = hn::IfThenElse(hn::AndNot(xWins, cellMove), hn::Add(boundaryY, m.nudgeY), y);
  m.posX = hn::IfThenElse(moving, x, m.posX);
  m.posY = hn::IfThenElse(moving, y, m.posY);
  m.posZ = hn::IfThenElse(moving, hn::Add(m.posZ, hn::Mul(m.dirZ, tStep)), m.posZ);
  m.t = hn::IfThenElse(moving, tNext, m.t);

  const MF hitNow = hn::And(depthMove, hn::RebindMask(df, hn::Eq(m.level, hn::Zero(di))));
  m.hit = hn::Or(m.hit, hitNow);
  const MF leaves = hn::AndNot(InsideImageV(m.posX, m.posY, float(frame.width), float(frame.height)), cellMove);
  m.live = hn::AndNot(hn::Or(hitNow, leaves), moving);
  const VI topLevel = hn::Set(di, frame.levels - 1);
  const VI coarser = step == 1 ? hn::Set(di, std::min(params.startLevel, frame.levels - 1))
                               : hn::Min(hn::Add(m.level, one), topLevel);
  m.level = hn::IfThenElse(hn::RebindMask(di, depthMove), hn::Sub(m.level, one),
                           hn::IfThenElse(hn::RebindMask(di, cellMove), coarser, m.level));
}

// EdgeFade of the scalar tracer.
VF EdgeFadeV(VF p, float size, float edgeFade) {
  const DF df;
  if (!(edgeFade > 0.0f)) return hn::Set(df, 1.0f);
  const VF fade = hn::Div(MinStd(p, hn::Sub(hn::Set(df, size), p)), hn::Set(df, edgeFade * size));
  return ClampStd(fade, hn::Zero(df), hn::Set(df, 1.0f));
}

// PixelTracer::Trace's rays for a vector of pixels, up to the march.
struct RayLanes {
  MF traced;
  VF originX, originY, originZ;
  Vec3V<DF> end;  // (x, y, 1/d)
  Vec3V<DF> r;    // the view-space reflected direction
  VF towardCamera;
};

// The rays of the pixels at image positions (px, py), whose G-buffer words 1 and 2 are word1 and d:
// `candidates` are the lanes with geometry below the roughness cut-off. Other lanes compute along,
// unused.
RayLanes SetUpRays(const SsrTraceFrame& frame, const SsrTraceParams& params, VF px, VF py, hn::Vec<DU> word1, VF d,
                   MF candidates) {
  const DF df;
  const VF zero = hn::Zero(df);
  const VF one = hn::Set(df, 1.0f);
  const ViewProjection& view = *frame.view;
  RayLanes rays;
  rays.originX = px;
  rays.originY = py;
  const Vec3V<DF> p = Scale3(PixelRayV(df, view, px, py).direction, d);
  const Vec3V<DF> v = Div3(p, Length3(p));
  const Vec3V<DF> n = UnpackNormalV(df, word1, frame.encoding);
  rays.r = Sub3(v, Scale3(n, hn::Mul(hn::Set(df, 2.0f), Dot3(v, n))));
  const VF fadeToCamera = hn::Sub(one, hn::Div(rays.r.z, hn::Set(df, params.towardCameraFade)));
  rays.towardCamera = hn::IfThenElse(hn::Le(rays.r.z, zero), one, fadeToCamera);
  // Near-plane clip before projecting.
  VF length = hn::Mul(hn::Set(df, kSsrMaxRayLengthInDepths), d);
  length = hn::IfThenElse(hn::Gt(rays.r.z, zero),
                          MinStd(length, hn::Div(hn::Sub(d, hn::Set(df, view.nearPlane)), rays.r.z)), length);
  const Vec3V<DF> q = Add3(p, Scale3(rays.r, length));
  const VF depth = hn::Neg(q.z);
  rays.traced = hn::And(candidates, hn::Gt(rays.towardCamera, zero));
  rays.traced = hn::And(rays.traced, hn::And(hn::Gt(length, zero), hn::Gt(depth, zero)));

  // Project.
  const VF half = hn::Set(df, 0.5f);
  const VF ndcX = hn::Div(q.x, hn::Mul(depth, hn::Set(df, view.halfX)));
  const VF ndcY = hn::Div(q.y, hn::Mul(depth, hn::Set(df, view.halfY)));
  rays.end.x = hn::Mul(hn::Add(hn::Mul(ndcX, half), half), hn::Set(df, float(frame.width)));
  rays.end.y = hn::Mul(hn::Sub(half, hn::Mul(ndcY, half)), hn::Set(df, float(frame.height)));
  rays.end.z = hn::Div(one, depth);
  rays.originZ = hn::Div(one, d);
  return rays;
}

// One vector of rays' outputs, SsrTraceOutputs' values.
struct RayResults {
  VF hitX, hitY, confidence, steps;
};

// The rest of PixelTracer::Trace after the march: the surface at the hit must be in front of the
// background and face the ray; the confidence fades.
RayResults FinishRays(const SsrTraceFrame& frame, const SsrTraceParams& params, const RayLanes& rays,
                      const MarchLanes& m) {
  const DF df;
  const DI di;
  const DU du;
  const VF zero = hn::Zero(df);
  const VF one = hn::Set(df, 1.0f);
  const VF none = hn::Set(df, -1.0f);
  const VF steps = hn::ConvertTo(df, m.steps);
  MF found = hn::And(m.hit, hn::And(InsideImageV(m.posX, m.posY, float(frame.width), float(frame.height)),
                                    hn::Gt(m.posZ, zero)));
  if (hn::AllFalse(df, found)) return {none, none, zero, steps};
  const auto foundI = hn::RebindMask(di, found);
  const VI hx = hn::Min(hn::ConvertTo(di, hn::IfThenElseZero(found, m.posX)), hn::Set(di, frame.width - 1));
  const VI hy = hn::Min(hn::ConvertTo(di, hn::IfThenElseZero(found, m.posY)), hn::Set(di, frame.height - 1));
  const VI index = hn::IfThenElseZero(foundI, hn::Add(hn::Mul(hy, hn::Set(di, frame.gbufferStride)), hx));
  const VF hitDepth = UnpackDepthV(df, hn::GatherIndex(du, frame.word2, index));
  found = hn::And(found, hn::Lt(hitDepth, hn::Set(df, kBackgroundDepth)));
  const Vec3V<DF> hitNormal = UnpackNormalV(df, hn::GatherIndex(du, frame.word1, index), frame.encoding);
  found = hn::AndNot(hn::Ge(Dot3(hitNormal, rays.r), zero), found);

  const VF excess = hn::Sub(hn::Div(hn::Div(one, m.posZ), hitDepth), one);
  const VF thickness = ClampStd(hn::Sub(hn::Set(df, 2.0f), hn::Div(excess, hn::Set(df, params.thickness))), zero, one);
  const VF fadeX = EdgeFadeV(m.posX, float(frame.width), params.edgeFade);
  const VF fadeY = EdgeFadeV(m.posY, float(frame.height), params.edgeFade);
  const VF fade = hn::Mul(hn::Mul(hn::Mul(thickness, rays.towardCamera), fadeX), fadeY);
  found = hn::And(found, hn::Gt(fade, zero));
  return {hn::IfThenElse(found, m.posX, none), hn::IfThenElse(found, m.posY, none),
          hn::IfThenElseZero(found, MinStd(fade, one)), steps};
}

constexpr int kMaxTilePixels = kSsrTraceTileSize * kSsrTraceTileSize;

// Lane i: row[min((x0 + i) & mask, last)], for x0 a multiple of 4 and mask ~1 or ~3: where a vector
// holds whole 4-pixel blocks, the vector at x0 loaded once and its lanes shuffled; else a gather.
template <class D>
hn::Vec<D> SourceLanes(D d, const hn::TFromD<D>* row, size_t x0, int last, int mask) {
  const hn::RebindToSigned<D> di;
  const auto offsets = hn::And(hn::Iota(di, 0), hn::Set(di, mask));
  if (hn::Lanes(d) >= 4) {
    return hn::TableLookupLanes(LoadRow(d, row, x0, size_t(last) + 1, hn::TFromD<D>(0)),
                                hn::IndicesFromVec(d, offsets));
  }
  const auto columns = hn::Min(hn::And(hn::Iota(di, int32_t(x0)), hn::Set(di, mask)), hn::Set(di, last));
  return hn::GatherIndex(d, row, columns);
}

// CopySharedHits's twin, a row's pixels in the lanes; codes: every pixel's SsrRaySource, rows
// tile.x1 - tile.x0 apart.
void CopySharedHitsV(const SsrTraceTile& tile, const int32_t* codes, SsrTraceOutputs& out) {
  const DF df;
  const DI di;
  const size_t width = size_t(tile.x1 - tile.x0), end = size_t(tile.x1);
  // Blocks first: a quad's top-left pixel may itself take its block's ray.
  for (const SsrRaySource shared : {SsrRaySource::kBlock, SsrRaySource::kQuad}) {
    const int mask = shared == SsrRaySource::kBlock ? ~3 : ~1;
    for (int y = tile.y0; y < tile.y1; ++y) {
      const int32_t* rowCodes = codes + size_t(y - tile.y0) * width;
      const size_t sy = size_t(y & mask);
      float* iterations = IterationsRow(out, y);
      for (size_t x = size_t(tile.x0); x < end; x += hn::Lanes(df)) {
        const MF take = hn::RebindMask(
            df, hn::Eq(LoadRow(di, rowCodes, x - size_t(tile.x0), width, 0), hn::Set(di, int32_t(shared))));
        if (hn::AllFalse(df, take)) continue;
        for (Plane<float>* plane : {&out.hitX, &out.hitY, &out.confidence}) {
          float* row = plane->MutableRow(size_t(y));
          const VF source = SourceLanes(df, plane->ConstRow(sy), x, tile.x1 - 1, mask);
          StoreRow(hn::IfThenElse(take, source, LoadRow(df, row, x, end, 0.0f)), df, row, x, end);
        }
        if (iterations)
          StoreRow(hn::IfThenZeroElse(take, LoadRow(df, iterations, x, end, 0.0f)), df, iterations, x, end);
      }
    }
  }
}

// SsrRaySourceOf's test against the source pixels (x & mask, sourceY) of the lanes at xs in row y,
// whose G-buffer words are word1 and d: whether each lane takes that source's ray.
MF SharesRay(const SsrTraceFrame& frame, const SsrTraceParams& params, size_t x0, int y, int mask, int lastX,
             hn::Vec<DU> word1, VF d, float threshold) {
  const DF df;
  const DI di;
  const DU du;
  const int sourceY = y & mask;
  const size_t row = size_t(sourceY) * size_t(frame.gbufferStride);
  const auto sourceWord = SourceLanes(du, frame.word1 + row, x0, lastX, mask);
  const VF sourceDepth = UnpackDepthV(df, SourceLanes(du, frame.word2 + row, x0, lastX, mask));
  const VI xs = hn::Iota(di, int32_t(x0));
  MF shares =
      sourceY == y ? hn::RebindMask(df, hn::Ne(hn::And(xs, hn::Set(di, mask)), xs)) : hn::FirstN(df, hn::Lanes(df));
  const VF cutoff = hn::Set(df, params.roughnessCutoff);
  const VF least = hn::Set(df, threshold);
  const VF sourceRoughness = UnpackRoughnessV(df, sourceWord);
  shares =
      hn::And(shares, hn::And(hn::Lt(sourceDepth, hn::Set(df, kBackgroundDepth)), hn::Gt(sourceDepth, hn::Zero(df))));
  shares = hn::And(shares, hn::And(hn::Lt(sourceRoughness, cutoff), hn::Ge(sourceRoughness, least)));
  shares = hn::And(shares, hn::Ge(UnpackRoughnessV(df, word1), least));
  shares = hn::And(
      shares, hn::Le(hn::Abs(hn::Sub(d, sourceDepth)), hn::Mul(hn::Set(df, kSharedRayDepthTolerance), sourceDepth)));
  // NormalCodesClose: each packed axis code within the encoding's steps.
  const auto codes = [&](auto v, int shift, uint32_t fieldMask) {
    return hn::BitCast(di, hn::And(hn::ShiftRightSame(v, shift), hn::Set(du, fieldMask)));
  };
  const bool xyz8 = frame.encoding == NormalEncoding::kXyz8;
  const int fields = xyz8 ? 3 : 2, bits = xyz8 ? 8 : 12;
  const VI beyond = hn::Set(di, (xyz8 ? kSharedRayOctStepsXyz8 : kSharedRayOctStepsOct24) + 1);
  for (int k = 0; k < fields; ++k) {
    const uint32_t fieldMask = (1u << bits) - 1u;
    const VI difference = hn::Sub(codes(word1, k * bits, fieldMask), codes(sourceWord, k * bits, fieldMask));
    shares = hn::And(shares, hn::RebindMask(df, hn::Lt(hn::Abs(difference), beyond)));
  }
  return shares;
}

void TraceTile(const SsrTraceFrame& frame, const SsrTraceParams& params, const SsrTraceTile& tile, SsrTraceOutputs& out,
               SsrTraceCounts& counts) {
  const DF df;
  const DI di;
  const DU du;
  const size_t lanes = hn::Lanes(df);
  const int width = tile.x1 - tile.x0;
  // The tile's pixels that trace their own ray, as (y - y0) << 8 | (x - x0), in row order (padded
  // for whole-vector writes), and every pixel's source (SsrRaySource), rows `width`
  // apart.
  HWY_ALIGN int32_t traced[kMaxTilePixels + hn::MaxLanes(DI())];
  size_t tracedCount = 0;
  int32_t sources[kMaxTilePixels];
  bool anyShared = false;
  const bool sharing = params.quadRoughness < params.roughnessCutoff || params.blockRoughness < params.roughnessCutoff;
  const size_t end = size_t(tile.x1);
  for (int y = tile.y0; y < tile.y1; ++y) {
    const uint32_t* word1Row = frame.word1 + size_t(y) * size_t(frame.gbufferStride);
    const uint32_t* word2Row = frame.word2 + size_t(y) * size_t(frame.gbufferStride);
    float* iterations = IterationsRow(out, y);
    for (size_t x0 = size_t(tile.x0); x0 < end; x0 += lanes) {
      // "No hit" first; the traced pixels and the shared ones are overwritten below.
      StoreRow(hn::Set(df, -1.0f), df, out.hitX.MutableRow(size_t(y)), x0, end);
      StoreRow(hn::Set(df, -1.0f), df, out.hitY.MutableRow(size_t(y)), x0, end);
      StoreRow(hn::Zero(df), df, out.confidence.MutableRow(size_t(y)), x0, end);
      if (iterations) StoreRow(hn::Zero(df), df, iterations, x0, end);
      int32_t* rowSources = sources + size_t(y - tile.y0) * size_t(width);
      const size_t column = x0 - size_t(tile.x0);
      StoreRow(hn::Set(di, int32_t(SsrRaySource::kOwn)), di, rowSources, column, size_t(width));
      const auto word1 = LoadRow(du, word1Row, x0, end, 0u);
      const VF d = UnpackDepthV(df, LoadRow(du, word2Row, x0, end, PackDepth(kBackgroundDepth)));
      // The scalar tracer's first two tests: geometry, and smooth enough.
      MF own = hn::And(hn::Lt(d, hn::Set(df, kBackgroundDepth)), hn::Gt(d, hn::Zero(df)));
      own = hn::And(own, hn::Lt(UnpackRoughnessV(df, word1), hn::Set(df, params.roughnessCutoff)));
      if (hn::AllFalse(df, own)) continue;
      if (sharing) {
        // A threshold at or above the cut-off shares nothing: its gathers are skipped.
        const auto shares = [&](int mask, float threshold) {
          if (!(threshold < params.roughnessCutoff)) return hn::FirstN(df, 0);
          return hn::And(own, SharesRay(frame, params, x0, y, mask, tile.x1 - 1, word1, d, threshold));
        };
        const MF block = shares(~3, params.blockRoughness);
        const MF quad = hn::AndNot(block, shares(~1, params.quadRoughness));
        if (!hn::AllFalse(df, hn::Or(block, quad))) {
          anyShared = true;
          StoreRow(hn::IfThenElse(hn::RebindMask(di, block), hn::Set(di, int32_t(SsrRaySource::kBlock)),
                                  hn::IfThenElse(hn::RebindMask(di, quad), hn::Set(di, int32_t(SsrRaySource::kQuad)),
                                                 hn::Set(di, int32_t(SsrRaySource::kOwn)))),
                   di, rowSources, column, size_t(width));
          own = hn::AndNot(hn::Or(block, quad), own);
        }
      }
      const VI packed = hn::Or(hn::ShiftLeft<8>(hn::Set(di, y - tile.y0)), hn::Iota(di, int32_t(column)));
      // Compress in a register and a whole-vector store: AVX-512's compress-to-memory is microcoded on
      // AMD's Zen 4 and 5, tens of cycles a store.
      const auto tracing = hn::RebindMask(di, own);
      hn::StoreU(hn::Compress(packed, tracing), di, traced + tracedCount);
      tracedCount += hn::CountTrue(di, tracing);
    }
  }

  // The rays of the vector at traced[i], marching.
  struct VectorRays {
    MF valid;
    VI x, y;
    RayLanes rays;
    MarchLanes march;
  };
  const auto start = [&](size_t i, VectorRays& v) {
    v.valid = hn::FirstN(df, std::min(lanes, tracedCount - i));
    const VI packed = hn::IfThenElseZero(hn::RebindMask(di, v.valid), hn::LoadU(di, traced + i));
    v.x = hn::Add(hn::And(packed, hn::Set(di, 255)), hn::Set(di, tile.x0));
    v.y = hn::Add(hn::ShiftRight<8>(packed), hn::Set(di, tile.y0));
    const VI index = hn::Add(hn::Mul(v.y, hn::Set(di, frame.gbufferStride)), v.x);
    const auto word1 = hn::GatherIndex(du, frame.word1, index);
    const VF d = UnpackDepthV(df, hn::GatherIndex(du, frame.word2, index));
    const VF half = hn::Set(df, 0.5f);
    const VF px = hn::Add(hn::ConvertTo(df, v.x), half);
    const VF py = hn::Add(hn::ConvertTo(df, v.y), half);
    v.rays = SetUpRays(frame, params, px, py, word1, d, v.valid);
    v.march = StartMarch(frame, v.rays.traced, v.rays.originX, v.rays.originY, v.rays.originZ, v.rays.end);
    counts.rays += hn::CountTrue(df, v.rays.traced);
  };
  const auto finish = [&](const VectorRays& v) {
    counts.iterations += uint64_t(hn::GetLane(hn::SumOfLanes(di, v.march.steps)));
    const RayResults results = FinishRays(frame, params, v.rays, v.march);
    HWY_ALIGN int32_t x[hn::MaxLanes(DI())], y[hn::MaxLanes(DI())];
    HWY_ALIGN float hitX[hn::MaxLanes(DF())], hitY[hn::MaxLanes(DF())], confidence[hn::MaxLanes(DF())],
        steps[hn::MaxLanes(DF())];
    hn::Store(v.x, di, x);
    hn::Store(v.y, di, y);
    hn::Store(results.hitX, df, hitX);
    hn::Store(results.hitY, df, hitY);
    hn::Store(results.confidence, df, confidence);
    hn::Store(results.steps, df, steps);
    const size_t count = hn::CountTrue(df, v.valid);
    for (size_t i = 0; i < count; ++i) {
      out.hitX.MutableRow(size_t(y[i]))[x[i]] = hitX[i];
      out.hitY.MutableRow(size_t(y[i]))[x[i]] = hitY[i];
      out.confidence.MutableRow(size_t(y[i]))[x[i]] = confidence[i];
      if (float* iterations = IterationsRow(out, y[i])) iterations[x[i]] = steps[i];
    }
  };
  // Two vectors march side by side: each step waits on its Hi-Z gather, and the other vector's step
  // fills that wait (a third, or refilling a finished vector's place, measured no faster). Each
  // vector steps exactly as it would alone.
  for (size_t i = 0; i < tracedCount; i += 2 * lanes) {
    VectorRays a, b;
    start(i, a);
    const bool hasB = i + lanes < tracedCount;
    if (hasB) start(i + lanes, b);
    for (int step = 1; step <= params.maxIterations; ++step) {
      const bool liveA = !hn::AllFalse(df, a.march.live);
      const bool liveB = hasB && !hn::AllFalse(df, b.march.live);
      if (!liveA && !liveB) break;
      if (liveA) StepMarch(frame, params, step, a.march);
      if (liveB) StepMarch(frame, params, step, b.march);
    }
    finish(a);
    if (hasB) finish(b);
  }
  if (anyShared) CopySharedHitsV(tile, sources, out);
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "core/check.h"

namespace ssgi {

HWY_EXPORT(TraceTile);

namespace {

SsrTraceFrame FlattenInputs(const SsrTraceInputs& in) {
  const GBuffer& g = in.gbuffer;
  SsrTraceFrame frame{};
  frame.width = g.width();
  frame.height = g.height();
  frame.word1 = g.word[GBufferWord::kNormalRoughness].ConstRow(0);
  frame.word2 = g.word[GBufferWord::kDepth].ConstRow(0);
  SSGI_CHECK_EQ(g.word[GBufferWord::kNormalRoughness].PixelsPerRow(), g.word[GBufferWord::kDepth].PixelsPerRow());
  frame.gbufferStride = int32_t(g.word[GBufferWord::kNormalRoughness].PixelsPerRow());
  frame.encoding = g.normalEncoding;
  frame.view = &in.view;
  frame.levels = int(in.hiz.levels.size());
  SSGI_CHECK_LE(frame.levels, kMaxHiZLevels);
  for (int k = 0; k < frame.levels; ++k) {
    const Plane<float>& level = in.hiz.levels[size_t(k)];
    frame.hiz[k] = level.ConstRow(0);
    SSGI_CHECK_EQ(level.xsize(), size_t(std::max(1, frame.width >> k)));
    SSGI_CHECK_EQ(level.ysize(), size_t(std::max(1, frame.height >> k)));
    frame.hizStride[k] = int32_t(level.PixelsPerRow());
  }
  // The lowest level address as the common base; every level's offset from it, and its last texel,
  // must be a 32-bit index.
  const auto address = [](const float* p) { return reinterpret_cast<uintptr_t>(p); };
  frame.hizBase = *std::min_element(frame.hiz, frame.hiz + frame.levels,
                                    [&](const float* a, const float* b) { return address(a) < address(b); });
  frame.hizOffsetsFit = true;
  for (int k = 0; k < frame.levels; ++k) {
    const uintptr_t offset = (address(frame.hiz[k]) - address(frame.hizBase)) / sizeof(float);
    const uintptr_t last = offset + uintptr_t(frame.hizStride[k]) * in.hiz.levels[size_t(k)].ysize();
    frame.hizOffsetsFit = frame.hizOffsetsFit && last <= uintptr_t(INT32_MAX);
    frame.hizOffset[k] = int32_t(std::min<uintptr_t>(offset, INT32_MAX));
  }
  return frame;
}

}  // namespace

void SsrTraceTileSimd(const SsrTraceInputs& in, const SsrTraceParams& params, const SsrTraceTile& tile,
                      SsrTraceOutputs& out, SsrTraceCounts& counts) {
  SSGI_CHECK(tile.x0 % 4 == 0 && tile.y0 % 4 == 0);
  // Its list packs a pixel as (y - y0) << 8 | (x - x0).
  SSGI_CHECK_LE(tile.x1 - tile.x0, kSsrTraceTileSize);
  SSGI_CHECK_LE(tile.y1 - tile.y0, kSsrTraceTileSize);
  HWY_DYNAMIC_DISPATCH(TraceTile)(FlattenInputs(in), params, tile, out, counts);
}

}  // namespace ssgi
#endif
