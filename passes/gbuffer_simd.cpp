// The Highway twin of GBufferResolveRowScalar (gbuffer.cpp): lanes are a block of pixels of a few
// rows (core/row-inl.h), which meets fewer triangles than a run of a row. Each triangle of a vector
// is broadcast into its lanes, then per pixel the view ray's barycentrics on the triangle's plane
// (SurfaceResolver::At, core/surface.cpp), the interpolated normal, its encoding and the depth are
// computed with the scalar operations in their order through the core twins (core/*-inl.h), so
// every target gives the scalar bits (tests/passes/gbuffer_test.cpp checks each compiled target).
// For pixels of textured materials the vectors also give the UV and its footprint (the neighbouring
// pixels' rays on the plane, as SurfaceResolver::At), sample the textures (core/texture-inl.h) and
// pack the words (core/color-inl.h).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/gbuffer_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/cache_control.h"
#include "hwy/highway.h"

#include <bit>

#include "core/check.h"
#include "core/color-inl.h"
#include "core/gbuffer-inl.h"
#include "core/math-inl.h"
#include "core/row-inl.h"
#include "core/texture-inl.h"
#include "passes/gbuffer.h"

#ifndef SSGI_PASSES_GBUFFER_SIMD_ONCE
#define SSGI_PASSES_GBUFFER_SIMD_ONCE
namespace ssgi {
namespace {

// What the resolve reads besides the rows, flattened into plain pointers for the dispatch boundary.
struct GBufferResolveInputs {
  const GBufferResolveContext* context;  // for the pixels of textured materials
  const ViewProjection* view;
  const uint32_t* indices;         // three per triangle
  const float* viewPositions;      // x, y, z per vertex, in the view
  const float* normals;            // x, y, z per vertex, world space
  const float* uvs;                // u, v per vertex
  const float* rayDirectionX;      // GBufferResolveContext's
  const float* rayDirectionY;
  const uint32_t* materials;       // per triangle
  const uint32_t* constantWord0;   // per material (GBufferResolveContext)
  const uint32_t* constantRoughnessBits;
  const float* constantRoughness;
  const uint32_t* textured;
  bool prefetchVertices;  // the mesh's vertex data is larger than the caches keep near (kGBufferCachedVertexBytes)
  glm::mat3 normalToView;
  NormalEncoding encoding;
  float specularAaKappa;
};

// The rows of a call of the twin: the first kGBufferResolveRowsPerCall are those it resolves (the
// first `count` of them), the others the rows below, which it asks the cache for ahead of their turn
// (the image's last row where there are no more).
struct GBufferResolveRows {
  int y;      // the first
  int count;  // 1 to kGBufferResolveRowsPerCall
  int width;
  const uint32_t* triangles[2 * kGBufferResolveRowsPerCall];
  const float* depthKeys[2 * kGBufferResolveRowsPerCall];
  uint32_t* word[4][kGBufferResolveRowsPerCall];
};

}  // namespace
}  // namespace ssgi
#endif

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace {

// What RayPlaneBarycentrics (core/surface.cpp) and the normal's face test compute of the lanes'
// planes p0 + b1 e1 + b2 e2 alone: the edges, the face normal e1 x e2, and for rays from the camera
// centre (RunGBuffer's views are perspective) the offset s = 0 - p0 and q = s x e1. So a triangle's
// terms serve every vector it alone covers.
struct PlaneTerms {
  Vec3V<DF> e1, e2, face, s, q;
};

// Of the triangles with vertices `position` (view space).
HWY_INLINE PlaneTerms PlaneTermsOf(const Vec3V<DF> position[3]) {
  const DF df;
  const Vec3V<DF> origin = {hn::Zero(df), hn::Zero(df), hn::Zero(df)};  // PixelRay's perspective origin
  const Vec3V<DF>& p0 = position[0];
  PlaneTerms terms;
  terms.e1 = Sub3(position[1], p0);
  terms.e2 = Sub3(position[2], p0);
  terms.face = Cross3(terms.e1, terms.e2);
  terms.s = Sub3(origin, p0);
  terms.q = Cross3(terms.s, terms.e1);
  return terms;
}

// What the resolve reads of each lane's triangle: its material's constant words (word 0, the
// roughness byte of word 1, whether it is textured) and roughness, per vertex the world-space normal, and the
// terms of its plane (of its vertices' view-space positions, which are not kept: fewer vectors for
// the registers).
struct TriangleData {
  hn::Vec<DU> word0, roughnessBits, textured;
  VF roughness;
  Vec3V<DF> normal[3];
  PlaneTerms terms;
};

// The data of one triangle in every lane, but for the plane's terms: its vertices' view positions
// instead.
HWY_INLINE void BroadcastTriangle(const GBufferResolveInputs& in, uint32_t triangle, TriangleData& data,
                                  Vec3V<DF> position[3]) {
  const DF df;
  const DU du;
  const uint32_t material = in.materials[triangle];
  data.word0 = hn::Set(du, in.constantWord0[material]);
  data.roughnessBits = hn::Set(du, in.constantRoughnessBits[material]);
  data.textured = hn::Set(du, in.textured[material]);
  data.roughness = hn::Set(df, in.constantRoughness[material]);
  for (int v = 0; v < 3; ++v) {
    const size_t vertex = in.indices[3 * size_t(triangle) + size_t(v)];
    const float* p = in.viewPositions + 3 * vertex;
    const float* normal = in.normals + 3 * vertex;
    position[v] = Set3(df, glm::vec3(p[0], p[1], p[2]));
    data.normal[v] = Set3(df, glm::vec3(normal[0], normal[1], normal[2]));
  }
}

// The data of one triangle in every lane.
HWY_INLINE TriangleData TriangleInEveryLane(const GBufferResolveInputs& in, uint32_t triangle) {
  TriangleData data;
  Vec3V<DF> position[3];
  BroadcastTriangle(in, triangle, data, position);
  data.terms = PlaneTermsOf(position);
  return data;
}

// Calls visit(value, holding) for each distinct value of `values` among the lanes `among`, in the
// order of the first lane holding it; `stored` holds the same values lane by lane, and `holding` is
// the lanes of `among` that hold `value`.
template <class D, class Visit>
HWY_INLINE void ForEachDistinctValue(D d, hn::Vec<D> values, hn::Mask<D> among, const hn::TFromD<D>* stored,
                                     const Visit& visit) {
  for (auto remaining = among; !hn::AllFalse(d, remaining);) {
    const hn::TFromD<D> value = stored[hn::FindFirstTrue(d, remaining)];
    const auto holding = hn::And(remaining, hn::Eq(values, hn::Set(d, value)));
    remaining = hn::AndNot(holding, remaining);
    visit(value, holding);
  }
}

// The lanes of a block (core/row-inl.h) a lane's value is compared with to find where each distinct
// value first appears: the lane before it (in row order) and the lane above it.
using LaneIndices = decltype(hn::SetTableIndices(DU(), static_cast<const int32_t*>(nullptr)));
struct EarlierLanes {
  LaneIndices before, above;       // the lane itself where there is none
  hn::Mask<DU> noneBefore, noneAbove;
};

HWY_INLINE EarlierLanes EarlierLanesOfBlock() {
  const DU du;
  constexpr size_t kLanes = hn::MaxLanes(DU()), kWidth = BlockWidth(DU());
  HWY_ALIGN int32_t before[kLanes], above[kLanes];
  HWY_ALIGN uint32_t noneBefore[kLanes], noneAbove[kLanes];
  for (size_t lane = 0; lane < kLanes; ++lane) {
    before[lane] = int32_t(lane == 0 ? lane : lane - 1);
    above[lane] = int32_t(lane < kWidth ? lane : lane - kWidth);
    noneBefore[lane] = lane == 0 ? ~0u : 0u;
    noneAbove[lane] = lane < kWidth ? ~0u : 0u;
  }
  return {hn::SetTableIndices(du, before), hn::SetTableIndices(du, above),
          hn::MaskFromVec(hn::Load(du, noneBefore)), hn::MaskFromVec(hn::Load(du, noneAbove))};
}

// As bits, the lanes of `among` whose value holds neither in the lane before nor in the lane above:
// the first lane of each distinct value is one of them. (A value may have more than one, which the
// callers tolerate: finding only the first ones, one after another, is a chain of dependent steps.)
HWY_INLINE uint64_t ValueStarts(hn::Vec<DU> values, hn::Mask<DU> among, const EarlierLanes& earlier) {
  const DU du;
  const auto newBefore = hn::Or(earlier.noneBefore, hn::Ne(values, hn::TableLookupLanes(values, earlier.before)));
  const auto newAbove = hn::Or(earlier.noneAbove, hn::Ne(values, hn::TableLookupLanes(values, earlier.above)));
  return LaneBits(du, hn::And(among, hn::And(newBefore, newAbove)));
}

// The triangle data of the lanes of `drawn` (`triangle` per lane, as in `triangles`); the other
// lanes hold some lane's data, never stored. A vector meets few triangles, and each is broadcast
// into the lanes it covers (a triangle met twice by ValueStarts, twice: the same lanes get the same
// values): even at about a triangle per lane (the 1M-triangle knot) that is no slower than
// gathering 19 values per lane (docs/perf-log.md).
TriangleData LoadTriangles(const GBufferResolveInputs& in, const uint32_t* triangles, hn::Vec<DU> triangle,
                           hn::Mask<DU> drawn, const EarlierLanes& earlier) {
  const DF df;
  const DU du;
  TriangleData data;
  Vec3V<DF> position[3];
  uint64_t starts = ValueStarts(triangle, drawn, earlier);
  BroadcastTriangle(in, triangles[std::countr_zero(starts)], data, position);
  for (starts &= starts - 1; starts != 0; starts &= starts - 1) {
    const uint32_t next = triangles[std::countr_zero(starts)];
    const auto covers = hn::Eq(triangle, hn::Set(du, next));
    TriangleData more;
    Vec3V<DF> morePosition[3];
    BroadcastTriangle(in, next, more, morePosition);
    const auto lanes = hn::RebindMask(df, covers);
    data.word0 = hn::IfThenElse(covers, more.word0, data.word0);
    data.roughnessBits = hn::IfThenElse(covers, more.roughnessBits, data.roughnessBits);
    data.textured = hn::IfThenElse(covers, more.textured, data.textured);
    data.roughness = hn::IfThenElse(lanes, more.roughness, data.roughness);
    for (int v = 0; v < 3; ++v) {
      position[v] = IfThenElse3(lanes, morePosition[v], position[v]);
      data.normal[v] = IfThenElse3(lanes, more.normal[v], data.normal[v]);
    }
  }
  data.terms = PlaneTermsOf(position);
  return data;
}

// Per lane of `lanes`, its triangle's UVs: the first vertex's and the differences to the other two
// (SurfaceResolver::At's uv0, du1, du2); the other lanes hold some lane's.
struct TriangleUvs {
  VF u0, v0, du1, dv1, du2, dv2;
};

TriangleUvs LoadUvs(const GBufferResolveInputs& in, const uint32_t* triangles, hn::Vec<DU> triangle,
                    hn::Mask<DU> lanes) {
  const DF df;
  TriangleUvs uvs{};
  bool first = true;
  ForEachDistinctValue(DU(), triangle, lanes, triangles, [&](uint32_t next, hn::Mask<DU> covers) {
    const uint32_t* index = in.indices + 3 * size_t(next);
    const glm::vec2 uv0(in.uvs[2 * size_t(index[0])], in.uvs[2 * size_t(index[0]) + 1]);
    const glm::vec2 uv1(in.uvs[2 * size_t(index[1])], in.uvs[2 * size_t(index[1]) + 1]);
    const glm::vec2 uv2(in.uvs[2 * size_t(index[2])], in.uvs[2 * size_t(index[2]) + 1]);
    const glm::vec2 d1 = uv1 - uv0, d2 = uv2 - uv0;
    const auto take = hn::RebindMask(df, covers);
    const auto set = [&](VF& lane, float value) {
      lane = first ? hn::Set(df, value) : hn::IfThenElse(take, hn::Set(df, value), lane);
    };
    set(uvs.u0, uv0.x), set(uvs.v0, uv0.y), set(uvs.du1, d1.x), set(uvs.dv1, d1.y), set(uvs.du2, d2.x);
    set(uvs.dv2, d2.y);
    first = false;
  });
  return uvs;
}

// RayPlaneBarycentrics of the rays from the camera centre with direction `direction`, in its
// operations and order: b1 and b2 in every lane; `plane` the lanes where the ray is not parallel to
// the plane (the scalar function writes b there), `hit` those of them where b is also finite (it
// returns true).
struct RayPlaneLanes {
  hn::Mask<DF> plane, hit;
  VF b1, b2;
};

HWY_INLINE RayPlaneLanes RayPlaneBarycentricsV(const Vec3V<DF>& direction, const PlaneTerms& terms) {
  const DF df;
  const Vec3V<DF> p = Cross3(direction, terms.e2);
  const VF det = Dot3(terms.e1, p);
  const VF invDet = hn::Div(hn::Set(df, 1.0f), det);
  RayPlaneLanes lanes;
  lanes.b1 = hn::Mul(Dot3(terms.s, p), invDet);
  lanes.b2 = hn::Mul(Dot3(direction, terms.q), invDet);
  lanes.plane = hn::Gt(hn::Abs(det), hn::Set(df, 1e-30f));
  lanes.hit = hn::And(lanes.plane, hn::And(hn::IsFinite(lanes.b1), hn::IsFinite(lanes.b2)));
  return lanes;
}

// NormalVariance (passes/gbuffer.cpp) in its operations and order.
HWY_INLINE VF NormalVarianceV(const Vec3V<DF>& m, const Vec3V<DF>& stepX, const Vec3V<DF>& stepY) {
  const DF df;
  const VF lengthSquared = Dot3(m, m);
  const Vec3V<DF> acrossX = Sub3(stepX, Scale3(m, hn::Div(Dot3(m, stepX), lengthSquared)));
  const Vec3V<DF> acrossY = Sub3(stepY, Scale3(m, hn::Div(Dot3(m, stepY), lengthSquared)));
  return hn::Mul(hn::Div(hn::Add(Dot3(acrossX, acrossX), Dot3(acrossY, acrossY)), lengthSquared),
                 hn::Set(df, kSpecularAaKernelVariance));
}

// WidenedRoughness (passes/gbuffer.cpp) in its operations and order.
HWY_INLINE VF WidenedRoughnessV(VF roughness, VF variance, VF kappa) {
  const DF df;
  const VF added = MinStd(variance, kappa);
  const VF alpha = hn::Mul(roughness, roughness);
  const VF widened = hn::Sqrt(hn::Sqrt(MinStd(hn::Add(hn::Mul(alpha, alpha), added), hn::Set(df, 1.0f))));
  return hn::IfThenElse(hn::Gt(added, hn::Zero(df)), widened, roughness);
}

// The last texture a row's resolve sampled, kept for its next textured vector.
struct TextureCache {
  int32_t texture = kNoTexture;
  TextureView view{};
};

// The words 0 and 1 of a vector's lanes `texturedLanes` (`triangles` and `triangle` the vector's
// ids, directionX and directionY their rays' (z is -1), rightX and downY the x of the rays one pixel
// right and the y of those one pixel down, the rest as GBufferResolveBlocks computes them): the
// constant words with the textures' samples packed in, a sampled roughness widened by `variance`. Out of line: inlined,
// its sampler's registers and stack slots slow the untextured vectors of the resolve. Its aggregates are taken by value
// and its words returned: an object whose address a call takes stays in memory throughout the loop, its vectors stored
// and loaded again.
struct Words01 {
  hn::Vec<DU> word0, word1;
};

HWY_NOINLINE Words01 TexturedWords(const GBufferResolveInputs& in, const uint32_t* triangles, hn::Vec<DU> triangle,
                                   hn::Mask<DU> texturedLanes, VF directionX, VF directionY, VF rightX, VF downY,
                                   PlaneTerms terms, RayPlaneLanes center, VF centerB1, VF centerB2, VF b1, VF b2,
                                   hn::Vec<DU> normalCode, VF variance, TextureCache& cache, hn::Vec<DU> words0,
                                   hn::Vec<DU> words1) {
  const DF df;
  const DI di;
  const DU du;
  const size_t lanes = hn::Lanes(df);
  const VF zero = hn::Zero(df);
  HWY_ALIGN uint32_t textured[HWY_MAX_BYTES / sizeof(uint32_t)];
  const CodeBuckets& encode = SrgbEncodeBuckets();
  // SurfaceResolver::At's UV at the clamped barycentrics, and its footprint from the unclamped
  // ones of this pixel's ray and of the rays one pixel right and one down (0 where any misses).
  const TriangleUvs uv = LoadUvs(in, triangles, triangle, texturedLanes);
  const VF u = hn::Add(hn::Add(uv.u0, hn::Mul(uv.du1, b1)), hn::Mul(uv.du2, b2));
  const VF v = hn::Add(hn::Add(uv.v0, hn::Mul(uv.dv1, b1)), hn::Mul(uv.dv2, b2));
  const VF directionZ = hn::Set(df, -1.0f);
  const RayPlaneLanes right = RayPlaneBarycentricsV({rightX, directionY, directionZ}, terms);
  const RayPlaneLanes down = RayPlaneBarycentricsV({directionX, downY, directionZ}, terms);
  const auto footprintHit = hn::And(center.hit, hn::And(right.hit, down.hit));
  const auto uvLength = [&](VF db1, VF db2) {  // glm::length(du1 * db1 + du2 * db2)
    const VF dU = hn::Add(hn::Mul(uv.du1, db1), hn::Mul(uv.du2, db2));
    const VF dV = hn::Add(hn::Mul(uv.dv1, db1), hn::Mul(uv.dv2, db2));
    return hn::Sqrt(hn::Add(hn::Mul(dU, dU), hn::Mul(dV, dV)));
  };
  const VF footprint = MaxStd(uvLength(hn::Sub(right.b1, centerB1), hn::Sub(right.b2, centerB2)),
                              uvLength(hn::Sub(down.b1, centerB1), hn::Sub(down.b2, centerB2)));
  const VF uvFootprint = hn::IfThenElseZero(hn::And(footprintHit, hn::IsFinite(footprint)), footprint);
  // The textures sampled in vectors, a texture at a time over the lanes that read it (a vector
  // mostly meets one material).
  hn::Store(hn::VecFromMask(du, texturedLanes), du, textured);
  const Scene& scene = in.context->scene;
  HWY_ALIGN int32_t slotTexture[3][HWY_MAX_BYTES / sizeof(float)];
  HWY_ALIGN float constant[5][HWY_MAX_BYTES / sizeof(float)];  // the material's colour, metallic, roughness
  for (size_t lane = 0; lane < lanes; ++lane) {
    const bool used = textured[lane] != 0;
    const Material& material = scene.materials[used ? in.materials[triangles[lane]] : 0];
    slotTexture[0][lane] = used ? material.baseColorTexture : kNoTexture;
    slotTexture[1][lane] = used ? material.metallicTexture : kNoTexture;
    slotTexture[2][lane] = used ? material.roughnessTexture : kNoTexture;
    const float values[5] = {material.baseColor.x, material.baseColor.y, material.baseColor.z, material.metallic,
                             material.roughness};
    for (int k = 0; k < 5; ++k) constant[k][lane] = values[k];
  }
  hn::Mask<DI> has[3];  // the lanes whose material has the slot's texture
  Vec4V sample[3] = {{zero, zero, zero, zero}, {zero, zero, zero, zero}, {zero, zero, zero, zero}};
  for (int slot = 0; slot < 3; ++slot) {
    const VI textures = hn::Load(di, slotTexture[slot]);
    has[slot] = hn::Ne(textures, hn::Set(di, kNoTexture));
    ForEachDistinctValue(di, textures, has[slot], slotTexture[slot], [&](int32_t texture, hn::Mask<DI> reads) {
      if (texture != cache.texture) {
        cache.view = ViewOf(scene.textures[size_t(texture)]);
        cache.texture = texture;
      }
      const Vec4V texel = SampleTextureV(cache.view, u, v, uvFootprint);
      const auto take = hn::RebindMask(df, reads);
      sample[slot] = {hn::IfThenElse(take, texel.r, sample[slot].r), hn::IfThenElse(take, texel.g, sample[slot].g),
                      hn::IfThenElse(take, texel.b, sample[slot].b), hn::IfThenElse(take, texel.a, sample[slot].a)};
    });
  }
  // The scalar resolve's packing: the material's constants times the samples of the textures it has.
  const auto times = [&](int slot, int k, VF sampled) {
    const VF value = hn::Load(df, constant[k]);
    return hn::IfThenElse(hn::RebindMask(df, has[slot]), hn::Mul(value, sampled), value);
  };
  const auto srgb = [&](VF value) { return LinearToSrgbCodeV(value, encode); };
  const VI albedoMetallic =
      hn::Or(hn::Or(srgb(times(0, 0, sample[0].r)), hn::ShiftLeft<8>(srgb(times(0, 1, sample[0].g)))),
             hn::Or(hn::ShiftLeft<16>(srgb(times(0, 2, sample[0].b))),
                    hn::ShiftLeft<24>(UnormCode8V(times(1, 3, sample[1].r)))));
  const VF sampledRoughness = hn::Mul(hn::Load(df, constant[4]), sample[2].r);
  const VI roughness =
      hn::ShiftLeft<24>(UnormCode8V(WidenedRoughnessV(sampledRoughness, variance, hn::Set(df, in.specularAaKappa))));
  return {hn::IfThenElse(hn::RebindMask(du, hn::Or(has[0], has[1])), hn::BitCast(du, albedoMetallic), words0),
          hn::IfThenElse(hn::RebindMask(du, has[2]), hn::Or(normalCode, hn::BitCast(du, roughness)), words1)};
}

// Asks the cache for what the resolve will read of the triangles `triangle` of a vector ahead (each
// once, or about: ValueStarts): their corner indices and materials (`corners`), or, once those have
// come, their vertices' view positions and normals.
// Inlined: a call would spill the resolve loop's vectors.
HWY_INLINE void PrefetchTriangles(const GBufferResolveInputs& in, hn::Vec<DU> triangle, const EarlierLanes& earlier,
                                  bool corners) {
  const DU du;
  HWY_ALIGN uint32_t triangles[hn::MaxLanes(DU())];
  hn::Store(triangle, du, triangles);
  const auto drawn = hn::Ne(triangle, hn::Set(du, kNoTriangle));
  for (uint64_t starts = ValueStarts(triangle, drawn, earlier); starts != 0; starts &= starts - 1) {
    const uint32_t id = triangles[std::countr_zero(starts)];
    const uint32_t* corner = in.indices + 3 * size_t(id);
    if (corners) {
      hwy::Prefetch(corner);
      hwy::Prefetch(in.materials + id);
      continue;
    }
    for (int v = 0; v < 3; ++v) {
      hwy::Prefetch(in.viewPositions + 3 * size_t(corner[v]));
      hwy::Prefetch(in.normals + 3 * size_t(corner[v]));
    }
  }
}

// Resolves the blocks (core/row-inl.h) of rows.count rows from rows.y: the lanes of a vector are a
// block's pixels.
size_t GBufferResolveBlocks(const GBufferResolveInputs& in, const GBufferResolveRows& rows) {
  const DF df;
  const DU du;
  constexpr size_t kLanes = hn::MaxLanes(DF()), kWidth = BlockWidth(DF()), kHeight = BlockHeight(DF());
  static_assert(kGBufferResolveRowsPerCall % kHeight == 0);
  const size_t width = size_t(rows.width);
  static_assert(kWidth * sizeof(float) == 16 || kLanes == 1, "LoadDup128 gives a block's columns in each row");
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
  const auto background = hn::Set(du, PackDepth(kBackgroundDepth)), shadowLit = hn::Set(du, kShadowLit);
  const EarlierLanes earlier = EarlierLanesOfBlock();
  size_t covered = 0;
  TextureCache textureCache;
  // A triangle mostly covers several neighbouring vectors: the last one broadcast alone is kept for
  // the next vector that meets only it.
  uint32_t broadcastTriangle = kNoTriangle;
  TriangleData broadcast;
  for (size_t r = 0; r < size_t(rows.count); r += kHeight) {
    const size_t rowCount = HWY_MIN(kHeight, size_t(rows.count) - r);
    const uint32_t* const* triangleRows = rows.triangles + r;
    const float* const* depthKeyRows = rows.depthKeys + r;
    uint32_t* const* wordRows[4] = {rows.word[GBufferWord::kAlbedoMetallic] + r,
                                    rows.word[GBufferWord::kNormalRoughness] + r, rows.word[GBufferWord::kDepth] + r,
                                    rows.word[GBufferWord::kShadowTerm] + r};
    // The view rays' y of the lanes' rows and of the rows below them (PixelRay's, as the columns' x).
    HWY_ALIGN float rayY[kLanes], downRayY[kLanes];
    for (size_t lane = 0; lane < kLanes; ++lane) {
      rayY[lane] = in.rayDirectionY[size_t(rows.y) + r + lane / kWidth];
      downRayY[lane] = in.rayDirectionY[size_t(rows.y) + r + lane / kWidth + 1];
    }
    const VF directionY = hn::Load(df, rayY), downY = hn::Load(df, downRayY);
    for (size_t x = 0; x < width; x += kWidth) {
      // A row of the visibility buffer is a page of its own at 1024 pixels, where the hardware's
      // prefetch stops: the rows of the next blocks down are asked for along these.
      if (x % (64 / sizeof(uint32_t)) == 0) {  // once per line
        for (size_t next = r + kHeight; next < r + 2 * kHeight; ++next) {
          hwy::Prefetch(rows.triangles[next] + x);
          hwy::Prefetch(rows.depthKeys[next] + x);
        }
      }
      // A large mesh's vertex data is asked for two vectors ahead, its corners four: beyond the
      // caches the vertex fetches are the resolve's wait; where the data stays in the caches
      // (in.prefetchVertices false) the extra requests only cost.
      if (in.prefetchVertices && x > 0) {
        for (int ahead : {2, 4}) {
          const size_t at = x + size_t(ahead) * kWidth;
          if (at >= width) break;
          PrefetchTriangles(in, LoadBlock(du, triangleRows, rowCount, at, width, kNoTriangle), earlier, ahead == 4);
        }
      }
      const auto triangle = LoadBlock(du, triangleRows, rowCount, x, width, kNoTriangle);
      const auto drawn = hn::Ne(triangle, hn::Set(du, kNoTriangle));
      const auto storeWords = [&](hn::Vec<DU> w0, hn::Vec<DU> w1, hn::Vec<DU> w2) {
        StoreBlock(w0, du, wordRows[0], rowCount, x, width);
        StoreBlock(w1, du, wordRows[1], rowCount, x, width);
        StoreBlock(w2, du, wordRows[2], rowCount, x, width);
        StoreBlock(shadowLit, du, wordRows[3], rowCount, x, width);
      };
      if (hn::AllFalse(du, drawn)) {
        storeWords(hn::Zero(du), hn::Zero(du), background);
        continue;
      }
      covered += hn::CountTrue(du, drawn);
      HWY_ALIGN uint32_t triangles[kLanes];
      hn::Store(triangle, du, triangles);
      const uint32_t firstTriangle = triangles[hn::FindFirstTrue(du, drawn)];
      const bool oneTriangle = hn::AllFalse(du, hn::AndNot(hn::Eq(triangle, hn::Set(du, firstTriangle)), drawn));
      // PixelRay's direction (the view is perspective): x per column, in each row of the block.
      const Vec3V<DF> direction = {hn::LoadDup128(df, in.rayDirectionX + x), directionY, hn::Set(df, -1.0f)};
      if (oneTriangle && firstTriangle != broadcastTriangle) {
        broadcast = TriangleInEveryLane(in, firstTriangle);
        broadcastTriangle = firstTriangle;
      }
      TriangleData mixed;
      if (!oneTriangle) mixed = LoadTriangles(in, triangles, triangle, drawn, earlier);
      const TriangleData& data = oneTriangle ? broadcast : mixed;
      const PlaneTerms& terms = data.terms;

      // SurfaceResolver::At: the barycentrics of the pixel-centre ray on the triangle's plane
      // (Moller-Trumbore without the bounds test), clamped into the triangle.
      const RayPlaneLanes center = RayPlaneBarycentricsV(direction, terms);
      const VF third = hn::Set(df, 1.0f / 3.0f);  // where the ray misses the plane
      const VF centerB1 = hn::IfThenElse(center.plane, center.b1, third);
      const VF centerB2 = hn::IfThenElse(center.plane, center.b2, third);
      VF b1 = MinStd(MaxStd(centerB1, zero), one);  // glm::clamp(b, 0, 1)
      VF b2 = MinStd(MaxStd(centerB2, zero), one);
      const VF sum = hn::Add(b1, b2);
      const auto beyond = hn::Gt(sum, one);
      if (!hn::AllFalse(df, beyond)) {  // rare: only rounding puts a covered pixel beyond an edge
        b1 = hn::IfThenElse(beyond, hn::Div(b1, sum), b1);
        b2 = hn::IfThenElse(beyond, hn::Div(b2, sum), b2);
      }
      const VF b0 = hn::Sub(hn::Sub(one, b1), b2);

      // The interpolated normal in the view, the face's where it vanishes, turned towards the camera.
      const Vec3V<DF> interpolated = Add3(Add3(Scale3(data.normal[0], b0), Scale3(data.normal[1], b1)),
                                          Scale3(data.normal[2], b2));
      const Vec3V<DF> normal = MulMat3(df, in.normalToView, interpolated);
      const VF length = Length3(normal);
      const Vec3V<DF>& faceNormal = terms.face;
      const auto usable = hn::And(hn::Gt(length, zero), hn::IsFinite(length));
      Vec3V<DF> unit = Div3(normal, length);
      if (!hn::AllTrue(df, usable)) unit = IfThenElse3(usable, unit, Normalize3(df, faceNormal));
      unit = IfThenElse3(hn::Gt(Dot3(faceNormal, direction), zero), Neg3(unit), unit);

      const auto depthKey = LoadBlock(df, depthKeyRows, rowCount, x, width, 1.0f);
      const auto depth = hn::Div(hn::Set(df, in.view->nearPlane), depthKey);  // ViewProjection::DepthFromKey
      // Specular anti-aliasing: the normal's variance over the pixel from the barycentrics' steps to
      // the rays one pixel right and down (SurfaceResolver::At's, 0 where a ray misses the plane).
      // A flat triangle's is 0 (or NaN where its normals are 0), which widens nothing: not computed.
      VF variance = zero;
      auto roughnessBits = data.roughnessBits;
      if (in.specularAaKappa > 0.0f) {
        const Vec3V<DF> normalEdge1 = Sub3(data.normal[1], data.normal[0]);
        const Vec3V<DF> normalEdge2 = Sub3(data.normal[2], data.normal[0]);
        const auto curved = hn::Or(hn::Or(hn::Or(hn::Ne(normalEdge1.x, zero), hn::Ne(normalEdge1.y, zero)),
                                          hn::Or(hn::Ne(normalEdge1.z, zero), hn::Ne(normalEdge2.x, zero))),
                                   hn::Or(hn::Ne(normalEdge2.y, zero), hn::Ne(normalEdge2.z, zero)));
        if (!hn::AllFalse(df, hn::And(curved, hn::RebindMask(df, drawn)))) {
          const VF kappa = hn::Set(df, in.specularAaKappa), directionZ = hn::Set(df, -1.0f);
          const RayPlaneLanes right =
              RayPlaneBarycentricsV({hn::LoadDup128(df, in.rayDirectionX + x + 1), direction.y, directionZ}, terms);
          const RayPlaneLanes down = RayPlaneBarycentricsV({direction.x, downY, directionZ}, terms);
          const auto stepsHit = hn::And(center.hit, hn::And(right.hit, down.hit));
          const VF stepX1 = hn::IfThenElseZero(stepsHit, hn::Sub(right.b1, centerB1));
          const VF stepX2 = hn::IfThenElseZero(stepsHit, hn::Sub(right.b2, centerB2));
          const VF stepY1 = hn::IfThenElseZero(stepsHit, hn::Sub(down.b1, centerB1));
          const VF stepY2 = hn::IfThenElseZero(stepsHit, hn::Sub(down.b2, centerB2));
          variance = NormalVarianceV(interpolated, Add3(Scale3(normalEdge1, stepX1), Scale3(normalEdge2, stepX2)),
                                     Add3(Scale3(normalEdge1, stepY1), Scale3(normalEdge2, stepY2)));
          const VF widened = WidenedRoughnessV(data.roughness, variance, kappa);
          roughnessBits = hn::IfThenElse(hn::RebindMask(du, hn::Gt(MinStd(variance, kappa), zero)),
                                         hn::ShiftLeft<24>(hn::BitCast(du, UnormCode8V(widened))), roughnessBits);
        }
      }
      const auto words0 = hn::IfThenElseZero(drawn, data.word0);
      const auto normalCode = EncodeNormalV(df, unit, in.encoding);
      const auto words1 = hn::IfThenElseZero(drawn, hn::Or(normalCode, roughnessBits));
      const auto words2 = hn::IfThenElse(drawn, hn::BitCast(du, depth), background);
      const auto texturedLanes = hn::And(hn::Ne(data.textured, hn::Zero(du)), drawn);
      if (hn::AllFalse(du, texturedLanes)) {
        storeWords(words0, words1, words2);
        continue;
      }
      const Words01 textured =
          TexturedWords(in, triangles, triangle, texturedLanes, direction.x, direction.y,
                        hn::LoadDup128(df, in.rayDirectionX + x + 1), downY, terms, center, centerB1, centerB2, b1, b2,
                        normalCode, variance, textureCache, words0, words1);
      const auto perPixel = hn::And(hn::Eq(data.textured, hn::Set(du, kGBufferResolvedPerPixel)), drawn);
      if (hn::AllFalse(du, perPixel)) {
        storeWords(textured.word0, textured.word1, words2);
        continue;
      }
      // Normal-mapped and vertex-coloured pixels: the scalar definition, lane by lane.
      HWY_ALIGN uint32_t laneWords[3][kLanes], lanePerPixel[kLanes];
      HWY_ALIGN float laneDepthKeys[kLanes];
      hn::Store(textured.word0, du, laneWords[0]);
      hn::Store(textured.word1, du, laneWords[1]);
      hn::Store(words2, du, laneWords[2]);
      hn::Store(hn::VecFromMask(du, perPixel), du, lanePerPixel);
      hn::Store(depthKey, df, laneDepthKeys);
      for (size_t lane = 0; lane < kLanes; ++lane)
        if (lanePerPixel[lane] != 0)
          GBufferResolvePixelScalar(*in.context, triangles[lane], laneDepthKeys[lane], int(x + lane % kWidth),
                                    int(size_t(rows.y) + r + lane / kWidth), laneWords[0][lane], laneWords[1][lane],
                                    laneWords[2][lane]);
      storeWords(hn::Load(du, laneWords[0]), hn::Load(du, laneWords[1]), hn::Load(du, laneWords[2]));
    }
  }
  return covered;
}

}  // namespace
}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(GBufferResolveBlocks);

size_t GBufferResolveRowsSimd(const GBufferResolveContext& context, const VisibilityBuffer& visibility, int y,
                              int rowCount, GBuffer& gbuffer) {
  // The twin's rays all start at the camera centre (PlaneTermsOf); the scalar kernel's would not.
  SSGI_CHECK(!context.view.orthographic);
  SSGI_CHECK(rowCount >= 1 && rowCount <= kGBufferResolveRowsPerCall);
  const Mesh& mesh = context.scene.mesh;
  const GBufferResolveInputs in{
      &context,
      &context.view,
      mesh.indices.data(),
      reinterpret_cast<const float*>(context.resolver.ViewPositions()),
      reinterpret_cast<const float*>(mesh.normals.data()),
      reinterpret_cast<const float*>(mesh.uvs.data()),
      context.rayDirectionX,
      context.rayDirectionY,
      mesh.materials.data(),
      context.constantWord0,
      context.constantRoughnessBits,
      context.constantRoughness,
      context.textured,
      mesh.positions.size() * 2 * sizeof(glm::vec3) > kGBufferCachedVertexBytes,
      context.normalToView,
      context.normalEncoding,
      context.specularAaKappa,
  };
  GBufferResolveRows rows{y, rowCount, context.view.width, {}, {}, {}};
  const size_t last = visibility.triangle.ysize() - 1;
  for (size_t r = 0; r < 2 * kGBufferResolveRowsPerCall; ++r) {
    const size_t row = HWY_MIN(size_t(y) + r, last);
    rows.triangles[r] = visibility.triangle.ConstRow(row);
    rows.depthKeys[r] = visibility.depthKey.ConstRow(row);
    if (r < size_t(rowCount)) {
      for (int w = 0; w < 4; ++w) rows.word[w][r] = gbuffer.word[w].MutableRow(row);
    }
  }
  return HWY_DYNAMIC_DISPATCH(GBufferResolveBlocks)(in, rows);
}

}  // namespace ssgi
#endif
