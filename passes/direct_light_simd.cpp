// The Highway twin of DirectLightRowScalar (direct_light.cpp): the same operations in the same order
// through the core twins (core/*-inl.h), so every target gives the scalar bits
// (tests/passes/direct_light_test.cpp checks each compiled target). Lanes are pixels of the row; a
// vector of background pixels skips the shading.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "passes/direct_light_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

#include "core/brdf-inl.h"
#include "core/camera-inl.h"
#include "core/color.h"
#include "core/gbuffer-inl.h"
#include "core/lighting-inl.h"
#include "core/row-inl.h"
#include "passes/direct_light.h"

#ifndef SSGI_PASSES_DIRECT_LIGHT_SIMD_ONCE
#define SSGI_PASSES_DIRECT_LIGHT_SIMD_ONCE
namespace ssgi {

// What the kernel reads of DirectLightContext, and the table it gathers albedo from: plain data
// for the dispatch boundary.
struct DirectLightConstants {
  const ViewProjection* view;
  const PreparedLight* lights;
  size_t lightCount;
  size_t shadowedLight;
  NormalEncoding normalEncoding;
  glm::vec3 background;
  const float* srgbDecodeTable;
};

}  // namespace ssgi
#endif

HWY_BEFORE_NAMESPACE();
namespace ssgi {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// DirectLightRowScalar's body for the pixels at image positions px on row py; `visibility` is read
// only when `shadowed`. Adds the pixels with geometry to `shaded`.
Vec3V<DF> ShadePixels(const DirectLightConstants& c, hn::Vec<DU> word0, hn::Vec<DU> word1, hn::Vec<DU> word2,
                      bool shadowed, hn::Vec<DF> visibility, hn::Vec<DF> px, float py, size_t& shaded) {
  const DF d;
  const Vec3V<DF> background = Set3(d, c.background);
  const auto depth = UnpackDepthV(d, word2);
  const auto geometry = hn::Ne(depth, hn::Set(d, kBackgroundDepth));
  if (hn::AllFalse(d, geometry)) return background;
  shaded += hn::CountTrue(d, geometry);
  const RayV<DF> ray = PixelRayV(d, *c.view, px, py);
  const Vec3V<DF> position = Add3(ray.origin, Scale3(ray.direction, depth));
  const Vec3V<DF> toViewer = Normalize3(d, Neg3(ray.direction));
  const Vec3V<DF> normal = UnpackNormalV(d, word1, c.normalEncoding);
  const SurfaceMaterialV<DF> material{UnpackAlbedoV(d, word0, c.srgbDecodeTable), UnpackMetallicV(d, word0),
                                      UnpackRoughnessV(d, word1)};
  const auto alpha = hn::Mul(material.roughness, material.roughness);
  Vec3V<DF> radiance = Set3(d, glm::vec3(0.0f));
  for (size_t i = 0; i < c.lightCount; ++i) {
    const LightAtPointV<DF> l = EvaluateV(d, c.lights[i], position);
    Vec3V<DF> contribution =
        Mul3(DiskLightBrdfCosineV(d, material, alpha, normal, toViewer, l.toLight, l.tanAngularRadius), l.irradiance);
    if (shadowed && i == c.shadowedLight) contribution = Scale3(contribution, visibility);
    radiance = Add3(radiance, contribution);
  }
  const Vec3V<DF> out = IfThenElse3(geometry, radiance, background);
  return {SanitizeRadianceV(out.x), SanitizeRadianceV(out.y), SanitizeRadianceV(out.z)};
}

size_t DirectLightRow(const DirectLightConstants& c, const uint32_t* word0, const uint32_t* word1,
                      const uint32_t* word2, const float* visibility, size_t y, int width, float* red, float* green,
                      float* blue) {
  const DF d;
  const DU du;
  const size_t count = size_t(width);
  const bool shadowed = visibility != nullptr;
  float* const radianceRows[3] = {red, green, blue};
  const auto lane = hn::Iota(d, 0.0f);
  const float py = float(y) + 0.5f;
  size_t shaded = 0;
  for (size_t x = 0; x < count; x += hn::Lanes(d)) {
    const Vec3V<DF> radiance = ShadePixels(
        c, LoadRow(du, word0, x, count, 0u), LoadRow(du, word1, x, count, 0u),
        LoadRow(du, word2, x, count, PackDepth(kBackgroundDepth)), shadowed,
        shadowed ? LoadRow(d, visibility, x, count, 0.0f) : hn::Zero(d),
        hn::Add(hn::Add(lane, hn::Set(d, float(x))), hn::Set(d, 0.5f)), py, shaded);
    StoreRow3(radiance, d, radianceRows, x, count);
  }
  return shaded;
}

}  // namespace HWY_NAMESPACE
}  // namespace ssgi
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ssgi {

HWY_EXPORT(DirectLightRow);

size_t DirectLightRowSimd(const DirectLightContext& context, const uint32_t* word0, const uint32_t* word1,
                          const uint32_t* word2, const float* visibility, size_t y, int width, float* red,
                          float* green, float* blue) {
  const DirectLightConstants constants{&context.view,          context.lights,
                                       context.lightCount,     context.shadowedLight,
                                       context.normalEncoding, context.background,
                                       SrgbDecodeTableForKernels()};
  return HWY_DYNAMIC_DISPATCH(DirectLightRow)(constants, word0, word1, word2, visibility, y, width, red, green,
                                              blue);
}

}  // namespace ssgi
#endif
