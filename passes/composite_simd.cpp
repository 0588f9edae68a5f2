// The Highway twin of CompositeRowScalar (composite.cpp): the same operations in the same order
// through the core twins (core/*-inl.h), so every target gives the scalar bits
// (tests/passes/composite_test.cpp checks each compiled target). Lanes are pixels of the row; a
// vector without a confident hit on geometry reads neither its material nor its reflection (unless
// the sky or the bounce lights it).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/composite_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep

#include "hwy/highway.h"

#include "core/brdf-inl.h"
#include "core/camera-inl.h"
#include "core/color.h"
#include "core/environment_lighting-inl.h"
#include "core/gbuffer-inl.h"
#include "core/row-inl.h"
#include "hwy/cache_control.h"
#include "passes/composite.h"

#ifndef SSGI_PASSES_COMPOSITE_SIMD_ONCE
#define SSGI_PASSES_COMPOSITE_SIMD_ONCE
namespace ssgi {

// What the kernel reads of CompositeContext, and the tables it gathers from: plain data for the
// dispatch boundary.
struct CompositeConstants {
  const ViewProjection* view;
  NormalEncoding normalEncoding;
  float roughnessCutoff;
  const float* srgbDecodeTable;
  const float* dfgTable;
  bool inPlace;  // CompositeContext::inPlace
  // The sky's specular light (CompositeContext::environment).
  const EnvironmentLighting* environment;
  glm::mat3 viewToWorld;
};

}  // namespace ssgi
#endif

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// CompositeRowScalar's body for pixels x, x + 1, ... of row y, short of `count` (the run's end).
void CompositePixels(const CompositeConstants& c, const CompositeRow& row, size_t x, size_t count, float py,
                     hn::Vec<DF> px) {
  const DF d;
  const DU du;
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0f);
  const auto confidence = row.confidence ? LoadRow(d, row.confidence, x, count, 0.0f) : zero;
  const auto confident = hn::Gt(confidence, zero);
  const bool sky = c.environment != nullptr;
  const bool bounce = row.bounce[0] != nullptr;
  if (c.inPlace && !sky && !bounce && hn::AllFalse(d, confident)) return;
  // As in the scalar kernel, word 2 is read only where a lane is confident or the sky or the bounce
  // lights it.
  auto lit = sky || bounce ? hn::FirstN(d, count - x) : confident;
  if (!hn::AllFalse(d, lit)) {
    const auto depth = UnpackDepthV(d, LoadRow(du, row.word2, x, count, PackDepth(kBackgroundDepth)));
    lit = hn::And(lit, hn::Ne(depth, hn::Set(d, kBackgroundDepth)));
  }
  Vec3V<DF> base = LoadRow3(d, row.direct, x, count);
  Vec3V<DF> indirect{zero, zero, zero};
  if (!hn::AllFalse(d, lit)) {
    const auto word0 = LoadRow(du, row.word0, x, count, 0u);
    const auto word1 = LoadRow(du, row.word1, x, count, 0u);
    const SurfaceMaterialV<DF> material{UnpackAlbedoV(d, word0, c.srgbDecodeTable), UnpackMetallicV(d, word0),
                                        UnpackRoughnessV(d, word1)};
    const auto reflecting = hn::And(confident, lit);
    if (sky || !hn::AllFalse(d, reflecting)) {
      const Vec3V<DF> normal = UnpackNormalV(d, word1, c.normalEncoding);
      const Vec3V<DF> toViewer = Normalize3(d, Neg3(PixelRayV(d, *c.view, px, py).direction));
      const auto nDotV = ClampStd(Dot3(normal, toViewer), zero, one);
      const auto fade =
          ClampStd(hn::Div(hn::Sub(hn::Set(d, c.roughnessCutoff), material.roughness), hn::Set(d, kRoughnessFadeWidth)),
                   zero, one);
      const Vec3V<DF> specular = SpecularWeightV(d, SpecularF0V(d, material), nDotV, material.roughness, c.dfgTable);
      if (!hn::AllFalse(d, reflecting)) {
        const Vec3V<DF> weight = Scale3(specular, hn::Mul(confidence, fade));
        indirect = IfThenElse3(reflecting, Mul3(LoadRow3(d, row.reflected, x, count), weight), indirect);
      }
      if (sky) {
        const auto unseen = hn::Sub(one, hn::Mul(confidence, fade));
        const auto share = hn::Mul(unseen, LoadRow(d, row.skyVisibility, x, count, 0.0f));
        Vec3V<DF> environment = Set3(d, c.environment->constantRadiance);
        if (!c.environment->constant) {
          // r = n (2 n.v) - v, into the world.
          const Vec3V<DF> reflection =
              Sub3(Scale3(normal, hn::Mul(hn::Set(d, 2.0f), Dot3(normal, toViewer))), toViewer);
          environment =
              PrefilteredEnvironmentV(d, *c.environment, MulMat3(d, c.viewToWorld, reflection), material.roughness);
        }
        Vec3V<DF> withSky = Add3(indirect, Mul3(environment, Scale3(specular, share)));
        if (row.skyReflected[0]) {
          withSky = Add3(withSky, Mul3(LoadRow3(d, row.skyReflected, x, count), Scale3(specular, unseen)));
        }
        indirect = IfThenElse3(lit, withSky, indirect);
      }
    }
    if (bounce) {
      const Vec3V<DF> diffuseAlbedo = Scale3(material.albedo, hn::Sub(one, material.metallic));
      indirect = IfThenElse3(lit, Add3(indirect, Mul3(LoadRow3(d, row.bounce, x, count), diffuseAlbedo)), indirect);
      if (row.skyDiffuse[0]) {
        const auto darkening = hn::Sub(LoadRow(d, row.ambientVisibility, x, count, 1.0f), one);
        base = IfThenElse3(lit, Add3(base, Scale3(LoadRow3(d, row.skyDiffuse, x, count), darkening)), base);
      }
    }
  }
  if (row.indirect[0]) StreamRow3(indirect, d, row.indirect, x, count);
  StreamRow3(Add3(base, indirect), d, row.result, x, count);
}

// 128 pixels, 8 vectors of 16 lanes: a line from memory takes about as long as 8 vectors of the kernel.
constexpr size_t kCompositeLookAhead = 128;

void CompositeRowKernel(const CompositeConstants& c, const CompositeRow& row, size_t y, int xBegin, int xEnd) {
  const DF d;
  const auto lane = hn::Iota(d, 0.0f);
  for (size_t x = size_t(xBegin); x < size_t(xEnd); x += hn::Lanes(d)) {
    // The G-buffer and reflection rows are read only under a confident hit, too sparsely for the
    // hardware's stream prefetch: a vector with a hit kCompositeLookAhead pixels on asks for them
    // now, so that their lines are in when it is reached.
    const size_t ahead = x + kCompositeLookAhead;
    if (row.confidence && ahead + hn::Lanes(d) <= size_t(xEnd) &&
        !hn::AllFalse(d, hn::Gt(hn::LoadU(d, row.confidence + ahead), hn::Zero(d)))) {
      hwy::Prefetch(row.word0 + ahead);
      hwy::Prefetch(row.word1 + ahead);
      hwy::Prefetch(row.word2 + ahead);
      for (const float* reflected : row.reflected) hwy::Prefetch(reflected + ahead);
    }
    const auto px = hn::Add(hn::Add(lane, hn::Set(d, float(x))), hn::Set(d, 0.5f));
    CompositePixels(c, row, x, size_t(xEnd), float(y) + 0.5f, px);
  }
  hwy::FlushStream();  // StreamRow3's stores, before the band's end lets another thread read them
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(CompositeRowKernel);

void CompositeRowSimd(const CompositeContext& context, const CompositeRow& row, size_t y, int xBegin, int xEnd) {
  const CompositeConstants constants{
      &context.view,        context.normalEncoding, context.roughnessCutoff, SrgbDecodeTableForKernels(),
      DfgTableForKernels(), context.inPlace,        context.environment,     context.viewToWorld};
  HWY_DYNAMIC_DISPATCH(CompositeRowKernel)(constants, row, y, xBegin, xEnd);
}

}  // namespace ssgi
#endif
